"""Replayed step units against the real robot (:mod:`simpick.real.steps`: DRIVE's steps, or any reader's):
per step, pooled per session and terrain.

Per replayed step, over its steady part (the real robot's figures from the reader's step and case tables);
each metric is one a unit may or may not carry (NaN where it does not, left out of every mean):

* ``gain_error``: |simulated - real yaw-rate gain|, both over the kinematic yaw rate of the measured wheels
  (the replay's input), on turning steps (``|w_kin| >`` :data:`simpick.real.steps.MIN_TURN`); the real
  yaw rate is the gyro's (for DRIVE, its sign fixed per file by the reader);
* ``heading_error``: |simulated - real mean yaw rate| x the steady time (rad,
  :func:`simpick.compare.realmetrics.heading_error`), on every step;
* ``speed_error``: |simulated forward speed - the independently measured forward speed| (m/s; DRIVE's
  lidar-ICP speed, ``v_icp``), on every step that has one: measured independently of the wheels the
  replay drives;
* the start-state mismatch: the simulated body speed and yaw rate at the end of the warm-up
  (:mod:`simpick.simulate.steps`) minus the real speed and gyro yaw rate at the step's start.

A step whose engine failed the health check (diverged, flipped, wheels not tracking: the project's check,
:mod:`simpick.simulate.health`) is listed with its reason and left out of every mean, never averaged.

The verdict over these errors: :mod:`simpick.score.steps`.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from simpick.compare import realmetrics
from simpick.real.steps import MIN_TURN, pair_sd, similar_pairs

ERROR_COLUMNS = [
    "case",
    "engine",
    "session",
    "terrain_class",
    "step",
    "status",
    "reasons",
    "turning",
    "w_kin",
    "v_kin",
    "start_vx",
    "sim_start_vx",
    "start_dv",
    "start_wz",
    "sim_start_wz",
    "start_dwz",
    "yaw_rate_real",
    "yaw_rate_sim",
    "gain_real",
    "gain_sim",
    "gain_bias",
    "gain_error",
    "heading_real",
    "heading_sim",
    "heading_error",
    "v_real",
    "v_sim",
    "speed_bias",
    "speed_error",
    "wall_time",
    "sim_time",
]
SUMMARY_COLUMNS = [
    "engine",
    "terrain_class",
    "session",
    "steps",
    "failed",
    "failed_reasons",
    "turning_steps",
    "gain_real_median",
    "gain_sim_median",
    "gain_error_mean",
    "gain_error_low",
    "gain_error_high",
    "gain_floor_sd",
    "heading_error_mean",
    "heading_error_low",
    "heading_error_high",
    "speed_error_mean",
    "speed_error_low",
    "speed_error_high",
    "speed_floor_sd",
    "speed_bias_mean",
    "start_dv_median_abs",
    "start_dwz_median_abs",
    "wall_time_per_step",
]
ALL = "all"


def step_errors(cases: pd.DataFrame, steps: pd.DataFrame, replayed: pd.DataFrame, min_turn: float = MIN_TURN):
    """One row per replayed step and engine (``ERROR_COLUMNS``), from the cases table, the real step table
    (its kinematic twist) and the replay's step rows (:data:`simpick.simulate.steps.STEP_COLUMNS`)."""
    real = cases.merge(steps[["session", "step", "w_kin", "v_kin"]], on=["session", "step"], how="left")
    m = replayed.merge(real, on=["case", "session", "terrain_class", "step"], how="left", suffixes=("", "_real"))
    duration = m.steady_end - m.steady_start
    turning = m.w_kin.abs() > min_turn
    ok = m.status == "ok"
    gain_sim = (m.sim_yaw_rate / m.w_kin).where(turning)
    gain_real = (m.yaw_rate / m.w_kin).where(turning)
    out = pd.DataFrame(
        {
            "case": m.case,
            "engine": m.engine,
            "session": m.session,
            "terrain_class": m.terrain_class,
            "step": m.step,
            "status": m.status,
            "reasons": m.reasons.fillna(""),
            "turning": turning,
            "w_kin": m.w_kin,
            "v_kin": m.v_kin,
            "start_vx": m.start_vx,
            "sim_start_vx": m.sim_start_vx,
            "start_dv": m.sim_start_vx - m.start_vx,
            "start_wz": m.start_wz,
            "sim_start_wz": m.sim_start_wz,
            "start_dwz": m.sim_start_wz - m.start_wz,
            "yaw_rate_real": m.yaw_rate,
            "yaw_rate_sim": m.sim_yaw_rate,
            "gain_real": gain_real,
            "gain_sim": gain_sim,
            "gain_bias": (gain_sim - gain_real).where(ok),
            "gain_error": (gain_sim - gain_real).abs().where(ok),
            "heading_real": m.yaw_rate * duration,
            "heading_sim": m.sim_yaw_rate * duration,
            "heading_error": ((m.sim_yaw_rate - m.yaw_rate).abs() * duration).where(ok),
            "v_real": m.v_icp,
            "v_sim": m.sim_v,
            "speed_bias": (m.sim_v - m.v_icp).where(ok),
            "speed_error": (m.sim_v - m.v_icp).abs().where(ok),
            "wall_time": m.wall_time,
            "sim_time": m.sim_time,
        },
        columns=ERROR_COLUMNS,
    )
    return out.sort_values(["engine", "session", "step"], ignore_index=True)


def gain_repeatability(steps: pd.DataFrame, tolerance: float) -> tuple[float, int]:
    """(single-step standard deviation, pairs) of the real gain between steps of similar command, the pairs
    sought within each terrain class (:func:`simpick.real.steps.similar_pairs`) and pooled."""
    pairs = pd.concat(
        [similar_pairs(g, tolerance) for _, g in steps.groupby("terrain_class")]
        or [pd.DataFrame(columns=["difference"])],
        ignore_index=True,
    )
    return pair_sd(pairs), len(pairs)


def speed_repeatability(steps: pd.DataFrame, tolerance: float) -> float:
    """The real robot's step-to-step spread of the part of its lidar-ICP forward speed the wheels do not
    explain (ICP speed minus the kinematic speed of the measured wheels, m/s) between steps of similar command
    (both wheels' commands within ``tolerance`` rad/s, within each terrain class): the single-step standard
    deviation sqrt(mean(d^2) / 2) over the pairs, as :func:`gain_repeatability` for the gain. The residual,
    not the speed itself, since two similar commands still differ by up to ``tolerance`` at the rim."""
    moving = steps.assign(turning=True, gain=steps.v_icp - steps.v_kin)  # every step with an ICP speed
    moving = moving[moving.gain.notna()]
    pairs = [similar_pairs(g, tolerance) for _, g in moving.groupby("terrain_class")]
    return pair_sd(pd.concat(pairs, ignore_index=True)) if pairs else math.nan


def _ci(values, min_runs: int, level: float, seed: int) -> tuple[float, float, float]:
    mean, low, high, _ = realmetrics.mean_ci(np.asarray(values, float), None, min_runs, level, seed)
    return mean, low, high


def _summary_row(g: pd.DataFrame, real: pd.DataFrame, tolerance: float, min_runs: int, level: float, seed: int):
    ok = g[g.status == "ok"]
    failed = g[g.status != "ok"]
    turning = ok[ok.turning & ok.gain_error.notna()]
    row = {
        "steps": len(g),
        "failed": len(failed),
        "failed_reasons": "; ".join(f"{r.session}/{r.step:03d}: {r.reasons}" for r in failed.itertuples())[:2000],
        "turning_steps": len(turning),
        "gain_real_median": turning.gain_real.median(),
        "gain_sim_median": turning.gain_sim.median(),
        "gain_floor_sd": gain_repeatability(real, tolerance)[0],
        "speed_floor_sd": speed_repeatability(real, tolerance),
        "speed_bias_mean": ok.speed_bias.mean(),
        "start_dv_median_abs": ok.start_dv.abs().median(),
        "start_dwz_median_abs": ok.start_dwz.abs().median(),
        "wall_time_per_step": g.wall_time.mean(),
    }
    for metric, rows in (("gain_error", turning), ("heading_error", ok), ("speed_error", ok)):
        row[f"{metric}_mean"], row[f"{metric}_low"], row[f"{metric}_high"] = _ci(rows[metric], min_runs, level, seed)
    return row


def summary_table(
    errors: pd.DataFrame, steps: pd.DataFrame, tolerance: float, statistics: dict | None = None, seed: int = 0
) -> pd.DataFrame:
    """Per engine: per session, per terrain (session ``all``) and over everything (terrain ``all``): steps,
    failures (with their reasons), the gain's median (real and simulated), each error's mean over the
    healthy steps with its BCa interval (every step a unit), the real robot's repeatability (the floor),
    the start-state mismatch and the wall time per step."""
    min_runs, level = realmetrics.statistics_settings(statistics)
    rows = []
    for engine, e in errors.groupby("engine", sort=True):
        for terrain, t in e.groupby("terrain_class", sort=True):
            real_t = steps[steps.terrain_class == terrain]
            for session, s in t.groupby("session", sort=True):
                real_s = real_t[real_t.session == session]
                rows.append(
                    {
                        "engine": engine,
                        "terrain_class": terrain,
                        "session": session,
                        **_summary_row(s, real_s, tolerance, min_runs, level, seed),
                    }
                )
            rows.append(
                {
                    "engine": engine,
                    "terrain_class": terrain,
                    "session": ALL,
                    **_summary_row(t, real_t, tolerance, min_runs, level, seed),
                }
            )
        rows.append(
            {
                "engine": engine,
                "terrain_class": ALL,
                "session": ALL,
                **_summary_row(e, steps, tolerance, min_runs, level, seed),
            }
        )
    return pd.DataFrame(rows, columns=SUMMARY_COLUMNS)
