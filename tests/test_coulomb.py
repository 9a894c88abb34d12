"""The quasi-static Coulomb skid-steer solver against hand-computed cases (METHOD.md s6)."""

import math

import numpy as np
import pytest

from simpick.coulomb import (
    ContactLayout,
    CoulombTable,
    contact_layout,
    equal_loads,
    mass_distribution,
    steady_twist,
    yaw_rate_gain,
)
from simpick.errors import InputError

TRACK = 0.555


def test_two_wheels_on_one_axle_turn_without_slip():
    # Contacts only on the axle (x = 0): no lateral slip, so yaw rate = (u_r - u_l) / (2 b) exactly.
    b = 0.2854
    # wheel order FL, FR, RL, RR -> contacts at left, right, left, right
    axle = ContactLayout(
        points=np.array([(0, b), (0, -b), (0, b), (0, -b)]),
        loads=np.ones(4),
        wheel=np.arange(4),
        com=(0.0, 0.0),
        mass=1.0,
    )
    assert yaw_rate_gain(axle, 0.5, 0.5, TRACK) == pytest.approx(TRACK / (2 * b), rel=1e-6)


def test_equal_loads_give_0_539_for_any_command(robot):
    equal = equal_loads(contact_layout(robot, points_per_wheel=1))
    for v, w in [(0.0, 0.5), (0.5, 0.5), (0.5, 0.2), (1.0, 0.1), (-0.3, 0.8)]:
        assert yaw_rate_gain(equal, v, w, TRACK) == pytest.approx(0.539, abs=0.001), (v, w)


def test_two_contact_points_per_wheel_give_0_526(robot):
    assert yaw_rate_gain(equal_loads(contact_layout(robot, 2)), 0.5, 0.5, TRACK) == pytest.approx(0.526, abs=0.001)


def test_urdf_centre_of_mass_shifts_the_load_and_lowers_the_gain(robot):
    mass, com = mass_distribution(robot.urdf)
    assert mass == pytest.approx(46.034 + 4 * 2.637 + 0.018, abs=0.05)
    # chassis COM y = -0.085 m over the whole robot's mass
    assert com[1] == pytest.approx(-0.085 * 46.034 / mass, rel=1e-3)
    one = contact_layout(robot, 1)
    shares = one.load_shares()
    # rigid body on equal springs: both left wheels together carry 1/2 (1 + yc / b), b = 0.2854 m
    assert shares[0] + shares[2] == pytest.approx(0.5 * (1 + com[1] / 0.2854), rel=1e-6)
    assert shares[0] == pytest.approx(0.19, abs=0.005) and shares[1] == pytest.approx(0.31, abs=0.005)
    assert one.loads.sum() == pytest.approx(mass * 9.81)
    assert yaw_rate_gain(one, 0.5, 0.5, TRACK) == pytest.approx(0.481, abs=0.001)
    assert yaw_rate_gain(contact_layout(robot), 0.5, 0.5, TRACK) == pytest.approx(0.478, abs=0.001)


def test_forces_balance_at_the_solution(robot):
    lay = contact_layout(robot, 1)
    u = np.array([0.36, 0.64, 0.36, 0.64])
    vx, vy, wz = steady_twist(lay, u)
    x, y = lay.points.T
    s = np.stack([vx - wz * y - u[lay.wheel], vy + wz * x], axis=1)
    f = -lay.loads[:, None] * s / np.linalg.norm(s, axis=1, keepdims=True)
    assert np.abs(f.sum(axis=0)).max() < 1e-4 * lay.loads.sum()
    assert abs((x * f[:, 1] - y * f[:, 0]).sum()) < 1e-4 * lay.loads.sum()


def test_straight_command_rolls_and_spin_does_not_translate(robot):
    lay = contact_layout(robot, 1)
    np.testing.assert_allclose(steady_twist(lay, [0.5] * 4), [0.5, 0.0, 0.0], atol=1e-6)
    assert steady_twist(lay, [0.0] * 4).tolist() == [0.0, 0.0, 0.0]


def test_table_interpolates_the_solver(robot):
    lay = contact_layout(robot, 1)
    table = CoulombTable(lay, angles=720)
    for left, right in [(0.36, 0.64), (-0.14, 0.14), (0.5, 0.5), (0.2, -0.05)]:
        np.testing.assert_allclose(
            table.twist([left], [right])[0], steady_twist(lay, [left, right] * 2), atol=2e-3 * math.hypot(left, right)
        )


# --- any robot: N contacts, casters, braking with casters ------------------------------------------


def test_diff_drive_on_a_frictionless_caster_turns_without_slip():
    from conftest import ROOT
    from simpick.inputs.robot import load_robot

    bot = load_robot(ROOT / "resources" / "robot" / "diffbot.urdf.xacro")
    one = contact_layout(bot, points_per_wheel=1)
    assert one.sides == ("left", "right", "caster")
    # three contacts: statically determinate, loads from moments about the axle (x = 0)
    x_c, x_g, weight = bot.casters[0].position[0], bot.com[0], bot.mass * 9.81
    shares = one.load_shares()
    assert shares[2] == pytest.approx(x_g / x_c, rel=1e-9)
    assert shares[0] == pytest.approx((1 - x_g / x_c) / 2, rel=1e-9) and one.loads.sum() == pytest.approx(weight)
    # no contact need slip: the gain is 1 for any command, the controller's track the geometric one
    for v, w in [(0.5, 0.5), (0.0, 1.0), (0.3, -0.2)]:
        assert yaw_rate_gain(one, v, w, bot.track) == pytest.approx(1.0, abs=1e-6), (v, w)
    # a line contact across each 25 mm wheel scuffs a little when turning
    assert 0.97 < yaw_rate_gain(contact_layout(bot), 0.5, 0.5, bot.track) < 1.0
    # a skid dragging with friction k mu instead of the caster, on a spin about the axle: it pulls
    # k mu N_c sideways at x_c; each wheel must hold half of that sideways and the moment k mu N_c |x_c|
    # as a force couple over the track: by hand, below mu N_w for k = 1 (no slip: gain 1), above it for
    # k = 2 (the wheels slip and the robot turns slower)
    n_w, n_c = one.loads[0], one.loads[2]
    for k in (1.0, 2.0):
        need = math.hypot(k * n_c * abs(x_c) / bot.track, k * n_c / 2)
        assert (need < n_w) == (k == 1.0)
    assert yaw_rate_gain(contact_layout(bot, 1, caster_friction=1.0), 0.0, 1.0, bot.track) == pytest.approx(
        1.0, abs=1e-6
    )
    assert yaw_rate_gain(contact_layout(bot, 1, caster_friction=2.0), 0.0, 1.0, bot.track) < 0.95


def test_braking_deceleration_with_casters_and_without():
    from conftest import ROOT
    from simpick.coulomb import braking_deceleration
    from simpick.inputs.robot import load_robot

    husky = load_robot(ROOT / "resources" / "robot" / "husky_a200.urdf")
    assert braking_deceleration(husky, 0.3) == (pytest.approx(0.3 * 9.81), None)
    bot = load_robot(ROOT / "resources" / "robot" / "diffbot.urdf.xacro")
    a, why = braking_deceleration(bot, 0.3)
    # by hand: moments about the centre of mass (h above ground) with friction mu N_d at the axle
    x_c, x_g, h = -0.18, bot.com[0], bot.com[2] + bot.base_height
    n_d = (x_c - x_g) / (x_c - 0.0 + 0.3 * h)
    assert why is None and a == pytest.approx(0.3 * 9.81 * n_d) and 0 < n_d < 1
    # so much friction that the caster lifts: not applicable, with the reason
    a, why = braking_deceleration(bot, 5.0)
    assert math.isnan(a) and "pitches over" in why


def test_rotated_joints_give_the_same_layout_as_plain_ones(tmp_path):
    from simpick.inputs.robot import load_robot
    from test_robot import four, write_robot

    plain = contact_layout(load_robot(write_robot(tmp_path, four(), name="plain")))
    rotated = contact_layout(load_robot(write_robot(tmp_path, four(rotate_right=True), name="rotated")))
    np.testing.assert_allclose(rotated.points, plain.points, atol=1e-12)
    np.testing.assert_allclose(rotated.loads, plain.loads, rtol=1e-12)


def test_a_skid_drags_with_the_ground_s_friction(tmp_path):
    from simpick.coulomb import braking_deceleration
    from simpick.inputs.robot import load_robot
    from test_robot import write_skid_robot

    spec = load_robot(write_skid_robot(tmp_path))
    one = contact_layout(spec, 1)
    assert one.sides == ("left", "right", "skid") and one.friction.tolist() == [1.0, 1.0, 1.0]
    # three supports: the skid's load from moments about the axle
    x_s = spec.skids[0].position[0]
    assert one.load_shares()[2] == pytest.approx(spec.com[0] / x_s, rel=1e-9)
    # the skid drags: spinning in place, the wheels must slip and the robot turns slower than
    # no-slip kinematics; every contact slides when the wheels lock: mu g
    assert yaw_rate_gain(one, 0.0, 1.0, spec.track) < yaw_rate_gain(
        contact_layout(spec, 1, caster_friction=0.0), 0.0, 1.0, spec.track
    )
    # its centre of mass 0.03 m behind the axle, 0.04 m up: the centre of pressure moves 0.3 x 0.04 m
    # forward when braking at mu 0.3, still behind the axle: mu g. At mu 0.8 it passes the axle
    h = spec.com[2] + spec.base_height
    assert spec.com[0] + 0.3 * h < 0 < spec.com[0] + 0.8 * h
    assert braking_deceleration(spec, 0.3) == (pytest.approx(0.3 * 9.81), None)
    a, why = braking_deceleration(spec, 0.8)
    assert math.isnan(a) and "pitches onto its nose" in why


# --- anisotropic (elliptic) friction --------------------------------------------------------------


def test_anisotropic_spin_matches_the_closed_form(robot):
    # Four equal loads at (+-a, +-b), pure spin at rim speed u: by symmetry vx = vy = 0 and
    # D(w) = 4 N sqrt((w b - u)^2 + r^2 (w a)^2) is least at w = u b / (b^2 + r^2 a^2); the
    # commanded turn is 2 u / track, so gain = track b / (2 (b^2 + r^2 a^2)).
    from simpick.coulomb import with_friction_ratio

    equal = equal_loads(contact_layout(robot, points_per_wheel=1))
    a, b = float(abs(equal.points[0, 0])), float(abs(equal.points[0, 1]))
    for r in (1.0, 0.8, 0.63, 0.5, 0.2):
        expected = TRACK * b / (2 * (b * b + r * r * a * a))
        assert yaw_rate_gain(with_friction_ratio(equal, r), 0.0, 0.5, TRACK) == pytest.approx(expected, rel=1e-5), r


def test_anisotropic_gain_is_monotone_in_the_ratio_and_has_both_limits(robot):
    from simpick.coulomb import with_friction_ratio

    husky = contact_layout(robot)
    # r = 1 is today's isotropic solver, bit for bit
    assert (
        yaw_rate_gain(contact_layout(robot, friction_ratio=1.0), 0.5, 0.5, TRACK)
        == yaw_rate_gain(husky, 0.5, 0.5, TRACK)
        == pytest.approx(0.478, abs=0.001)
    )
    gains = [yaw_rate_gain(with_friction_ratio(husky, r), 0.5, 0.5, TRACK) for r in (1.2, 1.0, 0.8, 0.63, 0.5, 0.3)]
    assert all(lo < hi for lo, hi in zip(gains, gains[1:])), gains  # less lateral friction turns more
    # symmetric robot, equal loads, one point per wheel: r -> 0 turns as the contacts' no-slip
    # kinematics (gain track / 2b), r -> 1 gives the isotropic 0.539
    equal = equal_loads(contact_layout(robot, points_per_wheel=1))
    b = float(abs(equal.points[0, 1]))
    assert yaw_rate_gain(with_friction_ratio(equal, 1e-3), 0.5, 0.5, TRACK) == pytest.approx(TRACK / (2 * b), rel=1e-3)
    assert yaw_rate_gain(with_friction_ratio(equal, 1 - 1e-6), 0.5, 0.5, TRACK) == pytest.approx(0.539, abs=0.001)


def test_anisotropic_forces_balance_on_the_ellipse(robot):
    # At the solution the elliptic friction forces F = -N (s_x, r^2 s_y) / sqrt(s_x^2 + r^2 s_y^2)
    # (maximum dissipation on the ellipse) sum to zero force and zero yaw moment.
    lay = contact_layout(robot, 1, friction_ratio=0.63)
    u = np.array([0.2, 0.7, 0.2, 0.7])
    vx, vy, wz = steady_twist(lay, u)
    x, y = lay.points.T
    sx, sy = vx - wz * y - u[lay.wheel], vy + wz * x
    norm = np.sqrt(sx**2 + 0.63**2 * sy**2)
    fx, fy = -lay.loads * sx / norm, -lay.loads * 0.63**2 * sy / norm
    assert abs(fx.sum()) < 1e-4 * lay.loads.sum() and abs(fy.sum()) < 1e-4 * lay.loads.sum()
    assert abs((x * fy - y * fx).sum()) < 1e-4 * lay.loads.sum()


@pytest.mark.parametrize("bad", [0.0, -0.5, float("nan"), float("inf")])
def test_bad_friction_ratio_is_refused(robot, bad):
    from simpick.errors import InputError

    with pytest.raises(InputError, match="friction_ratio"):
        contact_layout(robot, friction_ratio=bad)


def test_coulomb_baseline_turns_at_its_friction_ratio(robot):
    """The ``coulomb`` reference model reads baselines.coulomb.friction_ratio (a calibratable
    parameter): its steady yaw rate is the anisotropic solver's at that ratio."""
    from conftest import drive
    from simpick.studies.calibration.parameters import parameter_space

    assert "friction_ratio" in parameter_space("coulomb")
    for r in (1.0, 0.63):
        record = drive(
            "coulomb", robot, v=0.5, w=0.5, ground=0.8, duration=2.0, timestep=0.01, settings={"friction_ratio": r}
        )
        expected = yaw_rate_gain(contact_layout(robot, friction_ratio=r), 0.5, 0.5, TRACK)
        assert record.angular_velocity[-1, 2] / 0.5 == pytest.approx(expected, rel=2e-3), r
    with pytest.raises(Exception, match="friction_ratio"):
        drive("coulomb", robot, settings={"friction_ratio": -1.0})


# --- slip compliance ---------------------------------------------------------------------------


def _viscous_twist(layout, u, r=1.0):
    """Independent viscous limit: every contact below saturation, force -s / k_i, so the twist is
    the least-squares solution of s_i = 0 weighted by 1 / sqrt(k_i) (lateral rows by r as well)."""
    x, y = layout.points.T
    w = 1.0 / np.sqrt(layout.slip_compliance)
    n = len(x)
    a = np.zeros((2 * n, 3))
    b = np.zeros(2 * n)
    a[:n, 0], a[:n, 2], b[:n] = w, -w * y, w * np.asarray(u, dtype=float)[layout.wheel]
    a[n:, 1], a[n:, 2] = w * r, w * r * x
    return np.linalg.lstsq(a, b, rcond=None)[0]


def test_slip_compliance_zero_is_rigid_coulomb_and_large_is_viscous(robot):
    from simpick.coulomb import with_slip_compliance

    one = contact_layout(robot, points_per_wheel=1)
    u = one.rim_speeds(-0.1387, 0.1387)  # spin at w = 0.5
    assert with_slip_compliance(one, 0.0).slip_compliance is None
    np.testing.assert_array_equal(steady_twist(with_slip_compliance(one, 0.0), u), steady_twist(one, u))
    soft = with_slip_compliance(one, 1.0)  # saturation slip mu N k ~ 100 m/s: all viscous
    np.testing.assert_allclose(steady_twist(soft, u, mu=0.8), _viscous_twist(soft, u), atol=1e-6)
    # viscous and equal compliance: the loads drop out, the gain is the equal-loads 0.539 (rigid 0.481)
    assert yaw_rate_gain(soft, 0.0, 0.5, TRACK, mu=0.8) == pytest.approx(0.539, abs=0.001)
    assert yaw_rate_gain(with_slip_compliance(one, 1e-7), 0.0, 0.5, TRACK, mu=0.8) == pytest.approx(0.481, abs=0.001)


def test_compliant_gain_depends_on_the_command_size(robot):
    """Not homogeneous any more: at 1e-4 (m/s)/N a slow spin is viscous, a fast one Coulomb."""
    from simpick.coulomb import with_slip_compliance

    lay = with_slip_compliance(contact_layout(robot, points_per_wheel=1), 1e-4)
    gains = [yaw_rate_gain(lay, 0.0, w, TRACK, mu=0.8) for w in (0.01, 0.1, 0.5, 2.0)]
    assert gains[0] == pytest.approx(0.539, abs=0.002) and gains[-1] == pytest.approx(0.481, abs=0.002)
    assert all(a >= b - 1e-6 for a, b in zip(gains, gains[1:])), gains
    with pytest.raises(InputError, match="slip_compliance"):
        CoulombTable(lay, angles=8)
    with pytest.raises(InputError, match="slip_compliance"):
        with_slip_compliance(lay, -1.0)


def test_ratio_for_gain_inverts_the_anisotropic_gain_and_the_ros_multiplier(robot):
    from simpick.coulomb import ratio_for_gain, wheel_separation_multiplier

    husky = contact_layout(robot)
    r = ratio_for_gain(husky, 0.70, 0.5, 0.5, TRACK)
    assert 0.6 < r < 0.66  # the notes' r ~ 0.63 for hard ground
    assert yaw_rate_gain(contact_layout(robot, friction_ratio=r), 0.5, 0.5, TRACK) == pytest.approx(0.70, abs=1e-3)
    assert math.isnan(ratio_for_gain(husky, 1.2, 0.5, 0.5, TRACK))  # above the frictionless-sideways limit
    # Clearpath's Husky multiplier 1.875 on the 0.5708 m separation <=> a gain of 0.519 on track 0.555
    assert wheel_separation_multiplier(0.5186, TRACK, 0.5708) == pytest.approx(1.875, abs=0.001)
    assert wheel_separation_multiplier(1.0, 0.5708, 0.5708) == 1.0


# --- a robot on a passive suspension: the Warthog's rockers and their differential ----------------

WARTHOG = "resources/robot/warthog.urdf"
G = 9.81


def warthog_variant(tmp_path, name, chassis=(0.0, 0.0), left_rocker_dx=0.0, mimic=True):
    """The shipped Warthog with its chassis' mass centre moved to ``chassis`` (x, y), the left
    rocker's moved ``left_rocker_dx`` forward, or its rockers uncoupled (``mimic`` False)."""
    from conftest import ROOT

    text = (ROOT / WARTHOG).read_text()
    text = text.replace(
        '<origin xyz="0 0 0" rpy="0 0 0"/>\n      <mass value="100"/>',
        f'<origin xyz="{chassis[0]} {chassis[1]} 0" rpy="0 0 0"/>\n      <mass value="100"/>',
    )
    text = text.replace('<origin xyz="0 -0.05 0.197"', f'<origin xyz="{left_rocker_dx} -0.05 0.197"')
    if not mimic:
        text = text.replace('<mimic joint="left_diff_unit_jnt" multiplier="-1" offset="0"/>', "")
    path = tmp_path / f"{name}.urdf"
    path.write_text(text)
    return path


def lever_loads(chassis_x, chassis_y, left_rocker_dx=0.0):
    """The Warthog's wheel loads (FL, FR, BL, BR), N, by hand.

    Sides: every left wheel stands at y = +0.56 and every right one at -0.56, so the robot's roll
    balance alone splits the weight: T_left - T_right = W y_G / 0.56, and only the chassis' 100 kg
    is off the centre line (rockers at y +-0.50 and wheels at +-0.56 balance each other).
    Each side: a rocker is a lever about its pivot (x 0.04), its wheels 0.46 m ahead and behind.
    The differential passes the same torque to both rockers, and together they hold the chassis'
    weight moment about the pivots' line, 100 g (x_c - 0.04): half on each. The rocker's own 50 kg
    adds its moment 50 g dx about its pivot; the wheels' 15 kg each balance about it. So
    0.46 (N_front - N_back) = 50 g (x_c - 0.04) + 50 g dx and N_front + N_back = T_side."""
    weight = 260 * G
    split = 100 * G * chassis_y / 0.56
    loads = {}
    for side, total, dx in (("l", (weight + split) / 2, left_rocker_dx), ("r", (weight - split) / 2, 0.0)):
        difference = (50 * G * (chassis_x - 0.04) + 50 * G * dx) / 0.46
        loads["f" + side], loads["b" + side] = (total + difference) / 2, (total - difference) / 2
    return np.array([loads["fl"], loads["fr"], loads["bl"], loads["br"]])


def test_warthog_wheel_loads_are_the_rockers_lever_balance():
    from conftest import ROOT
    from simpick.inputs.robot import load_robot

    warthog = load_robot(ROOT / WARTHOG)
    assert [w.joint for w in warthog.driven] == ["fl_wheel_jnt", "fr_wheel_jnt", "bl_wheel_jnt", "br_wheel_jnt"]
    by_hand = lever_loads(0.0, 0.0)
    # front 616.3 N, back 659.0 N: the chassis' mass centre 4 cm behind the pivots loads the back wheels
    np.testing.assert_allclose(by_hand, [616.32, 616.32, 658.98, 658.98], atol=0.01)
    for points in (1, 2, None):
        layout = contact_layout(warthog, points)
        np.testing.assert_allclose(np.bincount(layout.wheel, layout.loads), by_hand, rtol=1e-9)
    # the validation's flat-ground turn (v 0.5, w 0.5) under the controller's track 1.08 m: a line contact
    # across each wheel gives 0.570 (one point per wheel 0.577), the same turning either way and spinning
    line = contact_layout(warthog)
    assert yaw_rate_gain(line, 0.5, 0.5, 1.08) == pytest.approx(0.570, abs=0.001)
    assert yaw_rate_gain(contact_layout(warthog, 1), 0.5, 0.5, 1.08) == pytest.approx(0.577, abs=0.001)
    for v, w in [(0.5, -0.5), (0.0, 0.5)]:
        assert yaw_rate_gain(line, v, w, 1.08) == pytest.approx(0.570, abs=0.001)


def test_the_differential_shares_an_off_centre_chassis_as_levers_not_as_a_rigid_body(tmp_path):
    from simpick.inputs.robot import load_robot

    moved = load_robot(warthog_variant(tmp_path, "moved", chassis=(-0.10, 0.08), left_rocker_dx=0.10))
    one = contact_layout(moved, 1)
    by_hand = lever_loads(-0.10, 0.08, left_rocker_dx=0.10)
    np.testing.assert_allclose(one.loads, by_hand, rtol=1e-9)
    assert one.loads.sum() == pytest.approx(260 * G)
    # a rigid robot on equally stiff contacts would share it otherwise: its loads are linear in position
    # (the same diagonal sums), which no differential-coupled pair of free rockers can give here
    x, y = one.points.T
    a = np.vstack([np.ones(4), x, y])
    rigid = a.T @ np.linalg.solve(a @ a.T, a @ by_hand)
    assert np.abs(rigid - by_hand).max() > 10.0
    # across each wheel's width the wheel totals stay those of the levers (a line contact's points share
    # its roll moment; 1 N in 1300 here)
    line = contact_layout(moved)
    np.testing.assert_allclose(np.bincount(line.wheel, line.loads), by_hand, atol=1.0)


def test_uncoupled_rockers_have_no_resting_pose_and_are_refused(tmp_path):
    from simpick.inputs.robot import load_robot

    loose = load_robot(warthog_variant(tmp_path, "loose", mimic=False))
    assert loose.couplings == ()
    with pytest.raises(InputError, match=r"no resting pose.*tips onto the joint limits.*robot.couplings"):
        contact_layout(loose)
    # the same file coupled through the config reads as the shipped one
    coupled = load_robot(
        warthog_variant(tmp_path, "loose", mimic=False),
        couplings=[{"joint": "right_diff_unit_jnt", "leader": "left_diff_unit_jnt", "multiplier": -1.0}],
    )
    np.testing.assert_allclose(contact_layout(coupled, 1).loads, lever_loads(0.0, 0.0), rtol=1e-9)


def test_coulomb_baseline_turns_the_warthog_at_its_gain():
    """The ``coulomb`` reference model runs the suspended robot (it reads its loads through
    contact_layout, never through an engine's suspension) and settles at its quasi-static gain."""
    from conftest import ROOT, drive
    from simpick.inputs.robot import load_robot

    warthog = load_robot(ROOT / WARTHOG)
    # the test scenario commands through the Husky's track 0.555: rim speeds 0.5 -+ 0.139 m/s
    record = drive("coulomb", warthog, v=0.5, w=0.5, ground=0.8, duration=2.0, timestep=0.01)
    expected = yaw_rate_gain(contact_layout(warthog), 0.5, 0.5, TRACK)
    assert record.angular_velocity[-1, 2] / 0.5 == pytest.approx(expected, rel=2e-3)
    # the gain scales with the commanded rim-speed difference: the same turn as 0.570 under track 1.08
    assert expected == pytest.approx(0.570 * TRACK / 1.08, rel=2e-3)


def test_a_robot_without_suspension_keeps_the_rigid_body_loads(robot):
    # the rigid body's minimum-norm loads, computed as before the suspension existed, to the last bit
    for points in (1, None):
        layout = contact_layout(robot, points)
        a = np.vstack([np.ones(len(layout.points)), layout.points[:, 0], layout.points[:, 1]])
        b = robot.mass * 9.81 * np.array([1.0, robot.com[0], robot.com[1]])
        assert np.array_equal(layout.loads, a.T @ np.linalg.solve(a @ a.T, b))


def test_rockers_whose_wheels_do_not_all_touch_at_zero_are_refused(tmp_path):
    from conftest import ROOT
    from simpick.inputs.robot import load_robot

    # the left front axle 2 cm lower: at rest the left rocker turns, and the loads at zero would be wrong
    text = (ROOT / WARTHOG).read_text().replace('<origin xyz="0.46 0.01 -0.005"', '<origin xyz="0.46 0.01 -0.025"')
    path = tmp_path / "tilted.urdf"
    path.write_text(text)
    with pytest.raises(InputError, match=r"do not touch flat ground with every joint at zero.*resting pose"):
        contact_layout(load_robot(path))


# --- locked wheels on a slope: elliptic anisotropic Coulomb friction (METHOD.md section 10) ---

G = 9.81


def _downhill(heading: float) -> tuple[float, float]:
    """The incline case's downhill direction in the wheel frame (the robot at heading 0): -(cos h, sin h)."""
    h = math.radians(heading)
    return (-math.cos(h), -math.sin(h))


def _config_case(name: str) -> dict:
    import yaml

    from conftest import ROOT

    return yaml.safe_load((ROOT / "config.yaml").read_text())["validation"]["cases"][name]


@pytest.mark.parametrize("heading", [0.0, 30.0, 45.0, 90.0, 135.0, -60.0])
def test_an_isotropic_slope_slide_is_the_closed_form_at_every_heading(heading):
    from simpick.slope import hold_angle, slope_holds, slope_slide

    mu, down = 0.5, _downhill(heading)
    angle = 1.2 * math.atan(mu)
    law = slope_slide(angle, down, mu, 1.0, duration=2.0)
    expected = G * (math.sin(angle) - mu * math.cos(angle))
    assert law.downhill_acceleration == pytest.approx(expected, rel=1e-9)
    assert law.acceleration == pytest.approx(expected, rel=1e-9)
    assert law.drift == pytest.approx(0.0, abs=1e-9)
    # a straight path down the slope at the constant acceleration: s = a t^2 / 2
    assert np.allclose(law.position, np.outer(expected * law.time**2 / 2, down), rtol=0, atol=1e-9)
    assert not law.holds
    assert hold_angle(down, mu) == pytest.approx(math.atan(mu), rel=1e-12)
    assert slope_holds(0.999 * math.atan(mu), down, mu) and not slope_holds(1.001 * math.atan(mu), down, mu)
    parked = slope_slide(0.8 * math.atan(mu), down, mu, 1.0, duration=2.0)
    assert parked.holds and not parked.position.any() and parked.acceleration == 0.0


@pytest.mark.parametrize("ratio", [0.698, 1.5])
@pytest.mark.parametrize("heading,across", [(0.0, False), (180.0, False), (90.0, True), (-90.0, True)])
def test_a_slope_along_an_axis_of_the_ellipse_is_the_closed_form_with_that_axis_coefficient(heading, across, ratio):
    from simpick.slope import hold_angle, slope_slide

    mu = 0.5
    own = ratio * mu if across else mu  # mu_t across the wheels, mu_l along them
    angle = 1.2 * math.atan(own)
    law = slope_slide(angle, _downhill(heading), mu, ratio, duration=2.0)
    assert law.downhill_acceleration == pytest.approx(G * (math.sin(angle) - own * math.cos(angle)), rel=1e-9)
    assert law.acceleration == pytest.approx(law.downhill_acceleration, rel=1e-9)
    assert law.drift == pytest.approx(0.0, abs=1e-9)
    assert hold_angle(_downhill(heading), mu, ratio) == pytest.approx(math.atan(own), rel=1e-12)


def test_the_diagonal_slope_slides_faster_on_wheels_that_slip_sideways_and_drifts_across_them():
    from scipy.optimize import minimize

    from simpick.slope import slope_slide

    case = _config_case("incline_slide_diagonal_mu0.5")
    mu, heading = case["mu"], case["heading"]
    angle = case["angle_factor"] * math.atan(mu)
    down = np.array(_downhill(heading))
    isotropic = G * (math.sin(angle) - mu * math.cos(angle))
    assert isotropic == pytest.approx(1.016, abs=5e-4)
    law = slope_slide(angle, down, mu, 0.698, duration=4.0, timestep=0.001)
    # what the case measures: s(t) along the downhill direction, fitted from 1 s (SETTLE_S) to the end
    window = law.time >= 1.0
    fitted = 2 * np.polyfit(law.time[window], law.position[window] @ down, 2)[0]
    assert fitted == pytest.approx(law.downhill_acceleration, rel=1e-9)
    assert law.downhill_acceleration == pytest.approx(1.6915, abs=1e-4)  # MuJoCo at ratio 0.698: 1.6937
    assert law.acceleration == pytest.approx(1.7390, abs=1e-4)
    assert law.acceleration > law.downhill_acceleration > isotropic
    # towards the low-friction axis (y): from -135 degrees towards -90, counter-clockwise
    assert law.drift == pytest.approx(0.2343, abs=1e-4)
    # independently: from rest the motion is u = c t, c the minimiser of |c|^2 / 2 - g sin a d.c + g cos a |M c|
    m = np.array([mu, 0.698 * mu])

    def objective(c):
        norm = np.linalg.norm(m * c)
        value = c @ c / 2 - G * math.sin(angle) * down @ c + G * math.cos(angle) * norm
        return value, c - G * math.sin(angle) * down + G * math.cos(angle) * m * m * c / norm

    c = minimize(objective, G * math.sin(angle) * down, jac=True, method="BFGS", options={"gtol": 1e-12}).x
    assert law.velocity[-1] / law.time[-1] == pytest.approx(c, rel=1e-7)
    assert np.allclose(law.velocity, np.outer(law.time, law.velocity[-1] / law.time[-1]), rtol=0, atol=1e-9)
    # wheels that grip harder across than along (ratio 1.5) slide slower and drift towards their x axis
    grippy = slope_slide(angle, down, mu, 1.5, duration=1.0)
    assert grippy.downhill_acceleration < isotropic and grippy.drift < 0


def test_a_slope_the_isotropic_ellipse_holds_slides_on_wheels_that_slip_sideways():
    from simpick.slope import hold_angle, slope_holds, slope_slide

    mu = 0.5
    angle = _config_case("incline_hold_mu0.5")["angle_factor"] * math.atan(mu)  # 0.8 atan(mu)
    across = _downhill(90.0)
    assert slope_holds(angle, across, mu, 1.0) and not slope_holds(angle, across, mu, 0.698)
    law = slope_slide(angle, across, mu, 0.698, duration=2.0)
    assert not law.holds
    assert law.downhill_acceleration == pytest.approx(G * (math.sin(angle) - 0.698 * mu * math.cos(angle)), rel=1e-9)
    held = slope_slide(angle, across, mu, 1.0, duration=2.0)
    assert held.holds and not held.velocity.any()
    # the threshold follows the heading: at 45 degrees 0.829 atan(mu) for ratio 0.698
    diagonal = _downhill(45.0)
    assert hold_angle(diagonal, mu, 0.698) / math.atan(mu) == pytest.approx(0.8294, abs=1e-4)
    assert slope_holds(0.82 * math.atan(mu), diagonal, mu, 0.698)
    assert not slope_holds(0.84 * math.atan(mu), diagonal, mu, 0.698)
    # just inside the ellipse the implicit step holds it exactly: no creep
    assert not slope_slide(0.999 * hold_angle(diagonal, mu, 0.698), diagonal, mu, 0.698).position.any()


@pytest.mark.parametrize(
    "bad", [dict(ratio=0.0), dict(mu=-0.5), dict(down=(0.0, 0.0)), dict(angle=math.pi / 2), dict(timestep=0.0)]
)
def test_slope_slide_refuses_what_is_no_slope(bad):
    from simpick.slope import slope_slide

    args = dict(angle=0.5, down=(-1.0, 0.0), mu=0.5, ratio=1.0, duration=1.0, timestep=0.001) | bad
    with pytest.raises(InputError):
        slope_slide(**args)


def test_slope_slide_follows_the_law_for_any_slope_heading_and_ratio():
    from hypothesis import given, settings
    from hypothesis import strategies as st

    from simpick.slope import slope_holds, slope_slide

    @settings(max_examples=40, deadline=None)
    @given(
        mu=st.floats(0.1, 1.5),
        ratio=st.floats(0.2, 2.0),
        heading=st.floats(-180.0, 180.0),
        factor=st.floats(0.3, 1.7),
    )
    def check(mu, ratio, heading, factor):
        angle = min(factor * math.atan(mu), 1.5)
        down = np.array(_downhill(heading))
        law = slope_slide(angle, down, mu, ratio, duration=0.05, timestep=0.001)
        assert law.holds == slope_holds(angle, down, mu, ratio)
        if law.holds:
            assert not law.velocity.any()
            return
        # a constant acceleration c from rest, which satisfies the law: c = g sin a d - g cos a M^2 c / |M c|
        c = law.velocity[-1] / law.time[-1]
        assert np.allclose(law.velocity, np.outer(law.time, c), rtol=0, atol=1e-9)
        m = np.array([mu, ratio * mu])
        residual = c - G * math.sin(angle) * down + G * math.cos(angle) * m * m * c / np.linalg.norm(m * c)
        assert np.abs(residual).max() <= 1e-7 * G
        assert law.acceleration >= law.downhill_acceleration - 1e-12

    check()
