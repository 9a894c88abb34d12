"""Reading any wheeled robot's description (simpick.inputs.robot): wheel detection, sides and
forward direction from geometry, the figures the study needs, and each refused layout."""

import math
from pathlib import Path

import numpy as np
import pytest

from conftest import study_config
from simpick.errors import InputError
from simpick.inputs.robot import load_from_config, load_robot

ROOT = Path(__file__).resolve().parents[1]
ROBOTS = ROOT / "resources" / "robot"

CYLINDER_ALONG_Y = '<origin xyz="0 0 0" rpy="1.5707963267948966 0 0"/>'


def _link(name, mass=1.0, collision=""):
    return (
        f'<link name="{name}"><inertial><origin xyz="0 0 0"/><mass value="{mass}"/>'
        f'<inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>{collision}</link>'
    )


def _wheel_collision(radius=0.1, width=0.05, rpy="1.5707963267948966 0 0", shape="cylinder"):
    geometry = (
        f'<cylinder radius="{radius}" length="{width}"/>' if shape == "cylinder" else f'<sphere radius="{radius}"/>'
    )
    return f'<collision><origin xyz="0 0 0" rpy="{rpy}"/><geometry>{geometry}</geometry></collision>'


def _joint(name, parent, child, xyz, rpy="0 0 0", axis="0 1 0", kind="continuous"):
    axis_tag = f'<axis xyz="{axis}"/>' if axis else ""
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}" rpy="{rpy}"/>{axis_tag}</joint>'
    )


def write_robot(tmp_path, wheels, extra="", name="testbot", base_mass=10.0):
    """A box on wheels: ``wheels`` maps joint name -> (x, y, z, rpy, axis) of a 0.1 m wheel."""
    parts = [_link("base_link", base_mass, '<collision><geometry><box size="0.6 0.4 0.1"/></geometry></collision>')]
    for joint, (x, y, z, rpy, axis) in wheels.items():
        link = joint.replace("_joint", "")
        # the wheel link's cylinder lies along the joint axis, in the link's own frame
        rot = "0 0 0" if axis.strip() in ("0 0 1", "0 0 -1") else "1.5707963267948966 0 0"
        parts.append(_link(link, 0.5, _wheel_collision(rpy=rot)))
        parts.append(_joint(joint, "base_link", link, f"{x} {y} {z}", rpy, axis))
    path = tmp_path / f"{name}.urdf"
    path.write_text(f'<?xml version="1.0"?><robot name="{name}">{"".join(parts)}{extra}</robot>')
    return path


def four(rotate_right=False):
    """Husky-like layout; ``rotate_right``: both right joints turned by pi about z (axis +y in the
    joint frame, so -y in the base frame: a mirrored wheel)."""
    r = "0 0 3.141592653589793" if rotate_right else "0 0 0"
    return {
        "fl_joint": (0.25, 0.3, 0.0, "0 0 0", "0 1 0"),
        "fr_joint": (0.25, -0.3, 0.0, r, "0 1 0"),
        "rl_joint": (-0.25, 0.3, 0.0, "0 0 0", "0 1 0"),
        "rr_joint": (-0.25, -0.3, 0.0, r, "0 1 0"),
    }


# --- the robots in the repository ----------------------------------------------------------------


def test_husky_is_read_as_before_and_loaded_as_it_is(robot):
    assert robot.wheel_joints == (
        "front_left_wheel_joint",
        "front_right_wheel_joint",
        "rear_left_wheel_joint",
        "rear_right_wheel_joint",
    )
    assert robot.sides == ("left", "right", "left", "right")
    assert [w.axis_sign for w in robot.driven] == [1, 1, 1, 1]
    assert robot.urdf == robot.source  # no rewrite: every engine loads the file itself
    assert robot.base_link == "base_link" and robot.imu_link == "imu_link"
    assert robot.wheel_radius == 0.1651 and robot.imu_mount == (0.19, 0.0, 0.149)
    assert robot.base_height == pytest.approx(0.1651 - 0.03282, abs=1e-12)
    assert robot.track == pytest.approx(2 * 0.2854) and robot.wheelbase == pytest.approx(0.512)
    assert robot.mass == pytest.approx(46.034 + 4 * 2.637 + 0.018)
    # the controller's wheel speeds: [l, r, l, r] / radius, bit for bit
    np.testing.assert_array_equal(robot.joint_speeds(0.3, 0.7), np.array([0.3, 0.7, 0.3, 0.7]) / 0.1651)


def test_jackal_from_a_massless_base_link():
    jackal = load_robot(ROBOTS / "jackal.urdf")
    assert jackal.name == "jackal" and jackal.base_link == "base_link"
    assert len(jackal.driven) == 4 and not jackal.casters
    assert jackal.mass == pytest.approx(16.523 + 4 * 0.477 + 0.001)
    assert jackal.base_height == pytest.approx(0.098 - 0.0345)
    assert jackal.track == pytest.approx(0.37559) and jackal.wheelbase == pytest.approx(0.262)
    # base_link has no mass (as in Clearpath's description): the engines get the fused copy
    assert jackal.urdf != jackal.source and jackal.urdf.is_file()
    fused = load_robot(jackal.urdf)
    assert fused.mass == pytest.approx(jackal.mass) and np.allclose(fused.com, jackal.com)
    assert [w.position for w in fused.wheels] == [w.position for w in jackal.wheels]


def test_diff_drive_xacro_with_footprint_mirrored_wheel_and_caster():
    bot = load_robot(ROBOTS / "diffbot.urdf.xacro")
    assert bot.base_link == "base_footprint"  # a massless root: fine
    assert bot.wheel_joints == ("left_wheel_joint", "right_wheel_joint")
    left, right = bot.driven
    # left: joint frame turned -pi/2 about x, spinning about its z = base +y; right: turned pi
    # about z, spinning about its +y = base -y: a positive speed rolls it backwards
    assert (left.axis_sign, right.axis_sign) == (1, -1)
    assert left.position == pytest.approx((0.0, 0.12, 0.05)) and right.position == pytest.approx((0.0, -0.12, 0.05))
    (caster,) = bot.casters
    assert caster.joint == "caster_wheel_joint" and caster.swivel == "caster_swivel_joint"
    assert caster.position == pytest.approx((-0.18, 0.0, 0.025))
    assert set(bot.passive_joints) == {"caster_wheel_joint", "caster_swivel_joint"}
    assert bot.base_height == pytest.approx(0.0) and bot.track == pytest.approx(0.24) and bot.wheelbase == 0.0
    assert bot.imu_link == "imu_link" and bot.imu_mount == pytest.approx((0.02, 0.0, 0.11))
    speeds = bot.joint_speeds(0.5, 0.5)
    assert speeds[0] == pytest.approx(10.0) and speeds[1] == pytest.approx(-10.0)
    np.testing.assert_allclose(bot.rim_speeds(speeds), [0.5, 0.5])


# --- layouts found from geometry ------------------------------------------------------------------


def test_rotated_right_joints_drive_forward(tmp_path):
    spec = load_robot(write_robot(tmp_path, four(rotate_right=True)))
    assert spec.wheel_joints == ("fl_joint", "fr_joint", "rl_joint", "rr_joint")
    assert [w.axis_sign for w in spec.driven] == [1, -1, 1, -1]
    assert spec.sides == ("left", "right", "left", "right")


def test_joint_axis_minus_y_is_mirrored(tmp_path):
    wheels = four()
    wheels["fr_joint"] = (0.25, -0.3, 0.0, "0 0 0", "0 -1 0")
    spec = load_robot(write_robot(tmp_path, wheels))
    assert [w.axis_sign for w in spec.driven] == [1, -1, 1, 1]


def test_six_wheels_in_command_order(tmp_path):
    wheels = {
        f"{pos}{side}_joint": (x, y, 0.0, "0 0 0", "0 1 0")
        for pos, x in (("f", 0.4), ("m", 0.0), ("r", -0.4))
        for side, y in (("l", 0.3), ("r", -0.3))
    }
    spec = load_robot(write_robot(tmp_path, dict(reversed(list(wheels.items())))))
    assert spec.wheel_joints == ("fl_joint", "fr_joint", "ml_joint", "mr_joint", "rl_joint", "rr_joint")
    assert spec.wheelbase == pytest.approx(0.8)


def test_figures_overridden_and_wheels_declared(tmp_path):
    path = write_robot(tmp_path, four())
    spec = load_from_config(
        {
            "urdf": str(path),
            "overrides": {"wheel_radius": 0.12, "mass": 20.0},
            "wheels": [{"joint": "fl_joint", "side": "left"}, {"joint": "fr_joint", "side": "right"}],
        }
    )
    assert spec.wheel_radius == 0.12 and spec.mass == 20.0 and set(spec.overridden) == {"wheel_radius", "mass"}
    assert spec.wheel_joints == ("fl_joint", "fr_joint")
    assert {w.joint for w in spec.casters} == {"rl_joint", "rr_joint"}


def test_imu_link_from_config_or_base(tmp_path):
    path = write_robot(
        tmp_path,
        four(),
        extra=_link("sensor", 0.01) + _joint("s", "base_link", "sensor", "0.1 0 0.2", axis="", kind="fixed"),
    )
    assert load_robot(path).imu_link == "base_link"  # no link named *imu*
    assert load_robot(path, imu_link="sensor").imu_mount == pytest.approx((0.1, 0.0, 0.2))
    with pytest.raises(InputError, match="robot.imu_link: 'nowhere' is not a link"):
        load_robot(path, imu_link="nowhere")


# --- refused, each with the joint or link named ------------------------------------------------------


@pytest.mark.parametrize(
    "extra,message",
    [
        (
            _link("steer", 0.1)
            + _joint("steer_joint", "base_link", "steer", "0.5 0 0", axis="0 0 1", kind="revolute")
            + _link("steered_wheel", 0.3, _wheel_collision())
            + _joint("steered_joint", "steer", "steered_wheel", "0 0 0"),
            "joint 'steer_joint': is revolute: a steered or sprung wheel",
        ),
        (
            _link("leg", 0.1) + _joint("knee", "base_link", "leg", "0.5 0 0", kind="prismatic"),
            "joint 'knee': is prismatic: a steering, leg or arm joint",
        ),
        (
            _link("bare", 0.1) + _joint("bare_joint", "base_link", "bare", "0.5 0.2 0"),
            "joint 'bare_joint': is continuous but its child link 'bare' has no cylinder or sphere collision",
        ),
        (
            _link("tilted", 0.1, _wheel_collision(rpy="0 1.5707963267948966 0"))
            + _joint("tilted_joint", "base_link", "tilted", "0.5 0.2 0"),
            "collision cylinder's axis",
        ),
        (
            _link("fan", 0.1, _wheel_collision(rpy="0 1.5707963267948966 0"))
            + _joint("fan_joint", "base_link", "fan", "0 0 0.2", axis="1 0 0"),
            "joint 'fan_joint': spins about [1.0, 0.0, 0.0] in the base frame",
        ),
    ],
)
def test_unsupported_parts_are_named(tmp_path, extra, message):
    with pytest.raises(InputError, match=message.replace("[", r"\[").replace("]", r"\]").replace("(", r"\(")):
        load_robot(write_robot(tmp_path, four(), extra=extra))


def test_no_driven_wheel_is_refused(tmp_path):
    path = write_robot(tmp_path, {})
    with pytest.raises(InputError, match="no driven wheel found.*tracked and legged robots are not supported"):
        load_robot(path)


def test_odd_or_unequal_driven_wheels_are_refused(tmp_path):
    wheels = four()
    del wheels["rr_joint"]
    with pytest.raises(InputError, match="2 left and 1 right driven wheels"):
        load_robot(write_robot(tmp_path, wheels))


def test_unequal_radii_are_refused(tmp_path):
    path = write_robot(tmp_path, four())
    path.write_text(path.read_text().replace('radius="0.1"', 'radius="0.12"', 1))
    with pytest.raises(InputError, match="driven wheel radii differ"):
        load_robot(path)


@pytest.mark.parametrize(
    "text,message",
    [
        ("this is not XML", "cannot read the robot description: not XML"),
        ('<?xml version="1.0"?><sdf version="1.6"/>', "the root element is <sdf>, not <robot>"),
    ],
)
def test_not_a_urdf_is_refused(tmp_path, text, message):
    path = tmp_path / "robot.urdf"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        load_robot(path)


def test_declared_wheel_must_exist(tmp_path):
    with pytest.raises(InputError, match=r"robot.wheels: joints \['nope'\] are not wheel joints"):
        load_robot(write_robot(tmp_path, four()), wheels={"nope": "left"})


def test_normalised_copy_fuses_fixed_links_and_drops_meshes(tmp_path):
    extra = (
        '<link name="lidar"><visual><geometry><mesh filename="package://x/lidar.stl"/></geometry></visual>'
        '<collision><geometry><mesh filename="package://x/lidar.stl"/></geometry></collision>'
        '<inertial><origin xyz="0 0 0.1"/><mass value="2.0"/><inertia ixx="0.001" iyy="0.001" izz="0.001"/>'
        "</inertial></link>"
        + _joint("lidar_joint", "base_link", "lidar", "0.2 0 0.1", "0 0 1.0", axis="", kind="fixed")
    )
    spec = load_robot(write_robot(tmp_path, four(), extra=extra))
    assert spec.urdf != spec.source and any("collision was dropped" in n for n in spec.notes)
    text = spec.urdf.read_text()
    assert "mesh" not in text and "lidar" not in text  # fused into base_link
    fused = load_robot(spec.urdf)
    assert fused.mass == pytest.approx(spec.mass) and np.allclose(fused.com, spec.com)
    assert fused.mass == pytest.approx(10.0 + 4 * 0.5 + 2.0)
    assert math.isclose(fused.com[2], 2.0 * 0.2 / fused.mass)


@pytest.mark.parametrize("name", ["jackal", "diffbot"])
def test_robot_configs_fit_their_robot(name):
    """config/robots/<name>.yaml: the controller's track is the robot's, the open-loop circle starts
    where the robot's own Coulomb arc crosses the strip, the wheel-tracking limit is the Husky's rim
    speed, and the real data (a Husky's) carry no score."""
    import yaml

    from simpick.coulomb import contact_layout, yaw_rate_gain
    from simpick.inputs.motions import arc_start_over_strip

    base = study_config()
    config = yaml.safe_load((ROOT / "config" / "robots" / f"{name}.yaml").read_text())
    spec = load_from_config({**config["robot"], "urdf": str(ROOT / config["robot"]["urdf"])})
    assert spec.name != base["real_data"]["robot"] and config["accuracy"]["reference"] != "real"
    assert config["robot"]["track"] == pytest.approx(spec.track) == config["baselines"]["kinematic"]["track"]
    circle = base["motions"]["circle"]
    gain = yaw_rate_gain(contact_layout(spec), circle["v"], circle["w"], config["robot"]["track"])
    start = config["motions"]["circle"]["start"]
    assert arc_start_over_strip(circle["v"], circle["w"], gain, (1.5, -0.2), start[0]) == pytest.approx(
        start, abs=0.005
    )
    husky = load_robot(ROBOTS / "husky_a200.urdf")
    rim = base["health"]["wheel_tracking"] * husky.wheel_radius
    assert config["health"]["wheel_tracking"] * spec.wheel_radius == pytest.approx(rim, rel=0.01)


def write_skid_robot(tmp_path):
    """A TurtleBot3-like layout (written here, not ROBOTIS's file): footprint root, wheel joints
    turned by -1.57 rad (not quite pi/2) about x spinning about their z, a box skid behind the axle
    fixed to the base 0.5 mm above the ground, an IMU link without mass, mesh visuals; the body's
    centre of mass 0.03 m behind the axle, so that the skid carries a third of the weight."""
    wheel = (
        '<link name="{n}"><visual><geometry><mesh filename="package://tb/{n}.stl"/></geometry></visual>'
        '<collision><geometry><cylinder length="0.018" radius="0.033"/></geometry></collision>'
        '<inertial><mass value="0.0285"/><inertia ixx="1.1e-05" iyy="1.1e-05" izz="2.1e-05" ixy="0" ixz="0" '
        'iyz="0"/></inertial></link>'
    )
    text = f"""<?xml version="1.0"?><robot name="tb_like">
      <link name="base_footprint"/>
      {_joint("base_joint", "base_footprint", "base_link", "0 0 0.010", axis="", kind="fixed")}
      <link name="base_link"><collision><origin xyz="-0.032 0 0.070"/><geometry><box size="0.14 0.14 0.143"/></geometry>
        </collision><inertial><origin xyz="-0.03 0 0.05"/><mass value="0.826"/><inertia ixx="0.0022" iyy="0.0021" izz="0.0020" ixy="0" ixz="0" iyz="0"/>
        </inertial></link>
      {_joint("wheel_left_joint", "base_link", "wheel_left_link", "0 0.08 0.023", "-1.57 0 0", "0 0 1")}
      {wheel.format(n="wheel_left_link")}
      {_joint("wheel_right_joint", "base_link", "wheel_right_link", "0 -0.08 0.023", "-1.57 0 0", "0 0 1")}
      {wheel.format(n="wheel_right_link")}
      {_joint("caster_back_joint", "base_link", "caster_back_link", "-0.081 0 -0.004", "-1.57 0 0", axis="", kind="fixed")}
      <link name="caster_back_link"><collision><origin xyz="0 0.001 0"/><geometry><box size="0.030 0.009 0.020"/></geometry>
        </collision><inertial><mass value="0.005"/><inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/>
        </inertial></link>
      {_joint("imu_joint", "base_link", "imu_link", "-0.032 0 0.068", axis="", kind="fixed")}
      <link name="imu_link"/>
    </robot>"""
    path = tmp_path / "tb_like.urdf"
    path.write_text(text)
    return path


def test_a_box_skid_fixed_to_the_base_is_a_sliding_support(tmp_path):
    spec = load_robot(write_skid_robot(tmp_path))
    assert spec.wheel_joints == ("wheel_left_joint", "wheel_right_joint") and not spec.casters
    assert [w.axis_sign for w in spec.driven] == [1, 1]  # -1.57 about x turns z onto base +y
    (skid,) = spec.skids
    # box 9 mm tall once turned by -1.57 about x, centre 5 mm above the footprint: 0.5 mm clearance
    assert skid.link == "caster_back_link" and skid.shape == "box"
    assert skid.clearance == pytest.approx(0.0005, abs=1e-4) and skid.position[0] == pytest.approx(-0.081)
    assert spec.base_height == pytest.approx(0.0, abs=1e-6) and spec.imu_mount == pytest.approx((-0.032, 0, 0.078))
    assert spec.urdf != spec.source and "mesh" not in spec.urdf.read_text()
    # the base's 0.143 m tall box is no skid: 8.5 mm up
    assert len(spec.skids) == 1


def test_joint_frames_turned_by_half_pi_spinning_about_x(tmp_path):
    """Joint origins turned by +pi/2 about z (left) and -pi/2 (right), each spinning about its
    own x: base +y on the left, base -y on the right (mirrored)."""
    half = "0 0 1.5707963267948966"
    wheels = {
        "fl_joint": (0.25, 0.3, 0.0, half, "1 0 0"),
        "fr_joint": (0.25, -0.3, 0.0, "0 0 -1.5707963267948966", "1 0 0"),
        "rl_joint": (-0.25, 0.3, 0.0, half, "1 0 0"),
        "rr_joint": (-0.25, -0.3, 0.0, "0 0 -1.5707963267948966", "1 0 0"),
    }
    path = write_robot(tmp_path, wheels)
    # the wheel links' cylinders along the joint axis (x in the link frame)
    path.write_text(
        path.read_text().replace(
            'rpy="1.5707963267948966 0 0"/><geometry><cylinder', 'rpy="0 1.5707963267948966 0"/><geometry><cylinder'
        )
    )
    spec = load_robot(path)
    assert spec.wheel_joints == ("fl_joint", "fr_joint", "rl_joint", "rr_joint")
    assert [w.axis_sign for w in spec.driven] == [1, -1, 1, -1]
    assert spec.track == pytest.approx(0.6) and spec.wheelbase == pytest.approx(0.5)


def test_a_massless_moving_part_is_refused(tmp_path):
    extra = (
        '<link name="swivel"/>'
        + _joint("swivel_joint", "base_link", "swivel", "-0.4 0 0", axis="0 0 1")
        + _link("caster", 0.1, _wheel_collision(radius=0.05))
        + _joint("caster_joint", "swivel", "caster", "-0.02 0 -0.05")
    )
    with pytest.raises(InputError, match=r"links \['swivel'\] \(with the links fixed to them\) have no mass"):
        load_robot(write_robot(tmp_path, four(), extra=extra))


def test_warthog_config_fits_the_warthog_and_runs_on_an_engine(tmp_path):
    """config/robots/warthog.yaml: DRIVE's and Clearpath's controller track, the circle over the strip at
    the Warthog's own Coulomb gain, its wheel-tracking limit above the servo lag measured on DRIVE, a valid
    merged config with the suspension's validation cases; and its cases run on an engine (a variant with the rockers fixed, as
    no engine here simulates the suspension yet: the suspension's own cases skip it, saying why)."""
    import yaml

    from simpick.config import problems
    from simpick.coulomb import contact_layout, yaw_rate_gain
    from simpick.inputs.motions import arc_start_over_strip
    from simpick.studies.validation.cases import Setup, run_case

    base = study_config()
    config = yaml.safe_load((ROOT / "config" / "robots" / "warthog.yaml").read_text())
    merged = study_config("config/robots/warthog.yaml")  # read as the workflow reads both files
    assert problems(merged) == []
    spec = load_from_config({**config["robot"], "urdf": str(ROOT / config["robot"]["urdf"])})
    assert spec.name == "warthog" != base["real_data"]["robot"] and config["accuracy"]["reference"] != "real"
    assert spec.track == pytest.approx(1.12)  # geometric; the controller's is DRIVE's and Clearpath's 1.08
    assert config["robot"]["track"] == 1.08 == config["baselines"]["kinematic"]["track"]
    circle = merged["motions"]["circle"]
    gain = yaw_rate_gain(contact_layout(spec), circle["v"], circle["w"], config["robot"]["track"])
    assert gain == pytest.approx(0.570, abs=0.001)
    start = circle["start"]
    assert arc_start_over_strip(circle["v"], circle["w"], gain, (1.5, -0.56), start[0]) == pytest.approx(
        start, abs=0.005
    )
    # the Warthog's own tracking limit: twice the largest servo lag measured at DRIVE's step changes (MuJoCo,
    # 0.35 rad/s over the 345 shared steps; the config says how), above the Husky's limit as a rim speed,
    # which failed healthy steps on that lag alone
    husky = load_robot(ROBOTS / "husky_a200.urdf")
    rim = base["health"]["wheel_tracking"] * husky.wheel_radius / spec.wheel_radius
    assert config["health"]["wheel_tracking"] >= 2 * 0.35 and rim < 0.35
    cases = merged["validation"]["cases"]
    assert {"rest_pose_mu0.8", "articulation_h0.05_mu0.8"} <= set(cases) and set(base["validation"]["cases"]) < set(
        cases
    )

    # the rockers fixed to the chassis: a robot without suspension of the Warthog's shape and weight
    text = (ROOT / config["robot"]["urdf"]).read_text().replace('type="revolute"', 'type="fixed"')
    rigid_path = tmp_path / "warthog_rigid.urdf"
    rigid_path.write_text(text.replace('<mimic joint="left_diff_unit_jnt" multiplier="-1" offset="0"/>', ""))
    rigid = load_from_config({**merged["robot"], "urdf": str(rigid_path)})
    assert rigid.suspension == () and rigid.mass == pytest.approx(260.0)
    setup = Setup(
        "pybullet",
        rigid,
        merged["physics"]["timestep"],
        merged["robot"]["max_wheel_torque"],
        merged["robot"]["track"],
        merged["engines"]["pybullet"],
    )
    skipped = run_case(setup, "rest_pose_mu0.8", cases["rest_pose_mu0.8"])
    assert skipped["status"] == "skipped" and "no suspension" in skipped["reasons"][0]
    straight = run_case(setup, "straight_mu0.8", {**cases["straight_mu0.8"], "duration": 2.0})
    assert straight["status"] == "ok"
    ratio = next(c for c in straight["checks"] if c["quantity"] == "speed_over_wheel_speed")["engine_value"]
    assert ratio == pytest.approx(1.0, abs=0.05)  # 260 kg rolling on 835 N m servos


# --- a maker's xacro package: $(find) includes, macros, package:// meshes, no coupling -------------

ROVER_PARAMS = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="tyre_r" value="0.25"/>
  <xacro:property name="tyre_w" value="0.20"/>
  <xacro:property name="tyre_m" value="10"/>
  <xacro:property name="arm" value="0.40"/>
  <xacro:property name="pivot_y" value="0.45"/>
  <xacro:property name="pivot_z" value="-0.08"/>
  <xacro:property name="rocker_m" value="30"/>
  <xacro:property name="body_m" value="80"/>
  <xacro:macro name="solid_box" params="m x y z">
    <inertia ixx="${m*(y*y+z*z)/12}" iyy="${m*(x*x+z*z)/12}" izz="${m*(x*x+y*y)/12}" ixy="0" ixz="0" iyz="0"/>
  </xacro:macro>
</robot>
"""

ROVER = """<?xml version="1.0"?>
<robot name="rover" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="$(find rover_description)/urdf/params.xacro"/>
  <xacro:macro name="tyre" params="name rocker fwd">
    <link name="${name}_tyre">
      <visual><geometry><mesh filename="package://rover_description/meshes/tyre.stl"/></geometry></visual>
      <collision><origin rpy="${pi/2} 0 0"/><geometry><cylinder radius="${tyre_r}" length="${tyre_w}"/></geometry>
      </collision>
      <inertial><mass value="${tyre_m}"/><inertia ixx="0.2" iyy="0.3" izz="0.2" ixy="0" ixz="0" iyz="0"/></inertial>
    </link>
    <joint name="${name}_tyre_joint" type="continuous">
      <parent link="${rocker}_rocker"/><child link="${name}_tyre"/>
      <origin xyz="${fwd*arm} 0 0"/><axis xyz="0 1 0"/>
    </joint>
  </xacro:macro>
  <xacro:macro name="rocker" params="side y">
    <link name="${side}_rocker">
      <visual><geometry><mesh filename="package://rover_description/meshes/rocker.stl"/></geometry></visual>
      <collision><origin xyz="0 0 0.15"/><geometry><box size="0.9 0.1 0.2"/></geometry></collision>
      <inertial><origin xyz="0 0 0.15"/><mass value="${rocker_m}"/>
        <xacro:solid_box m="${rocker_m}" x="0.9" y="0.1" z="0.2"/></inertial>
    </link>
    <joint name="${side}_rocker_joint" type="revolute">
      <parent link="body"/><child link="${side}_rocker"/>
      <origin xyz="0 ${y*pivot_y} ${pivot_z}"/><axis xyz="0 1 0"/>
      <limit lower="-0.2" upper="0.2" effort="1000" velocity="1"/>
      <dynamics damping="50" friction="0.2"/>
    </joint>
  </xacro:macro>
  <link name="base_link"/>
  <joint name="base_to_body" type="fixed"><parent link="base_link"/><child link="body"/></joint>
  <link name="body">
    <visual><geometry><mesh filename="package://rover_description/meshes/body.stl"/></geometry></visual>
    <collision><geometry><box size="1.0 0.6 0.25"/></geometry></collision>
    <inertial><mass value="${body_m}"/><xacro:solid_box m="${body_m}" x="1.0" y="0.6" z="0.25"/></inertial>
  </link>
  <link name="linkage_bar"><visual><geometry><mesh filename="package://rover_description/meshes/bar.stl"/>
    </geometry></visual></link>
  <joint name="linkage_bar_joint" type="fixed"><parent link="body"/><child link="linkage_bar"/></joint>
  <xacro:rocker side="left" y="1"/>
  <xacro:rocker side="right" y="-1"/>
  <xacro:tyre name="front_left" rocker="left" fwd="1"/>
  <xacro:tyre name="rear_left" rocker="left" fwd="-1"/>
  <xacro:tyre name="front_right" rocker="right" fwd="1"/>
  <xacro:tyre name="rear_right" rocker="right" fwd="-1"/>
  <xacro:include filename="$(find rover_description)/urdf/$(optenv ROVER_EXTRAS extras.urdf)"/>
</robot>
"""

ROVER_COUPLING = [{"joint": "right_rocker_joint", "leader": "left_rocker_joint", "multiplier": -1.0}]


def rover_package(tmp_path, params=True) -> Path:
    """A maker's description package of the Warthog's shape (written here): the xacro in urdf/, its
    figures in a params file it includes through $(find), an extras file named by an optenv."""
    package = tmp_path / "share" / "rover_description"
    (package / "urdf").mkdir(parents=True)
    (package / "urdf" / "rover.urdf.xacro").write_text(ROVER)
    if params:
        (package / "urdf" / "params.xacro").write_text(ROVER_PARAMS)
    (package / "urdf" / "extras.urdf").write_text('<?xml version="1.0"?><robot></robot>\n')
    return package


def test_a_maker_s_xacro_package_reads_without_ros(tmp_path, monkeypatch):
    from simpick.coulomb import contact_layout

    monkeypatch.delenv("ROVER_EXTRAS", raising=False)
    package = rover_package(tmp_path)
    spec = load_from_config(
        {
            "urdf": str(package / "urdf" / "rover.urdf.xacro"),
            "packages": {"rover_description": str(package)},
            "couplings": ROVER_COUPLING,
        }
    )
    assert spec.base_link == "base_link" and spec.urdf != spec.source  # a normalised copy: meshes dropped
    assert "mesh" not in spec.urdf.read_text() and "package://" not in spec.urdf.read_text()
    assert spec.mass == pytest.approx(80 + 2 * 30 + 4 * 10)
    assert [w.joint for w in spec.driven] == [
        "front_left_tyre_joint",
        "front_right_tyre_joint",
        "rear_left_tyre_joint",
        "rear_right_tyre_joint",
    ]
    assert spec.driven[0].position == pytest.approx((0.40, 0.45, -0.08)) and spec.wheel_radius == 0.25
    assert spec.base_height == pytest.approx(0.33)
    assert [s.joint for s in spec.suspension] == ["left_rocker_joint", "right_rocker_joint"]
    left = spec.suspension[0]
    assert (left.lower, left.upper, left.damping, left.friction) == (-0.2, 0.2, 50.0, 0.2)
    assert left.mass == pytest.approx(30 + 2 * 10)
    (coupling,) = spec.couplings
    assert (coupling.joint, coupling.leader, coupling.multiplier, coupling.source) == (
        "right_rocker_joint",
        "left_rocker_joint",
        -1.0,
        "robot.couplings[0]",
    )
    # symmetric about both axes, pivots over the axles' midpoint: a quarter of the weight on each wheel
    np.testing.assert_allclose(contact_layout(spec, 1).loads, [(80 + 60 + 40) * 9.81 / 4] * 4, rtol=1e-9)
    # without the coupling (the maker's file has none) the chassis has no resting pose, as the Warthog's
    loose = load_from_config(
        {"urdf": str(package / "urdf" / "rover.urdf.xacro"), "packages": {"rover_description": package}}
    )
    assert loose.couplings == ()


def test_a_xacro_package_that_is_not_given_or_incomplete_is_one_line(tmp_path):
    package = rover_package(tmp_path, params=False)
    xacro_file = str(package / "urdf" / "rover.urdf.xacro")
    with pytest.raises(InputError, match=r"^robot.packages: .*\$\(find rover_description\).*gives no folder") as info:
        load_robot(xacro_file, packages={"other_description": str(tmp_path)})
    assert "robot.packages: {PKG: FOLDER}" in str(info.value) and "xacro" not in str(info.value).split("(fix")[0][-60:]
    assert str(info.value).count("(fix:") == 1
    with pytest.raises(InputError, match=r"robot.packages: .*rover_description.*gives no folder"):
        load_robot(xacro_file)  # no packages at all: no ROS lookup, the same message
    with pytest.raises(InputError, match=r"robot.packages.rover_description: .*params.xacro.*point robot.packages"):
        load_robot(xacro_file, packages={"rover_description": str(package)})  # its params file is missing
    with pytest.raises(InputError, match=r"robot.packages.rover_description: .*is not a folder"):
        load_robot(xacro_file, packages={"rover_description": str(tmp_path / "nowhere")})


def test_uncoupled_rockers_are_refused_when_the_config_is_read(tmp_path):

    from simpick.config import problems

    text = (ROBOTS / "warthog.urdf").read_text()
    loose = tmp_path / "loose.urdf"
    loose.write_text(text.replace('<mimic joint="left_diff_unit_jnt" multiplier="-1" offset="0"/>', ""))
    config = study_config("config/robots/warthog.yaml")
    config["robot"]["urdf"] = str(loose)
    (line,) = problems(config)
    assert "no resting pose" in line and "robot.couplings" in line, line
    config["robot"]["couplings"] = [{"joint": "right_diff_unit_jnt", "leader": "left_diff_unit_jnt"}]
    assert problems(config) == []
