"""DART adapter specifics beyond the conformance suite: friction reaches the contact from
the terrain, the wheel servo respects its torque bound, robots collide with each other,
settings are checked."""

import dataclasses

import numpy as np
import pytest

from conftest import drive, flat_terrain, tile_terrain
from simpick.errors import InputError

dart_engine = pytest.importorskip("simpick.engines.dart_engine")
pytest.importorskip("dartpy")

DT = 0.001


def simulate(robot, **kwargs):
    return drive("dart", robot, **kwargs)


def forward_speed(record, t: float) -> float:
    return float(np.linalg.norm(record.linear_velocity[int(t / DT) - 1, :2]))


def test_terrain_friction_not_the_robot_s_decides_the_contact(robot):
    raised = dataclasses.replace(robot, base_height=robot.base_height + 0.01)  # spawn on the tile
    slippery = simulate(raised, terrain=tile_terrain(0.1), ground=0.95)
    grippy = simulate(raised, terrain=tile_terrain(0.95), ground=0.1)
    # traction limited to mu g: 0.1 x 9.81 m/s^2 for 0.25 s is 0.25 m/s at most
    assert forward_speed(slippery, 0.25) < 0.3
    assert forward_speed(grippy, 0.25) > 0.45


def test_ground_friction_is_the_scenario_s(robot):
    assert forward_speed(simulate(robot, terrain=flat_terrain(0.95), ground=0.1), 0.25) < 0.3


def test_wheel_torque_bound_limits_the_acceleration(robot):
    record = simulate(robot, terrain=flat_terrain(0.95), torque=1.0, duration=0.5)
    # 4 wheels x 1 N m / 0.1651 m on about 57 kg: 0.43 m/s^2 at most, so 0.21 m/s after 0.5 s
    assert forward_speed(record, 0.5) < 0.25
    assert record.wheel_speed[-1].mean() < 0.5 / robot.wheel_radius


def test_robots_collide_with_each_other(robot):
    record_a = simulate(robot, terrain=flat_terrain(0.95), starts=((0.0, 0.0, 0.0), (1.6, 0.0, np.pi)), duration=2.5)
    # robot 0 drives +x into robot 1 coming the other way; chassis are 0.99 m long, so their
    # centres cannot come closer than that while they push against each other
    assert record_a.position[:, 0].max() < 1.6 / 2 - 0.3


def test_unknown_setting_and_detector_are_refused(robot):
    with pytest.raises(InputError, match=r"engines\.dart: unknown setting\(s\) \['solver'\]"):
        simulate(robot, terrain=flat_terrain(), settings={"solver": "x"})
    with pytest.raises(InputError, match=r"engines\.dart\.collision_detector: .*'fcl'.*\(got 'havok'\)"):
        simulate(robot, terrain=flat_terrain(), settings={"collision_detector": "havok"})


@pytest.mark.parametrize("detector", dart_engine.DETECTORS)
def test_every_detector_rests_the_robot_at_its_height(robot, detector):
    record = simulate(
        robot,
        terrain=flat_terrain(),
        v=0.0,
        duration=0.5,
        settings={"collision_detector": detector, "lcp_solver": "dantzig"},
    )
    assert abs(record.position[-1, 2] - robot.base_height) < 0.001


def test_version_is_dartpy_s():
    assert dart_engine.DartEngine().version().startswith("6.")
