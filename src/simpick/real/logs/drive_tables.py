"""A DRIVE session's two tables: ``samples`` (one row per 20 Hz sample) and ``steps`` (one row per step:
the command, the steady means, the state at the step's start).

They stand apart as the reader's output form: what the step units downstream read, column by column,
built from the arrays, the ICP rates and the gyro with its sign fixed, and nothing else.
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd

from simpick.real.logs.drive_icp import Icp
from simpick.real.logs.drive_layout import SERIES, Layout
from simpick.real.logs.drive_signals import DT, held_longest

START_SECONDS = 0.5  # s at the end of the previous step averaged for a step's start state
SAMPLE_COLUMNS = [
    "step",
    "window",
    "sample",
    "time",
    "t_step",
    "steady",
    "cmd_left",
    "cmd_right",
    "wheel_left",
    "wheel_right",
    "ax",
    "ay",
    "az",
    "wz",
    "x_icp",
    "y_icp",
    "yaw_icp",
    "vx_icp_drive",
    "vy_icp_drive",
]
STEP_COLUMNS = [
    "step",
    "t_start",
    "steady_start",
    "t_end",
    "cmd_left",
    "cmd_right",
    "cmd_early_samples",
    "wheel_left",
    "wheel_right",
    "wz_gyro",
    "wz_icp",
    "vx_icp",
    "vy_icp",
    "icp_reversed",
    "vx_icp_drive",
    "heading_icp",
    "heading_gyro",
    "start_from",
    "start_vx",
    "start_vy",
    "start_wz",
    "start_wheel_left",
    "start_wheel_right",
]


def sample_table(raw: dict, icp: Icp, wz: np.ndarray, layout: Layout) -> pd.DataFrame:
    """One row per 20 Hz sample (:data:`SAMPLE_COLUMNS`); ``wz`` the gyro with its sign fixed, by step."""
    n, per_step, by_step = layout.n, layout.per_step, layout.by_step
    sample = np.tile(np.arange(per_step * n), layout.n_steps)
    step = np.repeat(np.arange(layout.n_steps), per_step * n)
    t_step = sample * DT
    return pd.DataFrame(
        {
            "step": step,
            "window": sample // n,
            "sample": sample,
            "time": step * per_step * layout.window_s + t_step,
            "t_step": t_step,
            "steady": sample >= n,
            **{
                SERIES[b]: by_step(raw[b]).ravel()
                for b in (
                    "cmd_left",
                    "cmd_right",
                    "left_wheel_vel",
                    "right_wheel_vel",
                    "imu_acceleration_x",
                    "imu_acceleration_y",
                    "imu_acceleration_z",
                )
            },
            "wz": wz.ravel(),
            "x_icp": by_step(icp.x).ravel(),
            "y_icp": by_step(icp.y).ravel(),
            "yaw_icp": by_step(icp.yaw).ravel(),
            "vx_icp_drive": by_step(raw["icp_vel_x"]).ravel(),
            "vy_icp_drive": by_step(raw["icp_vel_y"]).ravel(),
        },
        columns=SAMPLE_COLUMNS,
    )


def step_table(raw: dict, icp: Icp, wz: np.ndarray, wz_icp: np.ndarray, layout: Layout) -> pd.DataFrame:
    """One row per step (:data:`STEP_COLUMNS`): the command, the steady means, the start state; ``wz``
    the gyro with its sign fixed, by step, ``wz_icp`` the steps' steady ICP yaw rate."""
    n_steps, per_step, window_s, steady_slice = layout.n_steps, layout.per_step, layout.window_s, layout.steady
    cl, cr = layout.by_step(raw["cmd_left"]), layout.by_step(raw["cmd_right"])
    wl, wr = layout.by_step(raw["left_wheel_vel"]), layout.by_step(raw["right_wheel_vel"])
    cmd_l, cmd_r = held_longest(cl[:, steady_slice]), held_longest(cr[:, steady_slice])
    early = ((cl[:, steady_slice] != cmd_l[:, None]) | (cr[:, steady_slice] != cmd_r[:, None])).sum(axis=1)
    with warnings.catch_warnings():  # a step whose every steady window is unusable has no ICP speed (NaN)
        warnings.simplefilter("ignore", RuntimeWarning)
        vx_s = np.nanmean(layout.windows(icp.vx)[:, 1:], axis=1)
        vy_s = np.nanmean(layout.windows(icp.vy)[:, 1:], axis=1)
    reversed_s = layout.windows(icp.reversed)[:, 1:].sum(axis=1)
    last = max(1, round(START_SECONDS / DT))
    vx_w, vy_w = layout.windows(icp.vx), layout.windows(icp.vy)
    start = {  # the previous step's last START_SECONDS (steady: its command held 4 s), or step 0's own start
        "vx": np.r_[vx_w[0, 0], vx_w[:-1, -1]],
        "vy": np.r_[vy_w[0, 0], vy_w[:-1, -1]],
        "wz": np.r_[wz[0, :last].mean(), wz[:-1, -last:].mean(axis=1)],
        "wl": np.r_[wl[0, :last].mean(), wl[:-1, -last:].mean(axis=1)],
        "wr": np.r_[wr[0, :last].mean(), wr[:-1, -last:].mean(axis=1)],
    }
    return pd.DataFrame(
        {
            "step": np.arange(n_steps),
            "t_start": np.arange(n_steps) * per_step * window_s,
            "steady_start": np.full(n_steps, window_s),
            "t_end": np.full(n_steps, per_step * window_s),
            "cmd_left": cmd_l,
            "cmd_right": cmd_r,
            "cmd_early_samples": early,
            "wheel_left": wl[:, steady_slice].mean(axis=1),
            "wheel_right": wr[:, steady_slice].mean(axis=1),
            "wz_gyro": wz[:, steady_slice].mean(axis=1),
            "wz_icp": wz_icp,
            "vx_icp": vx_s,
            "vy_icp": vy_s,
            "icp_reversed": reversed_s,
            "vx_icp_drive": layout.by_step(raw["icp_vel_x"])[:, steady_slice].mean(axis=1),
            "heading_icp": np.nansum(layout.windows(icp.wz)[:, 1:], axis=1) * window_s,
            "heading_gyro": wz[:, steady_slice].sum(axis=1) * DT,
            "start_from": ["own first window (no previous step)"] + ["previous step's end"] * (n_steps - 1),
            "start_vx": start["vx"],
            "start_vy": start["vy"],
            "start_wz": start["wz"],
            "start_wheel_left": start["wl"],
            "start_wheel_right": start["wr"],
        },
        columns=STEP_COLUMNS,
    )
