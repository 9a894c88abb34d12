"""Robot descriptions shaped as makers write them, which the loader must accept and every engine run
alike: wheels on a chassis link fixed below base_link, base_link under a massless base_footprint
root, and angles rounded in the file (rpy "3.14 0 0" for pi, an axis a fraction of a degree off),
snapped within the loader's 0.5 degree and reported. A layout simpick cannot study is refused at
loading (planning), with one line naming the joint. The URDFs are written here, in the shapes of
public descriptions (a Jackal-like chassis link, a TurtleBot-like footprint, a Husky-like rounded
pi), not copied from any maker's file."""

import math

import numpy as np
import pytest

from simpick.engines import ADAPTERS, unavailable
from simpick.errors import InputError
from simpick.inputs.robot import SNAP_TOLERANCE_DEG, load_robot
from simpick.studies.validation.cases import Setup, run_case

ENGINES = [e for e in ADAPTERS if e not in unavailable([e])]
WHEEL_R, WHEEL_W = 0.1, 0.06


def _inertial(mass, xyz="0 0 0", i=0.02):
    return (
        f'<inertial><origin xyz="{xyz}" rpy="0 0 0"/><mass value="{mass}"/>'
        f'<inertia ixx="{i}" iyy="{i}" izz="{i}" ixy="0" ixz="0" iyz="0"/></inertial>'
    )


def _wheel_link(name, rpy="1.5707963267948966 0 0"):
    return (
        f'<link name="{name}">{_inertial(0.8, i=0.003)}<collision><origin xyz="0 0 0" rpy="{rpy}"/>'
        f'<geometry><cylinder radius="{WHEEL_R}" length="{WHEEL_W}"/></geometry></collision></link>'
    )


def _joint(name, parent, child, xyz, rpy="0 0 0", axis="0 1 0", kind="continuous"):
    axis_tag = f'<axis xyz="{axis}"/>' if kind != "fixed" else ""
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}" rpy="{rpy}"/>{axis_tag}</joint>'
    )


def _wheels(parent, z, rpy=None, axis=None):
    """Four wheels on ``parent``, their joints at height ``z`` in its frame; ``rpy`` / ``axis``:
    joint name -> the joint's origin rpy / axis where it is not the plain one."""
    rpy, axis = rpy or {}, axis or {}
    parts = []
    for name, x, y in (
        ("front_left", 0.2, 0.25),
        ("front_right", 0.2, -0.25),
        ("rear_left", -0.2, 0.25),
        ("rear_right", -0.2, -0.25),
    ):
        joint = f"{name}_wheel_joint"
        parts.append(_wheel_link(f"{name}_wheel"))
        parts.append(
            _joint(joint, parent, f"{name}_wheel", f"{x} {y} {z}", rpy.get(joint, "0 0 0"), axis.get(joint, "0 1 0"))
        )
    return "".join(parts)


CHASSIS = (
    "<link name='base_link'/>"  # massless root, as in a Jackal-like description
    f"<link name='chassis_link'>{_inertial(15.0, '0 0 0.05', 0.3)}<collision><origin xyz='0 0 0.06'/>"
    "<geometry><box size='0.5 0.4 0.12'/></geometry></collision></link>"
    + _joint("chassis_joint", "base_link", "chassis_link", "0 0 0", kind="fixed")
    + f"<link name='imu_link'>{_inertial(0.02, i=1e-5)}</link>"
    + _joint("imu_joint", "chassis_link", "imu_link", "0.1 0 0.1", kind="fixed")
    + _wheels("chassis_link", 0.0)
)
FOOTPRINT = (
    "<link name='base_footprint'/>"  # the ground-level root of a TurtleBot-like description
    f"<link name='base_link'>{_inertial(15.0, '0 0 0.05', 0.3)}<collision><origin xyz='0 0 0.06'/>"
    "<geometry><box size='0.5 0.4 0.12'/></geometry></collision></link>"
    + _joint("base_joint", "base_footprint", "base_link", f"0 0 {WHEEL_R}", kind="fixed")
    + _wheels("base_link", 0.0)
)
# the right wheels mirrored by a rounded pi about x (their axis then points to -y), and one left axis
# tilted 0.23 degree
ROUNDED = (
    f"<link name='base_link'>{_inertial(15.0, '0 0 0.05', 0.3)}<collision><origin xyz='0 0 0.06'/>"
    "<geometry><box size='0.5 0.4 0.12'/></geometry></collision></link>"
    + _wheels(
        "base_link",
        0.0,
        axis={"rear_left_wheel_joint": "0 1 0.004"},
        rpy={"front_right_wheel_joint": "3.14 0 0", "rear_right_wheel_joint": "3.14 0 0"},
    )
)
LAYOUTS = {"chassis": CHASSIS, "footprint": FOOTPRINT, "rounded": ROUNDED}


def _write(tmp_path, name, body):
    path = tmp_path / f"{name}.urdf"
    path.write_text(f'<?xml version="1.0"?><robot name="{name}">{body}</robot>')
    return path


@pytest.fixture(scope="module", params=list(LAYOUTS))
def layout(request, tmp_path_factory):
    return request.param, load_robot(_write(tmp_path_factory.mktemp("robots"), request.param, LAYOUTS[request.param]))


def test_the_loader_reads_each_layout(layout):
    name, robot = layout
    assert robot.wheel_joints == (
        "front_left_wheel_joint",
        "front_right_wheel_joint",
        "rear_left_wheel_joint",
        "rear_right_wheel_joint",
    )
    assert robot.track == pytest.approx(0.5) and robot.wheelbase == pytest.approx(0.4)
    assert robot.wheel_radius == WHEEL_R
    # the rigid model every body-by-body engine builds: one chassis with everything fixed to it
    assert robot.rigid.chassis.mass == pytest.approx(15.0 + (0.02 if name == "chassis" else 0.0))
    assert len(robot.rigid.wheels) == 4
    # and the file every engine loads has the fixed chains folded: no wheel hangs on a fixed link
    text = robot.urdf.read_text()
    assert "chassis_link" not in text or name != "chassis"
    if name == "rounded":
        assert [w.axis_sign for w in robot.driven] == [1, -1, 1, -1]  # mirrored by the (snapped) pi
        snapped = [n for n in robot.notes if "snapped" in n]
        assert len(snapped) == 3, robot.notes  # two rotations and one axis, each reported
        assert any("3.14 0 0" in n and "0.091 deg" in n for n in snapped), snapped


def test_an_angle_beyond_the_tolerance_is_refused_with_one_line(tmp_path):
    tilt = math.tan(math.radians(2 * SNAP_TOLERANCE_DEG))
    body = ROUNDED.replace("0 1 0.004", f"0 1 {tilt:.6f}")
    with pytest.raises(InputError) as raised:
        load_robot(_write(tmp_path, "cambered", body))
    message = str(raised.value)
    assert "rear_left_wheel_joint" in message and "\n" not in message, message


@pytest.mark.parametrize("engine", ENGINES)
def test_every_engine_runs_the_validation_on_each_layout(layout, engine):
    """The validation's rest and straight cases, as a job runs them: the robot rests level on its
    wheels and drives straight at its wheels' rim speed, whichever way the maker wrote it."""
    name, robot = layout
    setup = Setup(engine=engine, robot=robot, timestep=0.001, max_wheel_torque=20.0, track=robot.track, settings={})
    rest = run_case(setup, "rest", {"kind": "rest", "mu": 0.8, "duration": 1.5})
    assert rest["status"] == "ok", rest
    checks = {c["quantity"]: c["engine_value"] for c in rest["checks"]}
    assert checks["accel_z"] == pytest.approx(9.81, abs=0.05), checks
    assert checks["creep_distance"] < 0.005, checks
    straight = run_case(setup, "straight", {"kind": "straight", "v": 0.3, "mu": 0.8, "duration": 2.0})
    assert straight["status"] == "ok", straight
    checks = {c["quantity"]: c["engine_value"] for c in straight["checks"]}
    assert checks["speed_over_wheel_speed"] == pytest.approx(1.0, abs=0.03), checks
    assert np.isfinite(checks["heading_drift"]) and abs(checks["heading_drift"]) < 0.05, checks
