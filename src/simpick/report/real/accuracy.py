"""Which errors the paper's accuracy scores rest on, as the scores job recorded them, and what those
scores can tell apart, as the verdict rule wrote it: the report's account of the scores' data.

It reads the provenance and the verdict's table and never works out again which file or tests were
scored, so that the report cannot describe a scoring other than the one that ran."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from simpick.report.load import ReportData

if TYPE_CHECKING:
    from simpick.score.settings import Statistics
from simpick.report.real.common import (
    SET_TITLES,
    SET_UNITS,
    _f,
    _isnan,
    _test_classes,
    group_tests,
    statistics,
)


def _same_file(a: Any, b: Any) -> bool:
    return bool(a) and bool(b) and Path(str(a)).resolve() == Path(str(b)).resolve()


def accuracy(
    data: ReportData, settings: Statistics, engines: list[str], classes: list[str], lab_tests: list[str]
) -> dict[str, Any] | None:
    """The Eq. 7 totals the accuracy scores were computed from, and what they cover, as the
    scores job recorded them (results/scores/provenance.yaml): this reads that record, it
    does not work out again which file or tests were scored."""
    prov = dict((data.scores_provenance or {}).get("accuracy") or {})
    reference, kind, path = prov.get("reference"), prov.get("set") or "lab", prov.get("errors_file")
    if not prov or data.accuracy_errors is None:
        return {
            "reference": reference,
            "kind": kind,
            "errors_file": path,
            "given": False,
            "dataset": prov.get("dataset"),
            "lab_tests": lab_tests,
            "lab_scored": False,
        }
    # the errors file given to the report is the one the scores rest on, or the report says so
    given_file = data.sources.get("accuracy_errors")
    differs = None if _same_file(given_file, path) else str(given_file)

    ie = data.accuracy_errors.copy()
    ie["_e"] = [engines.index(e) if e in engines else len(engines) for e in ie["engine"]]
    ie = ie.sort_values(["quantity", "_e"], kind="mergesort")
    rows = []
    for r in ie.to_dict("records"):
        key = f"imu_{r['quantity']}"
        score = (
            data.weighted.loc[r["engine"], key]
            if r["engine"] in data.weighted.index and key in data.weighted.columns
            else None
        )
        rows.append(
            {
                **r,
                "score": score,
                "tests_list": [t for t in str(r["tests"]).split(";") if t.strip()],
                "excluded_list": [t for t in str(r["excluded"]).split(";") if t.strip()],
            }
        )
    sets = {tuple(r["tests_list"]) for r in rows}
    tests = list(prov.get("tests") or [])
    if kind != "lab":
        pos = {c: i for i, c in enumerate(classes)}
        cls_of = _test_classes(data)
        tests.sort(key=lambda t: (pos.get(cls_of.get(t, t.split("-", 1)[0]), len(pos)), t))
    why = {str(x["test"]): str(x.get("why") or "") for x in prov.get("excluded") or []}
    excluded = sorted(why)
    groups = group_tests(data, tests, classes) if kind != "lab" else []
    n_by_q = {q: sorted({int(x) for x in sel["n_tests"] if not _isnan(x)}) for q, sel in ie.groupby("quantity")}
    discrimination = _discrimination(data, statistics(settings))
    n = len(tests)
    noun = {"segments": "constant-command segment", "replay": "replayed run", "own": "replayed own log"}.get(
        kind, "test"
    )
    return {
        "count_text": f"{n} {noun}{'s' if n != 1 else ''}",
        "reference": reference,
        "kind": kind,
        "errors_file": path,
        "given": True,
        "differs": differs,
        "dataset": prov.get("dataset"),
        "rows": rows,
        "tests": tests,
        "n": len(tests),
        "same_for_all": len(sets) <= 1,
        "excluded": excluded,
        "why": why,
        "groups": groups,
        "uneven": {q: n for q, n in n_by_q.items() if len(n) > 1},
        "lab_tests": lab_tests,
        "lab_scored": kind == "lab",
        "discrimination": discrimination,
        "unit_name": SET_UNITS.get(kind, "test"),
        "kind_title": SET_TITLES.get(kind, "lab tests"),
    }


def _discrimination(data: ReportData, stats: Mapping[str, Any]) -> dict[str, Any] | None:
    """What the paper's accuracy scores can tell apart, as the verdict rule wrote it
    (results/verdict/discrimination.csv, simpick.score.verdict.score_discrimination): per quantity its rows."""
    table = data.verdict.get("discrimination")
    if table is None or table.empty:
        return None
    out = {}
    for q, g in table.groupby("quantity", sort=False):
        rows = g.to_dict("records")
        first = rows[0]
        sep = first.get("separates")
        sep = None if _isnan(sep) or sep in ("", None) else str(sep) == "True"
        shares = [_f(r["floor_share"]) for r in rows if not _isnan(r["floor_share"])]
        out[str(q)] = {
            "rows": rows,
            "spread": _f(first["spread"]),
            "half_width": _f(first["half_width"]),
            "separates": sep,
            "n_runs": int(_f(first["n_runs"])),
            "floor": _f(first["floor"]),
            "floor_models": [m for m in str(first.get("floor_models") or "").split(";") if m],
            "min_runs": stats["min_runs"],
            "engine_share_max": max(abs(1 - x) for x in shares) if shares else float("nan"),
        }
    return out
