"""Open-loop wheel commands: the paper's differential controller (Farley et al. 2022, Eq. 1).

v_l = v - w * tau / 2,  v_r = v + w * tau / 2, with tau the effective track; wheel angular
speed = side speed / wheel radius. Every engine receives the same command array.
"""

from __future__ import annotations

import numpy as np


def side_speeds(v: float, w: float, track: float) -> tuple[float, float]:
    return v - w * track / 2, v + w * track / 2


def constant_commands(v: float, w: float, duration: float, timestep: float, track: float,
                      wheel_radius: float, robots: int = 1) -> np.ndarray:
    """(steps, robots, 4) wheel angular speeds, wheels ordered FL, FR, RL, RR."""
    steps = int(round(duration / timestep))
    left, right = side_speeds(v, w, track)
    per_robot = np.array([left, right, left, right]) / wheel_radius
    return np.broadcast_to(per_robot, (steps, robots, 4)).copy()
