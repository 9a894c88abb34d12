"""The evidence's tables: the lab runs, the CPU load, the IMU errors, the qualitative facts, the
reference statistics, the lab tests' figures, the paper's Table 11 and its worked example, each arranged
for the templates in a given engine order. Nothing here reads a weight: the per-metric scores shown
beside the figures are the scores job's (``data.weighted``'s per-metric columns), which no weight reaches.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

from simpick.report import figures
from simpick.report.draw import test_label
from simpick.report.formats import isnan
from simpick.report.load import ReportData
from simpick.report.params import ReportConfig
from simpick.score.scoring import DEFAULT_WEIGHTS, METRIC_LABELS, METRICS

ROS_TEXT = {
    "out_of_the_box": "out of the box",
    "official_plugin": "official plugin (installed by hand)",
    "none": "none",
}
UI_TEXT = {"full": "full", "partial": "partial", "visualization": "visualization only", "none": "none"}
FACT_ROWS = ("free", "open_source", "ros", "languages", "ui", "model_formats", "physics_engines")
QUANTITY_UNITS = {"angular": "rad/s", "linear": "m/s²"}


def test_order(data: ReportData, config: ReportConfig) -> list[tuple[str, str]]:
    """The lab tests the tables hold, in the config's order (terrain, then motion); any other after them."""
    seen: list[tuple[str, str]] = []
    frames = [data.runs]
    for df in (data.trace_stats, data.per_test_errors, data.reference_stats):
        if df is not None:
            frames.append(df)
    for df in frames:
        for t, m in zip(df["terrain"], df["motion"]):
            if (t, m) not in seen:
                seen.append((t, m))
    terrains, motions = list(config.terrains), list(config.motions)

    def key(tm):
        t, m = tm
        return (
            terrains.index(t) if t in terrains else len(terrains),
            motions.index(m) if m in motions else len(motions),
            seen.index(tm),
        )

    return sorted(seen, key=key)


def engine_order(data: ReportData, first: list[str] | None = None) -> list[str]:
    """The engines in the ranking's order (weighted.csv), then any other engine a table names. With
    ``first`` (the study's engines, the figures' order) the order reads no weight: the engines the
    tables name, those in ``first`` in its order, then the others as they come (the appendices)."""
    engines = list(data.weighted.index) if first is None else []
    frames = [data.runs, data.trace_stats, data.imu_errors, data.rtf, data.accuracy_errors]
    frames += [tables.get(k) for tables in data.real.values() for k in ("summary", "per_test")]
    for df in frames:
        if df is not None:
            for e in df["engine"]:
                if e not in engines:
                    engines.append(e)
    if first is not None:
        pos = {e: i for i, e in enumerate(first)}
        engines.sort(key=lambda e: pos.get(e, len(pos)))  # stable: the others as they came
    return engines


def qualitative(data: ReportData, engines: list[str], ref_order: list[str] | None = None) -> dict[str, Any] | None:
    """The qualitative facts per engine (columns in ``engines``' order). The sources are numbered
    walking ``ref_order`` (default ``engines``): the appendices list them, and read no weight, so the
    body numbers them in the same weight-free order whatever its columns' order."""
    q = data.qualitative
    if not q:
        return None
    shown = [e for e in engines if e in q] + [e for e in q if e not in engines]
    order = ref_order if ref_order is not None else engines
    numbered = [e for e in order if e in q] + [e for e in q if e not in order]
    refs: list[dict[str, Any]] = []
    ref_index: dict[str, int] = {}

    def ref(engine: str, fact: str) -> list[int]:
        src = (q[engine].get("sources") or {}).get(fact)
        if not src:
            return []
        items = src if isinstance(src, list) else [src]
        nums = []
        for item in items:
            text = str(item).strip()
            if text not in ref_index:
                ref_index[text] = len(refs) + 1
                m = re.match(r"^(https?://\S+?)([.,;:]?(?:\s+.*)?)$", text)
                url, rest = (m.group(1), m.group(2).strip()) if m else (None, text)
                refs.append({"n": ref_index[text], "text": text, "url": url, "rest": rest, "where": []})
            refs[ref_index[text] - 1]["where"].append(f"{engine}: {METRIC_LABELS.get(fact, fact)}")
            nums.append(ref_index[text])
        return nums

    def numbers(engine: str, fact: str) -> list[int]:
        """The numbers ref() gave a fact's sources (each source counted once, where first met)."""
        src = (q[engine].get("sources") or {}).get(fact)
        items = (src if isinstance(src, list) else [src]) if src else []
        return [ref_index[str(item).strip()] for item in items]

    def fact_text(rec: Mapping[str, Any], key: str) -> str:
        if key not in rec:
            return "–"
        v = rec[key]
        if isinstance(v, bool):
            return "yes" if v else "no"
        if key == "ros":
            return ROS_TEXT.get(str(v), str(v))
        if key == "ui":
            return UI_TEXT.get(str(v), str(v))
        if isinstance(v, (list, tuple)):
            text = ", ".join(str(x) for x in v) if v else "none"
        else:
            text = str(v)
        if key == "model_formats" and rec.get("urdf_sdf_via_manual_plugin"):
            text += "; URDF/SDF via a plugin installed by hand"
        return text

    for key in FACT_ROWS:  # the sources' numbers first, row by row in the weight-free order
        for e in numbered:
            ref(e, key)
    extra_keys = sorted({k for e in numbered for k in (q[e].get("sources") or {}) if k not in FACT_ROWS})
    for e in numbered:
        for k in extra_keys:
            ref(e, k)
    rows = []
    for key in FACT_ROWS:
        cells = []
        for e in shown:
            rec = q[e]
            score = data.weighted.loc[e, key] if (e in data.weighted.index and key in data.weighted.columns) else None
            cells.append({"text": fact_text(rec, key), "score": score, "refs": numbers(e, key)})
        rows.append({"key": key, "label": METRIC_LABELS.get(key, key), "cells": cells})
    family = []
    for e in shown:
        sims = q[e].get("paper_simulators")
        family.append({"engine": e, "simulators": list(sims) if sims else [], "known": "paper_simulators" in q[e]})
    notes = []
    for e in numbered:
        for k, text in (q[e].get("notes") or {}).items():
            notes.append({"engine": e, "fact": METRIC_LABELS.get(k, k), "text": str(text)})
    return {"engines": shown, "rows": rows, "refs": refs, "family": family, "notes": notes}


def _sorted_runs(data: ReportData, tests: list[tuple[str, str]], engines: list[str]):
    """The lab runs, each with its test's label, by engine then test."""
    runs = data.runs.copy()
    runs["test"] = [test_label(t, m) for t, m in zip(runs["terrain"], runs["motion"])]
    order = {tm: i for i, tm in enumerate(tests)}
    runs["_e"] = [engines.index(e) if e in engines else len(engines) for e in runs["engine"]]
    runs["_t"] = [order.get((t, m), len(order)) for t, m in zip(runs["terrain"], runs["motion"])]
    return runs.sort_values(["_e", "_t"], kind="mergesort")


def run_health(data: ReportData, tests: list[tuple[str, str]], engines: list[str]) -> dict[str, Any]:
    """The runs that failed their health checks and how many ran: what the body says of them (section 1),
    without the tables of :func:`runs`."""
    records = _sorted_runs(data, tests, engines).to_dict("records")
    failed = [r for r in records if str(r["status"]).strip().lower() != "ok"]
    return {"failed": failed, "n": len(records)}


def runs(data: ReportData, tests: list[tuple[str, str]], engines: list[str]) -> dict[str, Any]:
    runs = _sorted_runs(data, tests, engines)
    records = runs.to_dict("records")
    failed = [r for r in records if str(r["status"]).strip().lower() != "ok"]
    pivot = []
    for t, m in tests:
        cells = []
        for e in engines:
            sel = runs[(runs["engine"] == e) & (runs["terrain"] == t) & (runs["motion"] == m)]
            if len(sel):
                r = sel.iloc[0]
                cells.append(
                    {
                        "steps_per_s": r["steps_per_s"],
                        "rtf": r["real_time_factor"],
                        "ok": str(r["status"]).strip().lower() == "ok",
                        "present": True,
                    }
                )
            else:
                cells.append({"present": False})
        pivot.append({"test": test_label(t, m), "cells": cells})
    versions = [
        {
            "engine": r["engine"],
            "test": r["test"],
            "version": r["engine_version"] or "–",
            "config_hash": r["config_hash"] or "–",
        }
        for r in records
    ]
    return {"records": records, "failed": failed, "n": len(records), "pivot": pivot, "versions": versions}


def cpu(data: ReportData, engines: list[str]) -> dict[str, Any] | None:
    if not data.cpu:
        return None
    recs = sorted(data.cpu, key=lambda r: engines.index(r["engine"]) if r["engine"] in engines else len(engines))
    rows = []
    for r in recs:
        e = r["engine"]
        health = r.get("health") or {}
        row = {
            "engine": e,
            "status": health.get("status", "unchecked" if not health else "ok"),
            "reasons": list(health.get("reasons") or []),
        }
        for scen in ("average", "intense"):
            s = r.get(scen) or {}
            row[scen] = {
                "robots": s.get("robots"),
                "load": s.get("load_percent"),
                "repeats": list(s.get("repeats_percent") or []),
                "score": data.weighted.loc[e, f"cpu_{scen}"] if e in data.weighted.index else None,
            }
        rows.append(row)
    definitions = []
    for r in recs:
        d = str(r.get("definition", "")).strip()
        if d and d not in [x["text"] for x in definitions]:
            definitions.append({"text": d, "engines": [r["engine"]]})
        elif d:
            next(x for x in definitions if x["text"] == d)["engines"].append(r["engine"])
    return {"rows": rows, "definitions": definitions, "n_defs": len(definitions)}


def imu(data: ReportData, engines: list[str], tests: list[tuple[str, str]]) -> dict[str, Any] | None:
    if data.imu_errors is None:
        return None
    ie = data.imu_errors.copy()
    ie["_e"] = [engines.index(e) if e in engines else len(engines) for e in ie["engine"]]
    ie = ie.sort_values(["quantity", "_e"], kind="mergesort")
    rows = []
    for r in ie.to_dict("records"):
        key = f"imu_{r['quantity']}"
        score = (
            data.weighted.loc[r["engine"], key]
            if (r["engine"] in data.weighted.index and key in data.weighted.columns)
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
    coverage = {}
    for q, sel in ie.groupby("quantity"):
        n = sorted({int(x) for x in sel["n_tests"] if not isnan(x)})
        coverage[q] = n
    uneven = {q: n for q, n in coverage.items() if len(n) > 1}
    breakdown = []
    pte = data.per_test_errors
    if pte is not None and len(pte):
        order = {tm: i for i, tm in enumerate(tests)}
        for q in ("angular", "linear"):
            sel = pte[pte["quantity"] == q]
            if not len(sel):
                continue
            trs = []
            for e in engines:
                es = sel[sel["engine"] == e]
                keys = sorted(
                    {(t, m) for t, m in zip(es["terrain"], es["motion"])}, key=lambda tm: order.get(tm, len(order))
                )
                for t, m in keys:
                    ts = es[(es["terrain"] == t) & (es["motion"] == m)].set_index("axis")
                    cells = {
                        a: (
                            {"range": ts.loc[a, "range_error"], "mean": ts.loc[a, "mean_error"]}
                            if a in ts.index
                            else None
                        )
                        for a in figures.AXES
                    }
                    trs.append(
                        {"engine": e, "test": test_label(t, m), "cells": cells, "total": float(ts["total_error"].sum())}
                    )
            breakdown.append({"quantity": q, "unit": QUANTITY_UNITS[q], "rows": trs})
    return {"rows": rows, "uneven": uneven, "breakdown": breakdown}


def reference(data: ReportData, tests: list[tuple[str, str]]) -> dict[str, Any]:
    ref = data.reference_stats
    have: list[dict[str, Any]] = []
    if ref is not None and len(ref):
        for (t, m), sel in ref.groupby(["terrain", "motion"], sort=False):
            srcs = sorted({s for s in sel["source"] if s})
            have.append(
                {
                    "terrain": t,
                    "motion": m,
                    "test": test_label(t, m),
                    "sources": srcs,
                    "quantities": sorted(set(sel["quantity"])),
                }
            )
    keys = {(h["terrain"], h["motion"]) for h in have}
    without = [test_label(t, m) for t, m in tests if (t, m) not in keys]
    covered = None
    if data.imu_errors is not None:
        covered = sorted({t for ts in data.imu_errors["tests"] for t in str(ts).split(";") if t.strip()})
    return {"tests": have, "without": without, "covered": covered, "given": ref is not None}


def status_map(data: ReportData) -> dict[tuple[str, str, str], str]:
    return {
        (r["engine"], r["terrain"], r["motion"]): str(r["status"]).strip().lower() for r in data.runs.to_dict("records")
    }


def per_test(data: ReportData, engines: list[str], tests: list[tuple[str, str]]) -> list[dict[str, Any]]:
    """Per lab test: its figures (rules figure_imu_stats, figure_traces) and where each run ended
    (rule figure_paths' endpoints table)."""
    status = status_map(data)
    ref = data.reference_stats
    ends = data.endpoints
    out = []
    for t, m in tests:
        item: dict[str, Any] = {"test": test_label(t, m), "terrain": t, "motion": m}
        failed = [e for e in engines if status.get((e, t, m), "ok") != "ok" and (e, t, m) in status]
        item["failed"] = failed
        if data.trace_stats is not None:
            rsel = None
            if ref is not None:
                rsel = ref[(ref["terrain"] == t) & (ref["motion"] == m)]
                if len(rsel):
                    item["reference_sources"] = sorted({s for s in rsel["source"] if s})
            item["has_reference"] = rsel is not None and len(rsel) > 0
            key = f"imu_stats/{t}/{m}"
            item["imu_uri"] = figures.data_uri(data.figures[key]) if key in data.figures else None
        if ends is not None:
            sel = ends[(ends["terrain"] == t) & (ends["motion"] == m)]
            rows = {r["engine"]: r for r in sel.to_dict("records")}
            item["trace_engines"] = [e for e in engines if e in rows]
            item["missing_traces"] = [e for e in engines if e not in rows and e not in failed and (e, t, m) in status]
            key = f"traces/{t}/{m}"
            item["ts_uri"] = figures.data_uri(data.figures[key]) if key in data.figures and rows else None
            item["endpoints"] = [rows.get(e) for e in engines]
        out.append(item)
    return out


def published(data: ReportData) -> dict[str, Any] | None:
    if data.table11 is None:
        return None
    t11 = data.table11
    sims = list(t11.index)
    cmp_ = data.table11_comparison
    lookup = {}
    if cmp_ is not None:
        for r in cmp_.to_dict("records"):
            lookup[(r["simulator"], r["metric"])] = r
    rows = []
    for m in METRICS:
        cells = []
        for s in sims:
            c = lookup.get((s, m))
            cells.append(
                {
                    "published": c["published"] if c else None,
                    "recomputed": t11.loc[s, m] if m in t11.columns else None,
                    "matches": bool(c["matches"]) if c else None,
                }
            )
        rows.append({"label": METRIC_LABELS.get(m, m), "weight": DEFAULT_WEIGHTS[m], "cells": cells})
    totals = [
        {
            "simulator": s,
            "total": t11.loc[s, "total"],
            "from_published": t11.loc[s, "total_from_published_scores"],
            "printed": t11.loc[s, "published_total"],
            "diff": float(t11.loc[s, "published_total"]) - float(t11.loc[s, "total_from_published_scores"]),
            "diff_recomputed": float(t11.loc[s, "total"]) - float(t11.loc[s, "published_total"]),
        }
        for s in sims
    ]
    mismatches = [r for r in (cmp_.to_dict("records") if cmp_ is not None else []) if not r["matches"]]
    for r in mismatches:
        r["label"] = METRIC_LABELS.get(r["metric"], r["metric"])
    return {
        "sims": sims,
        "rows": rows,
        "totals": totals,
        "mismatches": mismatches,
        "n_compared": 0 if cmp_ is None else len(cmp_),
    }


def worked(data: ReportData) -> dict[str, Any] | None:
    we = data.worked_example
    if not we:
        return None
    blocks = []
    for q in ("angular", "linear"):
        b = we.get(q)
        if not b:
            continue
        axes = []
        for a in figures.AXES:
            rec = (b.get("axes") or {}).get(a, {})
            pr = (b.get("printed_axes") or {}).get(a, {})
            axes.append(
                {
                    "axis": a,
                    "rec": rec,
                    "printed": pr,
                    "differs": any(
                        abs(float(rec.get(k, 0)) - float(pr.get(k, 0))) > 1e-9
                        for k in ("range_error", "mean_error", "total_error")
                        if k in rec and k in pr
                    ),
                }
            )
        figs = [b.get("total_from_inputs"), b.get("printed_rows_sum"), b.get("text_total")]
        agree = all(f is not None for f in figs) and max(figs) - min(figs) < 1e-9
        blocks.append(
            {
                "quantity": q,
                "unit": b.get("unit", QUANTITY_UNITS[q]),
                "axes": axes,
                "total_from_inputs": b.get("total_from_inputs"),
                "printed_rows_sum": b.get("printed_rows_sum"),
                "text_total": b.get("text_total"),
                "agree": agree,
            }
        )
    return {
        "source": we.get("source"),
        "test": we.get("test") or {},
        "frame": we.get("sensor_frame") or {},
        "blocks": blocks,
    }
