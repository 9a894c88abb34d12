"""Speed-accuracy sweeps: every engine over the committed real segments at several physics timesteps.

A sweep config (``config/sweeps/timestep.yaml``) names the timesteps; the workflow
(``rules/sweep.smk``) runs one job per engine x terrain class x timestep, each driving every
segment of the class as the segments source does (:mod:`simpick.sources.segments`: the same
simulation and the same per-segment comparison as the study's segment jobs) and writing one row per
segment: its real-data errors, the simulated and wall seconds, the health status.
:func:`sweep_summary_job` then puts, per class, engine and timestep, the mean errors over runs
(with intervals from ``statistics.min_runs`` runs on) next to the real-time factor (simulated
seconds / wall seconds of the stepping loop).

Equal comparisons: at each class and timestep the errors are averaged over the segments every
engine ran healthily; a segment any engine failed is left out for all and listed (errors and real-time factor alike, as
:func:`simpick.workflow.equal_rtf` for the lab study), and an engine's failed segments are
counted, never averaged in.
"""

from __future__ import annotations

import sys

import numpy as np
import pandas as pd

from simpick.watchdog import DEFAULT_TIMEOUT_S
from simpick.tables import write_csv

SUMMARY_COLUMNS = ("terrain_class", "engine", "timestep", "n_segments", "n_failed", "n_compared", "n_runs",
                   "excluded", "error_angular", "error_angular_low", "error_angular_high", "error_linear",
                   "error_linear_low", "error_linear_high", "gain_error", "gain_error_low", "gain_error_high",
                   "real_time_factor", "steps_per_s")


def sweep_job(segments_csv: str, urdf: str, params: dict, output: str, timeout: float = DEFAULT_TIMEOUT_S) -> None:
    """Every segment of one class on one engine at ``params["physics"]["timestep"]``: one CSV row each.

    Under the watchdog (``timeout`` s of wall time, simpick.watchdog.runtime_timeout of the rule's
    runtime): a job still running then writes the rows it has and every segment not yet done as
    failed (hung), so the summary counts them as failed and leaves them out for every engine,
    instead of averaging a partial class."""
    from simpick.sources import segments as source
    from simpick.watchdog import Watchdog

    segments = source.class_table(segments_csv, params["terrain_class"])
    dt = float(params["physics"]["timestep"])
    rows: list[dict] = []

    def hung() -> None:
        done = len(rows)  # the rows finished so far (the main thread only appends whole rows)
        left = [hung_row(params, segments.loc[name], timeout) for name in segments.index[done:]]
        print(f"simpick: sweep {params['engine']} {params['terrain_class']} {dt:g} s: {len(left)} segment(s) "
              f"not done: {left[0]['reasons'] if left else ''}", file=sys.stderr)
        write_csv(pd.DataFrame(rows[:done] + left), output)

    with Watchdog(timeout, hung):
        for name in segments.index:
            seg = segments.loc[name]
            frame, meta = source.simulate(seg, urdf, params)
            row = source.row(pd.DataFrame(frame), meta, seg, params["robot"]["track"])
            row.update({"timestep": dt, "steps": int(meta["steps"]), "sim_time": int(meta["steps"]) * dt,
                        "wall_time": float(meta["wall_time"])})
            rows.append(row)
    write_csv(pd.DataFrame(rows), output)


def hung_row(params: dict, seg: pd.Series, timeout: float) -> dict:
    """A segment the watchdog stopped, or never reached: failed, with the reason; no errors."""
    from simpick.watchdog import hung_reason

    return {"engine": params["engine"], "terrain_class": seg.terrain_class, "segment": seg.name, "run": seg.run,
            "kind": seg.kind, "status": "failed", "reasons": hung_reason(timeout),
            "yaw_rate_gain_real": seg.yaw_rate_gain, "error_angular": np.nan, "error_linear": np.nan,
            "yaw_rate_gain_sim": np.nan, "speed_sim": np.nan, "timestep": float(params["physics"]["timestep"]),
            "steps": 0, "sim_time": 0.0, "wall_time": np.nan}


def summarise(runs: pd.DataFrame, statistics: dict | None = None) -> pd.DataFrame:
    """Per class, engine and timestep: errors over the segments every engine ran healthily, as the
    real data's rule has it (simpick.realmetrics: a run's segments averaged first, the mean over
    runs, a BCa interval only from ``statistics.min_runs`` runs on), and the real-time factor."""
    from simpick.realmetrics import mean_ci, statistics_settings

    min_runs, level = statistics_settings(statistics)
    out = []
    for (cls, dt), group in runs.groupby(["terrain_class", "timestep"], sort=True):
        bad = sorted(set(group.loc[group.status != "ok", "segment"]))
        compared = group[~group.segment.isin(bad)]
        for engine, g in group.groupby("engine", sort=True):
            c = compared[compared.engine == engine]
            turning = c[c.kind == "turning"]
            wall = float(c.wall_time.sum())  # the same segments for every engine (workflow.equal_rtf's rule)
            row = {"terrain_class": cls, "engine": engine, "timestep": dt, "n_segments": len(g),
                   "n_failed": int((g.status != "ok").sum()), "n_compared": len(c),
                   "n_runs": int(c.run.astype(str).nunique()), "excluded": "; ".join(bad),
                   "real_time_factor": float(c.sim_time.sum()) / wall if wall > 0 else np.nan,
                   "steps_per_s": float(c.steps.sum()) / wall if wall > 0 else np.nan}
            figures = {"error_angular": (c, c.error_angular), "error_linear": (c, c.error_linear),
                       "gain_error": (turning, (turning.yaw_rate_gain_sim - turning.yaw_rate_gain_real).abs())}
            for name, (frame, values) in figures.items():
                mean, low, high, _ = (mean_ci(values.to_numpy(float), frame.run.astype(str).to_numpy(), min_runs, level)
                                      if len(frame) else (np.nan, np.nan, np.nan, 0))
                row.update({name: mean, f"{name}_low": low, f"{name}_high": high})
            out.append(row)
    return pd.DataFrame(out, columns=list(SUMMARY_COLUMNS))


def sweep_summary_job(inputs: list[str], output: str, statistics: dict | None = None) -> None:
    runs = pd.concat([pd.read_csv(p, dtype={"run": str}) for p in inputs], ignore_index=True)
    write_csv(summarise(runs, statistics), output)
