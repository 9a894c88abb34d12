"""How a DRIVE session's arrays are laid out, read and checked: the per-sample series (a row per 2 s
window, a column ``name_i`` per sample at 20 Hz), the window flags that mark each step (one transient
window, then its steady ones), and the accelerometer's units and axes.

It stands apart because every later stage (the ICP rates, the tables, the quirks) indexes the arrays by
this :class:`Layout`, and because this is where a pickle of another shape is refused, before anything
is measured from it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.errors import InputError
from simpick.real.logs.drive_signals import DT, column_of, series_of

SERIES = {  # per-sample columns read (DRIVE name -> name here); rad/s, m/s^2, m, rad
    "cmd_left": "cmd_left",
    "cmd_right": "cmd_right",
    "left_wheel_vel": "wheel_left",
    "right_wheel_vel": "wheel_right",
    "imu_acceleration_x": "ax",
    "imu_acceleration_y": "ay",
    "imu_acceleration_z": "az",
    "imu_yaw": "wz",
    "icp_x": "icp_x",
    "icp_y": "icp_y",
    "icp_yaw": "icp_yaw",
    "icp_vel_x": "vx_icp_drive",
    "icp_vel_y": "vy_icp_drive",
}
MASKS = ("transitory_state_mask", "steady_state_mask")
ACCEL_OK = (7.0, 13.0)  # m/s^2: the norm of the mean specific force (gravity; simpick.real.logs.validate's limits)


@dataclass(frozen=True)
class Layout:
    """A session's shape: windows of ``n`` samples, steps of ``per_step`` windows (one transient window,
    then steady ones), ``n_steps`` steps."""

    n: int
    per_step: int
    n_steps: int

    @property
    def window_s(self) -> float:
        return self.n * DT

    @property
    def steady(self) -> slice:
        """A step's steady samples, in a row of :meth:`by_step`."""
        return slice(self.n, self.per_step * self.n)

    def by_step(self, a: np.ndarray) -> np.ndarray:  # (rows, n) -> (steps, per_step * n)
        return a.reshape(self.n_steps, self.per_step * self.n)

    def windows(self, a: np.ndarray) -> np.ndarray:  # (rows,) -> (steps, per_step)
        return a.reshape(self.n_steps, self.per_step)


def read_arrays(frame: pd.DataFrame, path: Path) -> tuple[dict, dict, int]:
    """The per-sample series (DRIVE's names, (rows, n) each), the window flags, and n, the samples of a window."""
    n = sum(1 for c in frame.columns if re.fullmatch(r"cmd_left_\d+", str(c)))
    if n < 2:
        raise InputError(
            f"{path}: column 'cmd_left_0'",
            "missing (no per-sample cmd_left_i columns)",
            "use the pickle DRIVE's parser wrote",
        )
    raw = {base: series_of(frame, base, n, path) for base in SERIES}
    masks = {m: column_of(frame, m, path) for m in MASKS}
    return raw, masks, n


def step_layout(masks: dict, rows: int, n: int, geometry: dict, path: Path) -> Layout:
    """The steps the window flags mark, checked: each one transient window and the same number of steady
    windows, as long as the session's DRIVE configuration says."""
    trans, steady = masks["transitory_state_mask"], masks["steady_state_mask"]
    if (
        rows == 0
        or not np.isin(trans, (0, 1)).all()
        or not np.isin(steady, (0, 1)).all()
        or (trans + steady != 1).any()
    ):
        raise InputError(
            f"{path}: columns {list(MASKS)}",
            "must be 0/1 flags, exactly one set per row",
            "use the pickle DRIVE's parser wrote",
        )
    starts = np.flatnonzero(trans == 1)
    if len(starts) == 0 or starts[0] != 0:
        raise InputError(
            f"{path}: column 'transitory_state_mask'",
            "row 0 does not start a step (flag 1)",
            "use the pickle DRIVE's parser wrote, uncut",
        )
    lengths = np.diff(np.append(starts, rows))
    if len(set(lengths.tolist())) != 1 or lengths[0] < 2:
        bad = int(starts[np.flatnonzero(lengths != np.bincount(lengths).argmax())[0]]) if len(set(lengths)) > 1 else 0
        raise InputError(
            f"{path}: column 'transitory_state_mask'",
            f"steps must all be one transient window and the same number of steady windows; the step "
            f"at row {bad} differs ({rows} rows)",
            "drop incomplete steps (whole steps of rows)",
        )
    layout = Layout(n=n, per_step=int(lengths[0]), n_steps=rows // int(lengths[0]))
    per_step, window_s = layout.per_step, layout.window_s
    if geometry.get("step_len") is not None and abs(geometry["step_len"] - per_step * window_s) > 1e-6:
        raise InputError(
            f"{path}: column 'transitory_state_mask'",
            f"steps of {per_step} windows of {window_s:g} s, but the session's DRIVE configuration "
            f"({geometry['source']}) says step_len {geometry['step_len']:g} s",
            "use the pickle and the configuration of the same session",
        )
    return layout


def check_gravity(raw: dict, path: Path) -> None:
    """The mean specific force must be gravity along +z (m/s^2): the accelerometer's units and axes."""
    force = np.array([raw[f"imu_acceleration_{a}"].mean() for a in "xyz"])
    norm = float(np.linalg.norm(force))
    if not ACCEL_OK[0] <= norm <= ACCEL_OK[1] or force[2] < 0.5 * norm:
        raise InputError(
            f"{path}: columns imu_acceleration_*",
            f"mean specific force ({force[0]:.2f}, {force[1]:.2f}, {force[2]:.2f}) m/s^2: not gravity "
            f"along +z (norm {ACCEL_OK[0]:g}-{ACCEL_OK[1]:g} m/s^2 expected, as in DRIVE's own files)",
            "use the pickle DRIVE's parser wrote (m/s^2, z up, gravity included)",
        )
