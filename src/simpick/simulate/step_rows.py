"""A replayed step's summary row, and the row of a step not replayed: what a step-replay job writes and the
compare stage reads. Kept apart from :mod:`simpick.simulate.steps`, which drives the engines, so that the
compare jobs depend on the rows' shape alone: an edit to how steps are driven reruns the step replays, not
every source's comparison (the rules' code versions follow imports)."""

from __future__ import annotations

import numpy as np
import pandas as pd

START_WINDOW_S = 0.5  # s at the end of the warm-up averaged for the simulated start state (as the real one)
STEP_COLUMNS = [
    "case",
    "session",
    "terrain_class",
    "step",
    "engine",
    "status",
    "reasons",
    "warmup",
    "start_heading_deg",
    "sim_start_vx",
    "sim_start_wz",
    "sim_v",
    "sim_yaw_rate",
    "sim_heading",
    "wall_time",
    "sim_time",
]


def _mean(frame: dict, column: str, start: float, end: float) -> float:
    t = np.asarray(frame["time"])
    inside = (t > start) & (t <= end)
    return float(np.mean(np.asarray(frame[column])[inside])) if inside.any() else float("nan")


def step_row(frame, meta: dict, case) -> dict:
    """A replayed step's summary row (``STEP_COLUMNS``: the simulated start state, steady means and heading
    change, health, wall time) from its frame and metadata (:func:`drive_step`)."""
    warmup = float(meta["warmup"])
    a, b = warmup + float(case.steady_start), warmup + float(case.steady_end)
    sim_wz = _mean(frame, "yaw_rate", a, b)
    yaw = np.asarray(frame["yaw"])
    t = np.asarray(frame["time"])
    inside = (t > a) & (t <= b)
    return {
        "case": case.case,
        "session": case.session,
        "terrain_class": case.terrain_class,
        "step": int(case.step),
        "engine": meta["engine"],
        "status": meta["health"]["status"],
        "reasons": "; ".join(meta["health"]["reasons"]),
        "warmup": warmup,
        "start_heading_deg": float(np.degrees(meta["start_heading"])),
        "sim_start_vx": _mean(frame, "v_forward", warmup - START_WINDOW_S, warmup),
        "sim_start_wz": _mean(frame, "yaw_rate", warmup - START_WINDOW_S, warmup),
        "sim_v": _mean(frame, "v_forward", a, b),
        "sim_yaw_rate": sim_wz,
        "sim_heading": float(yaw[inside][-1] - yaw[inside][0]) if inside.sum() > 1 else float("nan"),
        "wall_time": meta["wall_time_step"],
        "sim_time": meta["sim_time"],
    }


def hung_row(case, engine: str, reason: str) -> dict:
    """The step row of a step not replayed (its engine hung, or hung before it)."""
    return {
        "case": case.case,
        "session": case.session,
        "terrain_class": case.terrain_class,
        "step": int(case.step),
        "engine": engine,
        "status": "failed",
        "reasons": reason,
    }


def hung_rows(cases: pd.DataFrame, engine: str, reason: str) -> pd.DataFrame:
    return pd.DataFrame([hung_row(c, engine, reason) for c in cases.itertuples()], columns=STEP_COLUMNS)
