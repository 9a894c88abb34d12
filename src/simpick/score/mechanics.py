"""The mechanics gate: which engines pass the analytic cases each real-data metric rests on.

Read from the validation summary (results/validation/summary.csv: one row per engine, case and
checked quantity, with ``passed``; ``kind`` ``invariance`` for the checks made across yaw-gain
cases). An engine passes a metric's mechanics when it fails no case or check of the kinds the
config lists for that metric (``verdict.mechanics``). A skipped case is not a failure.
"""

from __future__ import annotations

import pandas as pd

KIND_LABELS = {
    "yaw_gain": "yaw gain",
    "straight": "straight",
    "slide": "slide",
    "incline": "incline",
    "rest": "rest",
    "invariance": "turn symmetry and heading",
    "rest_pose": "suspension at rest",
    "articulation": "suspension articulation",
}
MECHANICS_COLUMNS = [
    "engine",
    "mechanics",
    "mechanics_failed",
    "mechanics_cases",
    "checks_failed",
    "failed_kinds",
    "mechanics_note",
]


def _bool(series: pd.Series) -> pd.Series:
    return series.map(lambda v: v is True or str(v).strip().lower() == "true")


def mechanics_table(summary: pd.DataFrame, engines: list[str]) -> pd.DataFrame:
    """Per engine: ``mechanics`` pass | fail; ``mechanics_failed`` the analytic cases failed out of
    ``mechanics_cases``; ``checks_failed`` the invariance checks failed (across cases);
    ``failed_kinds`` the kinds failed (``;``-separated, for the per-metric gate); a note such as
    "fails 14 of 20 analytic cases: yaw gain (12), incline (2)". An engine the summary lacks fails,
    with the note saying it was not validated."""
    rows = []
    for engine in engines:
        own = summary[(summary.engine == engine) & (summary.status.astype(str) != "skipped")]
        if own.empty:
            rows.append(
                {
                    "engine": engine,
                    "mechanics": "fail",
                    "mechanics_failed": 0,
                    "mechanics_cases": 0,
                    "checks_failed": 0,
                    "failed_kinds": "",
                    "mechanics_note": "not validated: the validation summary has no case of this engine",
                }
            )
            continue
        failed = own[~_bool(own.passed)]
        cases = own[own.kind != "invariance"]
        failed_cases = failed[failed.kind != "invariance"].drop_duplicates("case")
        checks = failed[failed.kind == "invariance"].drop_duplicates("case")
        counts = failed_cases.groupby("kind", sort=False).size()
        n_cases = int(cases.case.nunique())
        parts = [f"{KIND_LABELS.get(k, k)} ({n})" for k, n in counts.items()]
        if len(failed_cases):
            note = f"fails {len(failed_cases)} of {n_cases} analytic cases: {', '.join(parts)}"
        else:
            note = f"passes all {n_cases} analytic cases"
        if len(checks):
            note += f"; fails {len(checks)} {KIND_LABELS['invariance']} check{'s' if len(checks) > 1 else ''}"
        rows.append(
            {
                "engine": engine,
                "mechanics": "fail" if len(failed) else "pass",
                "mechanics_failed": len(failed_cases),
                "mechanics_cases": n_cases,
                "checks_failed": len(checks),
                "failed_kinds": ";".join(sorted(set(failed.kind.astype(str)))),
                "mechanics_note": note,
            }
        )
    return pd.DataFrame(rows, columns=MECHANICS_COLUMNS)


def recommendable(mechanics: pd.DataFrame, kinds: list[str]) -> dict[str, bool]:
    """engine -> whether it fails no validation case or check of ``kinds`` (and was validated)."""
    out = {}
    for row in mechanics.to_dict("records"):
        failed = {k for k in str(row["failed_kinds"] or "").split(";") if k and k != "nan"}
        out[row["engine"]] = bool(row["mechanics_cases"]) and not (failed & set(kinds))
    return out


def failures(summary) -> dict[str, list[str]]:
    """engine -> the cases it failed (each once), in case order; skipped cases are not failures."""
    out: dict[str, list[str]] = {}
    for row in summary.itertuples():
        if row.status == "skipped":
            continue
        if not row.passed and row.case not in out.setdefault(row.engine, []):
            out[row.engine].append(row.case)
    return {e: cases for e, cases in out.items() if cases}
