"""The ICP's speed and yaw rate per window of a DRIVE session: the poses unwrapped, the rates measured
between pose updates (:mod:`simpick.real.logs.drive_signals`), the steady windows whose ICP motion runs
against the wheels left out, and the poses composed into each step's start frame.

It stands apart because the ICP is the one measurement of the ground's speed DRIVE gives, and the
reader's main judgement (which windows' motion to trust) is made here, once, for the tables, the gyro's
sign and the quirks to read.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from simpick.real.logs.drive_layout import Layout
from simpick.real.logs.drive_signals import compose_windows, reversed_windows, update_rates


@dataclass(frozen=True)
class Icp:
    """Per window, the ICP's body velocity and yaw rate between pose updates (a reversed steady window's
    velocity NaN), which windows were reversed, and the poses composed into each step's start frame."""

    vx: np.ndarray
    vy: np.ndarray
    wz: np.ndarray
    reversed: np.ndarray
    x: np.ndarray
    y: np.ndarray
    yaw: np.ndarray


def icp_rates(raw: dict, steady: np.ndarray, geometry: dict, layout: Layout) -> Icp:
    """The ICP poses unwrapped, their update-to-update rates per window (reversed steady windows left
    out) and the poses composed per step."""
    yaw_u = np.unwrap(raw["icp_yaw"], axis=1)
    vx_w, vy_w, wz_w = update_rates(raw["icp_x"], raw["icp_y"], yaw_u)
    reversed_w = (steady == 1) & reversed_windows(
        vx_w, raw["left_wheel_vel"], raw["right_wheel_vel"], geometry["wheel_radius"]
    )  # a transient window may end moving against its wheels' mean: the robot reversing within it
    vx_w, vy_w = np.where(reversed_w, np.nan, vx_w), np.where(reversed_w, np.nan, vy_w)
    X, Y, Yaw = compose_windows(raw["icp_x"], raw["icp_y"], yaw_u, layout.per_step)
    return Icp(vx=vx_w, vy=vy_w, wz=wz_w, reversed=reversed_w, x=X, y=Y, yaw=Yaw)
