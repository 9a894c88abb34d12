"""Each failure mode of a simulation is provoked and must be caught with its reason."""

import numpy as np
import pytest

from conftest import setup, study_config
from simpick.engines import get_engine
from simpick.engines.base import PhysicsRecord
from simpick.simulate.health import HealthLimits, check

LIMITS = HealthLimits()
N, DT = 3000, 0.001


def resting() -> PhysicsRecord:
    """A healthy robot standing still for 3 s."""
    z = np.zeros((N, 3))
    return PhysicsRecord(
        time=DT * np.arange(1, N + 1),
        position=np.tile([0, 0, 0.132], (N, 1)),
        quaternion=np.tile([1.0, 0, 0, 0], (N, 1)),
        linear_velocity=z.copy(),
        angular_velocity=z.copy(),
        wheel_speed=np.zeros((N, 4)),
        imu_specific_force=np.tile([0, 0, 9.81], (N, 1)),
        imu_gyro=z.copy(),
        wall_time=0.1,
        cpu_time=0.1,
        steps=N,
    )


def reasons(record, commands=None):
    health = check(record, LIMITS, np.zeros((N, 4)) if commands is None else commands)
    return health.ok, " | ".join(health.reasons)


def test_a_resting_robot_is_healthy():
    assert reasons(resting()) == (True, "")


def test_non_finite_state_is_divergence():
    record = resting()
    record.linear_velocity[1500:] = np.nan
    ok, why = reasons(record)
    assert not ok and "non-finite linear velocity from t = 1.501 s" in why


def test_falling_through_the_ground():
    record = resting()
    record.position[2000:, 2] = np.linspace(0.1, -1.0, 1000)
    ok, why = reasons(record)
    assert not ok and "fell through the ground" in why


def test_flipped():
    record = resting()
    angle = np.pi / 2  # rolled onto its side
    record.quaternion[2500:] = [np.cos(angle / 2), np.sin(angle / 2), 0, 0]
    ok, why = reasons(record)
    assert not ok and "flipped: roll/pitch 90 deg" in why


def test_exploded_speed():
    record = resting()
    record.linear_velocity[:, 0] = np.linspace(0, 50, N)
    ok, why = reasons(record)
    assert not ok and "exploded" in why


def test_jump_in_velocity():
    record = resting()
    record.linear_velocity[1200:, 2] = 1.0
    ok, why = reasons(record)
    assert not ok and "jump: base velocity changed by 1.00 m/s within one step at t = 1.201 s" in why


def test_sliding_while_parked():
    record = resting()
    record.linear_velocity[1000:, 0] = 0.2
    ok, why = reasons(record)
    assert not ok and "slides while commanded to stand still" in why


def test_wheels_not_tracking():
    record = resting()
    commands = np.full((N, 4), 3.0)
    record.linear_velocity[:, 0] = 0.0
    ok, why = reasons(record, commands)
    assert not ok and "wheels do not track their command" in why


def teleoperated(seed: int = 0, steps: int = N, rate: float = 50.0) -> np.ndarray:
    """(steps, 4) wheel speeds of a teleoperated 50 Hz log held at 1 kHz: a new level of v and w every
    0.3 s (up to 1 m/s and 1 rad/s) and joystick noise on every sample."""
    rng = np.random.default_rng(seed)
    samples = int(steps * DT * rate) + 1
    levels = rng.choice([-1.0, -0.5, 0.0, 0.5, 1.0], size=(samples // 15 + 1, 2))
    v, w = (np.repeat(levels, 15, axis=0)[:samples] + 0.05 * rng.standard_normal((samples, 2))).T
    held = (DT * np.arange(steps) * rate).astype(int)
    left, right = (v - w * 0.555 / 2) / 0.165, (v + w * 0.555 / 2) / 0.165
    return np.stack([left, right, left, right], axis=1)[held]


def lagging(commands: np.ndarray, tau: float) -> np.ndarray:
    """The speeds of a first-order servo with time constant ``tau`` (s) following ``commands`` from rest."""
    speed, out, a = np.zeros(commands.shape[1]), np.empty_like(commands), DT / tau
    for k, command in enumerate(commands):
        speed = speed + a * (command - speed)
        out[k] = speed
    return out


def test_a_servo_lagging_at_command_changes_tracks():
    # a servo of time constant 0.03 s (settled a tenth of a second after each change) on a 50 Hz
    # command: its plain error averages above the limit over a second (MuJoCo's did on such logs),
    # but it lags no more than the check allows
    commands = teleoperated()
    record = resting()
    record.wheel_speed[:] = lagging(commands, tau=0.03)
    plain = np.convolve(np.abs(record.wheel_speed - commands).mean(axis=1), np.ones(1000) / 1000, mode="same")
    assert plain.max() > LIMITS.wheel_tracking  # the case the check used to fail
    health = check(record, LIMITS, commands)
    assert health.ok, health.reasons
    # with no lag allowed the same servo is judged a tracking failure
    strict = check(record, HealthLimits(wheel_lag=0.0), commands)
    assert not strict.ok and "wheels do not track" in " ".join(strict.reasons)


def test_a_stuck_wheel_fails_whatever_its_commands_do():
    for commands in (np.full((N, 4), 3.0), teleoperated(seed=1)):
        record = resting()
        record.wheel_speed[:] = lagging(commands, tau=0.03)
        record.wheel_speed[:, 0] = 0.0  # the front left wheel held
        record.wheel_speed[:, 2] = 0.0  # and the rear left
        ok, why = reasons(record, commands)
        assert not ok and "wheels do not track their command" in why


def test_a_wheel_too_slow_for_its_commands_fails():
    # a servo ten times slower than the lag allowed: it never reaches a level before the next
    commands = teleoperated(seed=2)
    record = resting()
    record.wheel_speed[:] = lagging(commands, tau=10 * LIMITS.wheel_lag)
    ok, why = reasons(record, commands)
    assert not ok and "wheels do not track their command" in why


@pytest.mark.parametrize("engine", ["pybullet", "mujoco"])
def test_a_torque_bound_far_too_low_is_caught_in_a_real_engine(engine, robot):
    scenario, commands = setup(robot, torque=0.05, duration=2.0)
    record = get_engine(engine).simulate(scenario, commands)
    health = check(record, LIMITS, commands[:, 0])
    assert not health.ok and "wheels do not track" in " ".join(health.reasons)


@pytest.mark.parametrize("engine", ["pybullet"])
def test_a_robot_spawned_inside_a_box_is_caught(engine, robot):
    # A 20 cm block where the robot stands: Bullet's rigid contacts eject the robot in one
    # step, a jump the check must catch. MuJoCo's soft contacts push it out over many steps
    # without any jump, which is a legitimate resolution rather than a failure to report.
    block = {
        "schema": "simpick.inputs.terrain/1",
        "name": "block",
        "friction": 0.9,
        "spheres": [],
        "boxes": [[0.0, 0.0, 0.1, 0.0, 0.6, 0.4, 0.2]],
    }
    scenario, commands = setup(robot, terrain=block, torque=100.0, v=0.0, duration=1.0)
    record = get_engine(engine).simulate(scenario, commands)
    health = check(record, LIMITS, commands[:, 0])
    assert not health.ok, "an interpenetrating start must not pass as healthy"


def mujoco_settings() -> dict:

    return study_config()["engines"]["mujoco"]


def test_mujoco_lagging_at_frequent_command_changes_is_healthy_and_a_starved_one_is_not(robot):
    # MuJoCo's wheel servo settles about a quarter second after a step to 1 m/s (the slowest of the
    # engines measured): the plain error over a 50 Hz teleoperated log averaged 0.7-0.95 rad/s over a
    # second, and the runs were failed as stuck
    commands = teleoperated(seed=0, steps=6000)
    engine = get_engine("mujoco")
    scenario, _ = setup(robot, ground=0.8, torque=100.0, settings=mujoco_settings())
    record = engine.simulate(scenario, commands[:, None, :])
    health = check(record, LIMITS, commands)
    assert health.ok, health.reasons
    # a torque bound too low for these commands (the wheels follow no level) still fails
    scenario, _ = setup(robot, ground=0.8, torque=5.0, settings=mujoco_settings())
    health = check(engine.simulate(scenario, commands[:, None, :]), LIMITS, commands)
    assert not health.ok and "wheels do not track" in " ".join(health.reasons)


def test_the_healthy_default_engines_pass_on_flat_ground(robot):
    for engine in ("pybullet", "mujoco"):
        scenario, commands = setup(robot, torque=100.0, w=0.5, duration=3.0)
        health = check(get_engine(engine).simulate(scenario, commands), LIMITS, commands[:, 0])
        assert health.ok, (engine, health.reasons)


def test_the_lag_gives_lfilters_floats_bit_for_bit():
    """The servo band's lag is computed without scipy.signal (its import costs each job 0.6 s of CPU): it must give
    the very floats lfilter gives, so a trace's health record stays what it was."""
    from scipy.signal import lfilter

    from simpick.simulate.health import first_order_lag

    rng = np.random.default_rng(3)
    held = np.repeat(rng.normal(scale=10.0, size=(60, 2)), 150, axis=0)  # a replay: commands held 0.15 s
    arrays = [
        np.column_stack([held, held]),  # the Husky: each side's two wheels on one command
        rng.normal(size=(2000, 4)),
        np.array([[0.0, -0.0, 1e-300], [1e300, -2.5, 0.0], [np.inf, 3.0, -0.0]]),
        np.zeros((1, 2)),
    ]
    for dt, lag in ((0.001, 0.05), (0.004, 0.05), (0.0005, 0.2)):
        a = -np.expm1(-dt / lag)
        for commands in arrays:
            expected = lfilter([a], [1.0, a - 1.0], commands, axis=0)
            assert first_order_lag(commands, a).view(np.uint64).tolist() == expected.view(np.uint64).tolist()


def test_the_health_check_does_not_import_scipy_signal():
    import os
    import subprocess
    import sys
    from pathlib import Path

    import simpick

    code = (
        "import sys, numpy as np\n"
        "from simpick.simulate.health import following_error\n"
        "following_error(np.zeros((10, 4)), np.ones((10, 4)), 0.001, 0.05)\n"
        "assert 'scipy.signal' not in sys.modules, 'scipy.signal imported'\n"
    )
    # the simpick this test imports, whichever is installed
    src = str(Path(simpick.__file__).resolve().parents[1])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([src, os.environ.get("PYTHONPATH", "")])}
    subprocess.run([sys.executable, "-c", code], check=True, env=env)
