"""How the real robot turns: its yaw-rate gain against the command.

The rigid Coulomb model (:mod:`simpick.coulomb`) predicts one gain for a given turn radius,
whatever the speed, the size of the wheel-speed difference and the friction coefficient: its
dissipation is positively homogeneous in the rim speeds, so scaling the command scales the
twist. A compliant contact (slip that grows with the force, as in a tyre's linear region, or
ODE's force-dependent slip) makes the gain depend on the speeds themselves; sinkage and
bulldozing (soft ground) make it depend on how long and how fast the wheels scrub. So the
question the data can answer is which of these variables the real gain follows.

:func:`turning_windows` cuts each real log into short windows of steady command (both side
speeds within a tolerance over the window and a settling time before it) and measures in each
the gain = mean gyro yaw rate / kinematic yaw rate ``(v_right - v_left) / track``, with the
command's speed, turn radius and wheel-speed difference. :func:`turning_summary` gives per
terrain class the spread between runs and the rank correlation of the gain with each variable
(Spearman, over runs' windows; with the caveat that windows of one run are not independent,
so a correlation is read together with the run-to-run spread).
"""

from __future__ import annotations

import math
from functools import cache

import numpy as np
import pandas as pd
from pydantic import Field

from simpick.coulomb import load_layout, ratio_for_gain, wheel_separation_multiplier, yaw_rate_gain
from simpick.inputs.robot import load_robot
from simpick.params import NonNegative, Positive
from simpick.real.logs import read_canonical
from simpick.real.settings import SteadyRules
from simpick.tables import write_csv

WINDOW_COLUMNS = [
    "dataset",
    "terrain_class",
    "run",
    "t_start",
    "t_end",
    "v_left",
    "v_right",
    "v",
    "w_kinematic",
    "wheel_speed_difference",
    "turn_radius",
    "yaw_rate",
    "yaw_rate_gain",
    "coulomb_gain",
]
SUMMARY_COLUMNS = [
    "terrain_class",
    "windows",
    "runs",
    "gain_median",
    "gain_q25",
    "gain_q75",
    "run_gain_min",
    "run_gain_max",
    "left_gain_median",
    "right_gain_median",
    "spin_gain_median",
    "moving_gain_median",
    "rho_speed",
    "p_speed",
    "rho_radius",
    "p_radius",
    "rho_difference",
    "p_difference",
    "coulomb_gain_min",
    "coulomb_gain_max",
    "separation_multiplier",
    "coulomb_ratio",
]
SPIN_SPEED = 0.05  # m/s: below this mean side speed a turn is a spin on the spot (turn radius 0)


def turning_windows(
    log,
    track: float,
    *,
    window: float = 1.0,
    settle: float = 0.5,
    tolerance: float = 0.05,
    min_turn: float = 0.1,
    coulomb=None,
) -> pd.DataFrame:
    """Steady-command turning windows of one canonical log (wheel commands), one row each.

    A window [t, t + window) counts when every command sample in [t - settle, t + window] keeps
    both side speeds within ``tolerance`` m/s of their window means (so the wheels had time to
    reach the command) and the kinematic yaw rate exceeds ``min_turn`` rad/s. Windows do not
    overlap. ``coulomb``, a callable (v, w) -> gain, adds the rigid-Coulomb prediction at each
    window's command.
    """
    # a log of body commands (v, w: a user's own CSV or bag) is read as the wheel speeds they command
    imu, cmd = log.imu, log.wheel_commands(track)
    t_imu, wz = imu["time"].to_numpy(float), imu["wz"].to_numpy(float)
    t_cmd = cmd["time"].to_numpy(float)
    left, right = cmd["v_left"].to_numpy(float), cmd["v_right"].to_numpy(float)
    rows = []
    start = max(t_imu[0], t_cmd[0]) + settle
    while start + window <= min(t_imu[-1], t_cmd[-1]):
        held = (t_cmd >= start - settle) & (t_cmd <= start + window)
        inside = (t_imu >= start) & (t_imu < start + window)
        steady = held.sum() >= 2 and np.ptp(left[held]) <= 2 * tolerance and np.ptp(right[held]) <= 2 * tolerance
        if steady and inside.any():
            v_left, v_right = float(left[held].mean()), float(right[held].mean())
            v, w = (v_left + v_right) / 2, (v_right - v_left) / track
            if abs(w) > min_turn:
                yaw = float(wz[inside].mean())
                rows.append(
                    {
                        "dataset": log.meta.get("dataset", ""),
                        "terrain_class": str(log.meta.get("terrain_class", "")).lower(),
                        "run": str(log.meta.get("run_id", "")),
                        "t_start": round(float(start), 3),
                        "t_end": round(float(start + window), 3),
                        "v_left": v_left,
                        "v_right": v_right,
                        "v": v,
                        "w_kinematic": w,
                        "wheel_speed_difference": v_right - v_left,
                        "turn_radius": 0.0 if abs(v) < SPIN_SPEED else abs(v / w),
                        "yaw_rate": yaw,
                        "yaw_rate_gain": yaw / w,
                        "coulomb_gain": float(coulomb(v, w)) if coulomb is not None else math.nan,
                    }
                )
                start += window
                continue
        start += window / 2
    return pd.DataFrame(rows, columns=WINDOW_COLUMNS)


def _spearman(x: pd.Series, y: pd.Series) -> tuple[float, float]:
    from scipy.stats import spearmanr  # about 2 s to import: only where needed (simpick.compare.realmetrics)

    if len(x) < 4 or np.ptp(x) <= 1e-9 or np.ptp(y) <= 1e-9:  # a constant has no rank to correlate
        return math.nan, math.nan
    result = spearmanr(x, y)
    return float(result.statistic), float(result.pvalue)


def turning_summary(windows: pd.DataFrame) -> pd.DataFrame:
    """Per terrain class: the gain's median and quartiles over windows, the range of the runs'
    medians, left against right turns, spins against moving turns, and Spearman's rank
    correlation (rho, p) of the gain with |speed|, turn radius and |wheel-speed difference|."""
    rows = []
    for cls, g in windows.groupby("terrain_class", sort=True):
        runs = g.groupby("run")["yaw_rate_gain"].median()
        spin = g["turn_radius"] == 0
        row = {
            "terrain_class": cls,
            "windows": len(g),
            "runs": int(runs.size),
            "gain_median": g["yaw_rate_gain"].median(),
            "gain_q25": g["yaw_rate_gain"].quantile(0.25),
            "gain_q75": g["yaw_rate_gain"].quantile(0.75),
            "run_gain_min": runs.min(),
            "run_gain_max": runs.max(),
            "left_gain_median": g.loc[g["w_kinematic"] > 0, "yaw_rate_gain"].median(),
            "right_gain_median": g.loc[g["w_kinematic"] < 0, "yaw_rate_gain"].median(),
            "spin_gain_median": g.loc[spin, "yaw_rate_gain"].median(),
            "moving_gain_median": g.loc[~spin, "yaw_rate_gain"].median(),
            "coulomb_gain_min": g["coulomb_gain"].min(),
            "coulomb_gain_max": g["coulomb_gain"].max(),
        }
        for name, column in (
            ("speed", g["v"].abs()),
            ("radius", g["turn_radius"]),
            ("difference", g["wheel_speed_difference"].abs()),
        ):
            row[f"rho_{name}"], row[f"p_{name}"] = _spearman(column, g["yaw_rate_gain"])
        rows.append(row)
    return pd.DataFrame(rows, columns=SUMMARY_COLUMNS)


def with_equivalents(summary: pd.DataFrame, layout, track: float, separation: float) -> pd.DataFrame:
    """The summary with, per class, what its median gain means for a user:
    ``separation_multiplier``, the ROS diff_drive_controller wheel_separation_multiplier that makes
    a controller on the robot's geometric wheel separation turn it as commanded, and
    ``coulomb_ratio``, the lateral/longitudinal friction ratio at which anisotropic Coulomb gives
    that gain (the same at every command; NaN outside 0.02-2)."""
    out = summary.copy()
    out["separation_multiplier"] = [wheel_separation_multiplier(g, track, separation) for g in out.gain_median]
    out["coulomb_ratio"] = [ratio_for_gain(layout, g, 0.5, 0.5, track) for g in out.gain_median]
    return out


class TurningParams(SteadyRules):
    """What rule real_turning's job reads: the controller's track, the windows' length and settling, and when
    a command is steady and turning (the segment rules' tolerance and min_turn)."""

    track: Positive = Field(description="m, the controller's track (the config's robot.track)")
    window: Positive = Field(description="s, the length of a steady-command window")
    settle: NonNegative = Field(description="s of held command before a window")


def turning_job(logs: list[str], urdf: str, params: dict, outputs: dict[str, str]) -> None:
    """Rule real_turning: the windows of every canonical log of a replayed dataset and their
    per-class summary, with the rigid-Coulomb gain of the study's robot at each command."""
    p = TurningParams.model_validate(params)
    track = p.track
    layout = load_layout(urdf)

    @cache
    def coulomb(v: float, w: float) -> float:
        return yaw_rate_gain(layout, v, w, track)

    options = {"window": p.window, "settle": p.settle, "tolerance": p.tolerance, "min_turn": p.min_turn}
    frames = [
        turning_windows(read_canonical(path), track, coulomb=lambda v, w: coulomb(round(v, 3), round(w, 3)), **options)
        for path in logs
    ]
    windows = pd.concat(frames, ignore_index=True) if frames else pd.DataFrame(columns=WINDOW_COLUMNS)
    write_csv(windows, outputs["windows"])

    separation = load_robot(urdf).track  # the wheels' geometric separation (the controller's wheel_separation)
    write_csv(with_equivalents(turning_summary(windows), layout, track, separation), outputs["summary"])
