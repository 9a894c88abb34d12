"""Passive suspension in MuJoCo, PyBullet, ODE and PhysX: the Warthog's two rockers, limited, damped,
with joint friction, and coupled by its differential (the right rocker turns by minus the left).

What would fail if the coupling were missing, applied twice or with the wrong sign: at rest the
chassis stays level (a), without the coupling it tips onto a rocker stop (b), an offset in the
coupling pitches it by half the offset (c), the engine's rocker angles keep the coupling (d), and
the robot drives and spins without diverging, turning the commanded way (e)."""

import dataclasses
import math

import numpy as np
import pytest

from simpick.engines import get_engine
from simpick.engines.kinematics import euler_rpy
from simpick.inputs.robot import load_robot
from suspension import DT, WARTHOG, flat_scenario, hold

ENGINES = ["mujoco", "pybullet", "ode", "physx"]
STOP = 0.15  # rad, the Warthog's rocker limits


@pytest.fixture(scope="module")
def warthog():
    return load_robot(WARTHOG)


def _pitch_deg(record) -> np.ndarray:
    return np.degrees(euler_rpy(record.quaternion)[:, 1])


def _rocker_angles(engine: str, world, robot) -> list[float]:
    """The recorded robot's suspension joint angles from the engine's own state, RobotSpec order."""
    names = [s.joint for s in robot.suspension]
    if engine == "mujoco":
        return [float(world.data.joint(f"r0/{n}").qpos[0]) for n in names]
    if engine == "pybullet":
        pb, cid, body = world.pb, world.cid, world.body0
        index = {
            pb.getJointInfo(body, j, physicsClientId=cid)[1].decode(): j
            for j in range(pb.getNumJoints(body, physicsClientId=cid))
        }
        return [pb.getJointState(body, index[n], physicsClientId=cid)[0] for n in names]
    if engine == "ode":
        return world.suspension_angles()
    order = [j.name for j in world.art.active_joints]  # physx
    return [float(world.art.qpos[order.index(n)]) for n in names]


@pytest.mark.parametrize("engine", ENGINES)
def test_the_coupled_warthog_rests_level_at_its_height(engine, warthog):
    record = get_engine(engine).simulate(flat_scenario(warthog), hold(warthog, 0.0, 0.0, 2.0))
    pitch = _pitch_deg(record)
    print(f"{engine}: rest pitch {pitch[-1]:+.4f} deg, height {record.position[-1, 2]:.4f} m")
    assert abs(pitch[-1]) < 0.5
    assert abs(pitch).max() < 0.5  # on the way down too
    assert record.position[-1, 2] == pytest.approx(warthog.base_height, abs=0.005)


@pytest.mark.parametrize("engine", ENGINES)
def test_without_the_coupling_the_chassis_tips_onto_a_rocker_stop(engine, warthog):
    """The description's own <mimic> must not couple the rockers behind RobotSpec's back."""
    free = dataclasses.replace(warthog, couplings=())
    record = get_engine(engine).simulate(flat_scenario(free), hold(free, 0.0, 0.0, 2.0))
    pitch = _pitch_deg(record)[-1]
    print(f"{engine}: uncoupled rest pitch {pitch:+.3f} deg")
    # both rockers on their stop, level on their wheels: the chassis pitched by the stop, 8.59 deg
    assert abs(pitch) == pytest.approx(math.degrees(STOP), abs=0.1)


@pytest.mark.parametrize("engine", ENGINES)
def test_a_coupling_offset_pitches_the_chassis_by_half_of_it(engine, warthog):
    """q(right) = -q(left) + 0.05: both rockers level on their wheels turn 0.025 rad, the chassis -0.025."""
    (coupling,) = warthog.couplings
    shifted = dataclasses.replace(warthog, couplings=(dataclasses.replace(coupling, offset=0.05),))
    record = get_engine(engine).simulate(flat_scenario(shifted), hold(shifted, 0.0, 0.0, 2.0))
    pitch = _pitch_deg(record)[-1]
    print(f"{engine}: offset 0.05 rad, rest pitch {pitch:+.3f} deg")
    assert pitch == pytest.approx(-math.degrees(0.025), abs=0.1)


@pytest.mark.parametrize("engine", ENGINES)
def test_the_rockers_keep_the_coupling_at_rest_and_in_a_spin(engine, warthog):
    adapter = get_engine(engine)
    world = adapter.build(flat_scenario(warthog))
    (coupling,) = warthog.couplings
    names = [s.joint for s in warthog.suspension]
    follower, leader = names.index(coupling.joint), names.index(coupling.leader)
    try:
        residuals = []
        for left, right, seconds in ((0.0, 0.0, 2.0), (0.5, -0.5, 2.0)):
            world.set_wheel_targets(hold(warthog, left, right, DT)[0])
            world.step(round(seconds / DT))
            q = _rocker_angles(engine, world, warthog)
            residuals.append(q[follower] - coupling.multiplier * q[leader] - coupling.offset)
            assert all(STOP * -1.01 < a < STOP * 1.01 for a in q), q  # within the stops
    finally:
        close = getattr(world, "close", None)
        if close is not None:
            close()
    print(f"{engine}: rocker residual q_r + q_l at rest {residuals[0]:+.2e} rad, after a 2 s spin {residuals[1]:+.2e}")
    assert max(abs(r) for r in residuals) < 1.0e-3


@pytest.mark.parametrize("engine", ENGINES)
def test_the_warthog_drives_and_spins_without_diverging(engine, warthog):
    commands = np.concatenate([hold(warthog, 0.5, 0.5, 3.0), hold(warthog, 0.5, -0.5, 3.0)])
    record = get_engine(engine).simulate(flat_scenario(warthog), commands)
    assert np.isfinite(record.position).all() and np.isfinite(record.quaternion).all()
    rpy = np.degrees(euler_rpy(record.quaternion))
    assert np.abs(rpy[:, :2]).max() < 10.0  # roll and pitch within the rockers' reach
    assert np.abs(record.position[:, 2] - warthog.base_height).max() < 0.05
    straight = slice(1500, 3000)
    speed = np.linalg.norm(record.linear_velocity[straight, :2], axis=1).mean()
    # last second and a half of the spin: gyro yaw rate over the kinematic rate of the measured wheels
    spin = slice(4500, 6000)
    rims = warthog.rim_speeds(record.wheel_speed[spin])
    sides = np.array(warthog.sides)
    kinematic = (rims[:, sides == "right"].mean(axis=1) - rims[:, sides == "left"].mean(axis=1)) / warthog.track
    gain = record.angular_velocity[spin, 2].mean() / kinematic.mean()
    print(
        f"{engine}: straight speed {speed:.3f} m/s, spin gain {gain:.3f} (kinematic {kinematic.mean():+.3f} rad/s), "
        f"{record.steps / record.wall_time:.0f} steps/s"
    )
    assert speed == pytest.approx(0.5, abs=0.05)
    assert np.isfinite(gain) and 0.0 < gain < 1.2


@pytest.mark.parametrize("engine", ENGINES)
def test_each_of_two_warthogs_keeps_its_own_coupling(engine, warthog):
    """Every robot of a world gets its suspension (the second one recorded here), none another's."""
    scenario = dataclasses.replace(flat_scenario(warthog), starts=((0.0, 0.0, 0.0), (0.0, 3.0, 0.5)), recorded_robot=1)
    commands = np.broadcast_to(hold(warthog, 0.0, 0.0, 1.5), (1500, 2, warthog.wheel_count)).copy()
    record = get_engine(engine).simulate(scenario, commands)
    assert record.position[-1, 1] == pytest.approx(3.0, abs=0.01)
    assert abs(_pitch_deg(record)[-1]) < 0.5
