"""The Warthog on flat ground, as both suspension test modules drive it (tests/test_suspension_a.py for
MuJoCo, PyBullet, ODE and PhysX, tests/test_suspension_b.py for DART, Drake, Newton and Genesis)."""

import numpy as np

from conftest import ROOT, flat_terrain
from simpick.engines.base import Scenario

WARTHOG = ROOT / "resources" / "robot" / "warthog.urdf"
DT = 0.001  # s
MU = 0.8  # the validation's ground friction
# N m per wheel: above the 153 N m a wheel needs while sliding fully (a quarter of 260 kg x 9.81 x mu 0.8 x r
# 0.3 m), so a spin's wheels track their command (at the study's default 100 N m DART's cannot: measured)
TORQUE = 500.0


def flat_scenario(robot) -> Scenario:
    """One robot at the origin on flat ground of friction MU, 1 kHz, TORQUE per wheel."""
    return Scenario(
        robot=robot,
        terrain=flat_terrain(MU),
        ground_friction=MU,
        timestep=DT,
        max_wheel_torque=TORQUE,
        starts=((0.0, 0.0, 0.0),),
    )


def hold(robot, left: float, right: float, seconds: float) -> np.ndarray:
    """(steps, 1 robot, wheels) joint speeds for rim speeds ``left`` and ``right``, m/s, held ``seconds``."""
    return np.broadcast_to(robot.joint_speeds(left, right), (round(seconds / DT), 1, robot.wheel_count)).copy()
