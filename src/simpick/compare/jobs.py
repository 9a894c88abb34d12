"""The compare stage's jobs, the same for every source: its traces against their reference (by its
kind's comparison: :mod:`simpick.compare.kinds`), then its per-test rows summed (Eq. 7) and summarised.
"""

from __future__ import annotations

import pandas as pd

from simpick.compare import metrics
from simpick.compare.kinds import BY_KIND
from simpick.compare.real import class_verdicts, pairwise_table, summary_table
from simpick.compare.settings import SummariseSettings
from simpick.tables import write_csv


def compare_job(kind: str, traces: list[str], inputs: dict, params: dict, outputs: dict[str, str]) -> None:
    """One source's traces against what they are compared with, by its kind's comparison
    (:data:`simpick.compare.kinds.BY_KIND`; ``kind`` is the source's DRIVEN kind): the paper's reference statistics
    (lab), each segment's real window statistics (segments), the real log window by window
    (replay). Writes ``per_test`` (Eq. 7 per model and test: what scores and summaries use),
    ``detail`` (the rows a test's error sums: per axis, or per window for a replay) and ``runs``
    (each trace's timing and health)."""
    per_test, detail, runs = BY_KIND[kind](traces, inputs, params)
    write_csv(per_test, outputs["per_test"])
    write_csv(detail, outputs["detail"])
    write_csv(runs, outputs["runs"])


def summarise_job(per_test: str, runs: str, params: dict, outputs: dict[str, str]) -> None:
    """A source's per-test rows summed and summarised (:func:`source_tables`; :class:`SummariseSettings`: the
    group column and the statistics), each table written to its ``outputs`` entry."""
    p = SummariseSettings.model_validate(params)
    tests = pd.read_csv(per_test, dtype={"run": str, "test": str})
    run_table = pd.read_csv(runs, dtype={"terrain": str, "motion": str, "test": str})
    statistics = None if p.statistics is None else p.statistics.model_dump()
    for name, table in source_tables(tests, run_table, p.group, statistics).items():
        write_csv(table, outputs[name])


def source_tables(tests, run_table, group: str, statistics: dict | None = None) -> dict:
    """A source's per-test rows (its compare job's ``per_test``) and run rows (``runs``) summed and
    summarised, the same way for every source and for the sweep at each timestep (simpick.studies.sweep):
    Eq. 7 totals over the tests every model completed (``imu_errors``), the real-time factor over
    the tests every model ran healthily (``rtf``), per model and ``group`` (terrain or terrain
    class) means with intervals and paired verdicts over independent runs (``summary``,
    ``pairwise``: simpick.compare.real.summary_table, pairwise_table)."""
    pairwise = pairwise_table(tests, group, statistics)
    return {
        "imu_errors": metrics.eq7_totals(tests, engines=run_table.engine.unique()),
        "rtf": equal_rtf(run_table),
        "summary": class_verdicts(summary_table(tests, group, statistics), pairwise, group),
        "pairwise": pairwise,
    }


def equal_rtf(runs) -> pd.DataFrame:
    """Eq. 2 per engine over the same tests for every engine: a test any engine failed is left
    out for all (an engine failing the slowest terrain would otherwise look faster) and named
    in ``excluded``; an engine with no run of a test leaves that test out too."""
    if "test" not in runs:  # a run table without the test column (TRACE_KEYS) names it by terrain/motion
        runs = runs.assign(test=runs.terrain + "/" + runs.motion)
    runs = runs.assign(test=runs.test.astype(str))
    engines = sorted(runs.engine.unique())
    ok = runs[runs.status == "ok"]
    common = set.intersection(*(set(ok[ok.engine == e].test) for e in engines)) if engines else set()
    excluded = ";".join(sorted(set(runs.test) - common))
    rows = []
    for engine in engines:
        g = ok[(ok.engine == engine) & ok.test.isin(common)]
        rows.append(
            {
                "engine": engine,
                "sim_time": g.sim_time.sum(),
                "wall_time": g.wall_time.sum(),
                "real_time_factor": (metrics.real_time_factor(g.sim_time, g.wall_time) if len(g) else float("nan")),
                "n_runs": len(g),
                "tests": ";".join(sorted(common)),
                "excluded": excluded,
            }
        )
    return pd.DataFrame(
        rows, columns=["engine", "sim_time", "wall_time", "real_time_factor", "n_runs", "tests", "excluded"]
    )
