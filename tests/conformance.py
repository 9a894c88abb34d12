"""The one conformance check every registered engine adapter passes: what the runner
(simpick.engines.runner) relies on of an adapter's primitives. tests/test_engines.py imports
:func:`check_adapter` and runs it on every engine of the registry; a new engine passes it before
anything else of the suite means anything.
"""

from __future__ import annotations

import numpy as np

from simpick.engines import get_engine
from simpick.engines.base import BaseState, BaseStates, PhysicsRecord, Scenario, World
from simpick.engines.runner import Adapter
from simpick.inputs.robot import RobotSpec
from simpick.inputs.terrain import Terrain

DT = 0.001
# m: how far base_link may rest from the loader's resting height (RobotSpec.base_height) after the
# spawn drop: the compliant contacts sag (MuJoCo 1.5 mm, Drake 0.5 mm, PyBullet 0.14 mm)
REST_TOLERANCE = 0.004


def check_adapter(name: str, robot: RobotSpec) -> None:
    """Build, set targets, step and read ``name``'s world directly; then run it through the runner:
    shapes, a record at rest at the robot's resting height, and the same record twice."""
    adapter = get_engine(name)
    assert isinstance(adapter, Adapter), f"{name}: an engine adapter subclasses simpick.engines.runner.Adapter"
    scenario = Scenario(
        robot=robot,
        terrain=Terrain.flat(0.8),
        ground_friction=0.8,
        timestep=DT,
        max_wheel_torque=100.0,
        starts=((0.0, 0.0, 0.0), (3.0, 0.0, 0.0)),
    )
    wheels = len(robot.wheel_joints)

    # the primitives, as the runner calls them
    world = adapter.build(scenario)
    try:
        assert isinstance(world, World), f"{name}: build() must return a World (set_wheel_targets, step, read)"
        world.set_wheel_targets(np.zeros((2, wheels)))
        samples = []
        for _ in range(3):
            world.step()
            samples.append(world.read())
        world.step(5)
        samples.append(world.read())
        states = world.states(samples) if hasattr(world, "states") else BaseStates.stacked(samples)
        assert isinstance(states, BaseStates)
        if not hasattr(world, "states"):
            assert all(isinstance(s, BaseState) for s in samples)
        # a world that logs its own state returns every step, else one row per read
        rows = 8 if getattr(world, "logs_states", False) else 4
        for field, width in (
            ("position", 3),
            ("quaternion", 4),
            ("linear_velocity", 3),
            ("angular_velocity", 3),
            ("wheel_speed", wheels),
        ):
            value = getattr(states, field)
            assert value.shape == (rows, width), (name, field, value.shape)
            assert np.isfinite(value).all(), (name, field)
        assert np.allclose(np.linalg.norm(states.quaternion, axis=1), 1.0, atol=1e-9), name
    finally:
        close = getattr(world, "close", None)
        if close is not None:
            close()

    # through the runner: 0.6 s parked, then 0.4 s driving forward (a command change)
    commands = np.zeros((1000, 2, wheels))
    commands[600:] = robot.joint_speeds(0.3, 0.3)
    record = adapter.simulate(scenario, commands)
    assert isinstance(record, PhysicsRecord) and record.steps == 1000
    np.testing.assert_array_equal(record.time, DT * np.arange(1, 1001))
    for field, width in (
        ("position", 3),
        ("quaternion", 4),
        ("linear_velocity", 3),
        ("angular_velocity", 3),
        ("wheel_speed", wheels),
        ("imu_specific_force", 3),
        ("imu_gyro", 3),
    ):
        value = getattr(record, field)
        assert value.shape == (1000, width), (name, field, value.shape)
        assert np.isfinite(value).all(), (name, field)
    assert record.wall_time > 0 and record.cpu_time >= 0
    # at rest on its wheels at the loader's resting height, reading +g on z
    z = record.position[550:600, 2]
    assert np.abs(z - robot.base_height).max() < REST_TOLERANCE, (name, z.min(), z.max(), robot.base_height)
    assert abs(record.imu_specific_force[550:600, 2].mean() - 9.81) < 0.05, name
    # then driving forward: the wheels follow the command's sign
    assert (np.sign(record.wheel_speed[-1]) == np.sign(commands[-1, 0])).all(), (name, record.wheel_speed[-1])
    assert record.position[-1, 0] > record.position[600, 0] + 0.02, name
    # deterministic: the same scenario and commands give the same record, bit for bit
    again = adapter.simulate(scenario, commands)
    for field in ("position", "quaternion", "linear_velocity", "angular_velocity", "wheel_speed", "imu_specific_force"):
        np.testing.assert_array_equal(getattr(record, field), getattr(again, field), err_msg=f"{name} {field}")
    # the bare loop steps the same world and returns its wall time
    assert adapter.bare_loop(scenario, commands[:200]) > 0
