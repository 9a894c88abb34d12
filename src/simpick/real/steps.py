"""Step units: what a reader of a dataset whose real robot was told to hold one command per step (DRIVE's
sessions, :mod:`simpick.real.drive`) hands the stages downstream, and the figures of the real robot
computed over them.

A step unit is one row of a case table (the reader's ``cases.csv``): ``case`` (its id), ``dataset``,
``session`` (the units a job replays together), ``terrain_class``, ``step``; the state the real robot was
in at the step's start (``start_vx``, ``start_wz``, ``start_wheel_left/right`` in rad/s); the command
(``cmd_left/right``, rad/s, what a unit is paired by); the steady window compared (``steady_start``,
``steady_end``, s from the step's start); and the measured values an engine is compared with over it: the
gyro yaw rate (``yaw_rate``) and, where measured, an independent forward speed (``v_icp``; NaN where the
reader has none: a unit without it carries no speed error). Beside it, a step table (``steps.csv``: the
measured wheels' kinematic twist ``v_kin``, ``w_kin``, whether a step turns, its gain) and the wheels'
measured speeds over every step (:data:`WHEEL_COLUMNS`, the wheels table), which is what an engine
replays. Downstream of the readers (simulate, compare, score, studies, report) reads only these tables:
no stage asks which dataset a unit came from except to label it.

The real robot's figures over step units (module constants and functions): the yaw-rate gain counts on
turning steps (``|w_kin| > MIN_TURN``), the forward-speed ratio on moving ones (``|v_kin| > MIN_SPEED``).
Repeatability: the real robot's gain differs between steps of the same command. Where commands are drawn at
random no command repeats exactly; two turning steps are *similar* when both wheels' commanded speeds
differ by at most ``tolerance`` (default :data:`SIMILAR`, 1 rad/s = 0.3 m/s at the Warthog's rim, under 4 %
of its command range). Over all similar pairs of a group, the spread is the median |gain_i - gain_j| and
the single-step standard deviation sqrt(mean((gain_i - gain_j)^2) / 2) (a pair's difference has twice one
step's variance). It is the floor no model can beat.
"""

from __future__ import annotations

import math
from itertools import combinations

import numpy as np
import pandas as pd

MIN_TURN = 0.2  # rad/s: the kinematic yaw rate above which a step counts as turning (as DRIVE's README)
MIN_SPEED = 0.2  # m/s: the kinematic forward speed above which a step's speed ratio is counted
SIMILAR = 1.0  # rad/s: two steps are of similar command when both wheels' commands differ by at most this
# the wheels table: per session and step, the measured wheel speeds as rim speeds (m/s; time s from the
# step's start) and the wheel radius they were converted with (m), what an engine replays
WHEEL_COLUMNS = ["session", "step", "time", "v_left", "v_right", "wheel_radius"]


def write_wheels(frames: list[pd.DataFrame], path: str) -> None:
    """The wheels table (:data:`WHEEL_COLUMNS`) of every session, as Parquet (floats kept exactly)."""
    from pathlib import Path

    table = pd.concat(frames, ignore_index=True) if frames else pd.DataFrame(columns=WHEEL_COLUMNS)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    table[WHEEL_COLUMNS].to_parquet(path, index=False)


def similar_pairs(steps: pd.DataFrame, tolerance: float = SIMILAR) -> pd.DataFrame:
    """Every pair of turning steps of one group whose commands are similar (both wheels within
    ``tolerance`` rad/s), with the difference of their gains. Pairs are taken within a session and
    terrain (the caller groups)."""
    turning = steps[steps.turning & steps.gain.notna()]
    rows = []
    left, right, gain = (turning[c].to_numpy(float) for c in ("cmd_left", "cmd_right", "gain"))
    ids = turning[["session", "step"]].to_numpy()
    for i, j in combinations(range(len(turning)), 2):
        if abs(left[i] - left[j]) <= tolerance and abs(right[i] - right[j]) <= tolerance:
            rows.append(
                {
                    "session_a": ids[i][0],
                    "step_a": ids[i][1],
                    "session_b": ids[j][0],
                    "step_b": ids[j][1],
                    "gain_a": gain[i],
                    "gain_b": gain[j],
                    "difference": gain[i] - gain[j],
                }
            )
    return pd.DataFrame(rows, columns=["session_a", "step_a", "session_b", "step_b", "gain_a", "gain_b", "difference"])


def pair_sd(pairs: pd.DataFrame) -> float:
    """The single-step standard deviation from pairs of similar steps: sqrt(mean(difference^2) / 2), a
    pair's difference having twice one step's variance; NaN without pairs."""
    d = pairs["difference"].to_numpy(float)
    return float(np.sqrt(np.mean(d**2) / 2)) if len(d) else math.nan


def repeatability(steps: pd.DataFrame, tolerance: float = SIMILAR) -> dict:
    """The spread of the gain between steps of similar command (module doc): pairs, median |difference|,
    single-step standard deviation."""
    pairs = similar_pairs(steps, tolerance)
    d = pairs["difference"].to_numpy(float)
    return {
        "similar_pairs": len(d),
        "repeat_median_abs_diff": float(np.median(np.abs(d))) if len(d) else math.nan,
        "repeat_sd": pair_sd(pairs),
    }


def gain_bins(steps: pd.DataFrame, variable: str, edges) -> pd.DataFrame:
    """The gain per terrain in bins of one step variable (e.g. ``cmd_turn_radius``, ``v_cmd`` or
    ``cmd_wheel_speed_difference``; absolute values): steps, median, quartiles per bin."""
    t = steps[steps.turning & steps.gain.notna()].copy()
    t["bin"] = pd.cut(t[variable].abs(), edges, include_lowest=True)
    out = t.groupby(["terrain_class", "bin"], observed=True).gain.agg(
        steps="size", gain_median="median", gain_q25=lambda x: x.quantile(0.25), gain_q75=lambda x: x.quantile(0.75)
    )
    return out.reset_index().assign(variable=variable, bin=lambda f: f["bin"].astype(str))


BINS = {  # the gain against the command, per terrain: bin edges of each commanded variable (absolute values)
    "v_cmd": [0.0, 0.5, 1.0, 2.0, 3.0, math.inf],  # m/s
    "cmd_turn_radius": [0.0, 0.5, 1.0, 2.0, 5.0, math.inf],  # m (a spin is 0)
    "cmd_wheel_speed_difference": [0.0, 1.0, 2.0, 4.0, math.inf],  # m/s at the rim
}


def gain_against_command(steps: pd.DataFrame) -> pd.DataFrame:
    """:func:`gain_bins` of each variable of :data:`BINS`, in one table."""
    return pd.concat([gain_bins(steps, v, edges) for v, edges in BINS.items()], ignore_index=True)
