"""Open-loop wheel commands: the paper's differential controller (Farley et al. 2022, Eq. 1).

v_l = v - w * tau / 2,  v_r = v + w * tau / 2, with tau the effective track; wheel angular
speed = side speed / wheel radius. Every engine receives the same command array.
"""

from __future__ import annotations

import math

import numpy as np


def side_speeds(v: float, w: float, track: float) -> tuple[float, float]:
    return v - w * track / 2, v + w * track / 2


def constant_commands(
    v: float, w: float, duration: float, timestep: float, track: float, wheel_radius, robots: int = 1
) -> np.ndarray:
    """(steps, robots, driven wheels) joint speeds. ``wheel_radius``: a
    :class:`simpick.inputs.robot.RobotSpec` (its driven wheels, sides and axis signs), or a radius for
    the Husky's four wheels ordered FL, FR, RL, RR."""
    steps = int(round(duration / timestep))
    left, right = side_speeds(v, w, track)
    if hasattr(wheel_radius, "joint_speeds"):
        per_robot = wheel_radius.joint_speeds(left, right)
    else:
        per_robot = np.array([left, right, left, right]) / wheel_radius
    return np.broadcast_to(per_robot, (steps, robots, len(per_robot))).copy()


def arc_start_over_strip(
    v: float, w: float, gain: float, lowest: tuple[float, float], start_x: float
) -> tuple[float, float, float]:
    """Start pose (x, y, yaw) of a left-turning open-loop circle whose *driven* arc passes
    lowest (heading +x) through ``lowest`` = (x, y), entering from ``start_x``.

    The paper's controller is open loop (Eq. 1 from (v, w); no pose feedback), and a skid-steer
    robot turns at ``gain`` x w, so it drives a circle of radius v / (gain w), not v / w. Placing
    that arc, not the commanded one, over the strip is what makes the circle test cross terrain.
    """
    radius = v / (gain * w)
    x_low, y_low = lowest
    sin_phi = (x_low - start_x) / radius
    if not -1.0 <= sin_phi <= 1.0:
        raise ValueError(f"the driven arc (radius {radius:.2f} m) cannot reach x = {x_low} from x = {start_x}")
    phi = math.asin(sin_phi)
    return (start_x, y_low + radius * (1 - math.cos(phi)), -phi)
