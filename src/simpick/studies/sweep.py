"""Speed-accuracy sweeps: every engine over the committed real segments at several physics timesteps.

A sweep config (``config/sweeps/timestep.yaml``) names the timesteps; the workflow
(``rules/sweep.smk``) runs one job per engine x terrain class x timestep. A job is the segments
source's own path at that timestep: its class's segments simulated as the source's simulate job
does (:func:`simpick.simulate.jobs.simulate_job`: the same cases, metadata, start headings and per-case
watchdog), compared as its compare job does (:func:`simpick.sources.segments.compare`), one row
per segment: its per-test row and its run's timing. :func:`summarise` then puts each class and
timestep through the source's summarise step (:func:`simpick.compare.jobs.source_tables`): Eq. 7 and
the per-run aggregation are the source's, not restated here. At the study's own timestep a sweep
point's figures are the segments source's figures.

What each column follows (the source's rules): an engine's errors are its means over runs (a
run's segments averaged first) of the segments it ran healthily, with intervals and ``n_runs``
from the ``statistics`` settings; the Eq. 7 totals and the real-time factor cover the segments
every engine ran healthily (a segment any engine failed is left out of them for all, and listed in
``excluded``); an engine's failed segments (diverged, hung, not run) are counted in ``n_failed``,
never averaged in.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.compare.jobs import source_tables
from simpick.compare.kinds import BY_KIND
from simpick.compare.real import SEGMENT_TEST_COLUMNS
from simpick.simulate.jobs import simulate_job
from simpick.simulate.real import SegmentsUnitParams
from simpick.tables import write_csv

# a segment's timing, from its compare job's run row, beside its per-test row
TIMING = ("sim_time", "wall_time", "cpu_time", "steps")
SUMMARY_COLUMNS = (
    "terrain_class",
    "engine",
    "timestep",
    "n_segments",
    "n_failed",
    "n_compared",
    "n_runs",
    "excluded",
    "error_angular",
    "error_angular_low",
    "error_angular_high",
    "error_linear",
    "error_linear_low",
    "error_linear_high",
    "gain_error",
    "gain_error_low",
    "gain_error_high",
    "total_angular",
    "total_linear",
    "n_common",
    "real_time_factor",
    "steps_per_s",
)


class SweepPointParams(SegmentsUnitParams):
    """What rule sweep_segments' job reads: a segments unit's params (simpick.sources.segments.case_params) of one
    terrain class's segments on one model, at the sweep point's timestep."""


def sweep_job(inputs: dict, params: dict, settings: dict, output: str) -> None:
    """Every segment of one class (:class:`SweepPointParams`) on one engine at the sweep point's timestep,
    simulated and compared as the segments source's jobs do; one CSV row per segment
    (:func:`compare_traces`). A case that hangs is written failed with the cases after it (the
    simulate job's watchdog), and the rows are written before the process ends, so the summary
    counts them as failed."""
    p = SweepPointParams.model_validate(params)
    folder = tempfile.mkdtemp(prefix="simpick-sweep-")
    traces = [str(Path(folder) / f"{name}.parquet") for name in p.cases]

    def compare_and_write() -> None:
        write_csv(compare_traces(traces, inputs, params, settings), output)
        shutil.rmtree(folder, ignore_errors=True)

    try:
        # simulate_job (simpick.simulate.jobs) reads the params as a mapping still: its stage converts them
        simulate_job(traces, inputs["urdf"], inputs, params, after_hung=compare_and_write)
        compare_and_write()
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def compare_traces(traces: list[str], inputs: dict, params: dict, settings: dict) -> pd.DataFrame:
    """A sweep point's traces compared by their kind's comparison (simpick.compare.kinds, as the
    compare job): its per-test rows with each run's timing (:data:`TIMING`) and the timestep."""
    p = SweepPointParams.model_validate(params)
    per_test, _, runs = BY_KIND[p.kind](traces, inputs, settings)
    timing = runs[["engine", "test", *TIMING]].astype({"test": str})
    rows = per_test.astype({"test": str}).merge(timing, on=["engine", "test"], how="left", validate="one_to_one")
    return rows.assign(timestep=p.physics.timestep)


def summarise(rows: pd.DataFrame, statistics: dict | None = None) -> pd.DataFrame:
    """Per class, engine and timestep: the segments source's tables of those rows
    (:func:`simpick.compare.jobs.source_tables`) with the sweep's counts and the cost of a step."""
    out = []
    for (cls, dt), group in rows.groupby(["terrain_class", "timestep"], sort=True):
        tables = source_tables(
            group[SEGMENT_TEST_COLUMNS], group[["engine", "test", "status", *TIMING]], "terrain_class", statistics
        )
        summary = tables["summary"].set_index("engine")
        totals = tables["imu_errors"].pivot(index="engine", columns="quantity", values="error")
        common = tables["imu_errors"].drop_duplicates("engine").set_index("engine")
        rtf = tables["rtf"].set_index("engine").real_time_factor
        for engine, g in group.groupby("engine", sort=True):
            figures = summary.loc[engine] if engine in summary.index else pd.Series(dtype=float)
            row = {
                "terrain_class": cls,
                "engine": engine,
                "timestep": float(dt),
                "n_segments": len(g),
                "n_failed": int((g.status != "ok").sum()),
                "n_compared": int(figures.get("n_tests", 0)),
                "n_runs": int(figures.get("n_runs", 0)),
                "excluded": common.loc[engine, "excluded"].replace(";", "; "),
                "total_angular": totals.loc[engine, "angular"],
                "total_linear": totals.loc[engine, "linear"],
                "n_common": int(common.loc[engine, "n_tests"]),
                "real_time_factor": rtf.loc[engine],
                # sim_time is steps x timestep: steps per wall second over the same segments
                "steps_per_s": rtf.loc[engine] / float(dt),
            }
            row.update(
                {
                    f"{name}{end}": figures.get(f"{name}{end}", np.nan)
                    for name in ("error_angular", "error_linear", "gain_error")
                    for end in ("", "_low", "_high")
                }
            )
            out.append(row)
    return pd.DataFrame(out, columns=list(SUMMARY_COLUMNS))


def sweep_summary_job(inputs: list[str], output: str, statistics: dict | None = None) -> None:
    rows = pd.concat(
        [pd.read_csv(p, dtype={"run": str, "test": str, "segment": str}) for p in inputs], ignore_index=True
    )
    write_csv(summarise(rows, statistics), output)
