"""Quasi-static skid-steer on flat rigid ground with Coulomb friction (METHOD.md section 6).

At steady state a wheeled robot's body twist (vx, vy, wz) is the one for which the friction
forces of all wheel contacts, each ``-mu_i N_i`` times the unit slip vector of its contact
point, and their yaw moment sum to zero. Those sums are the gradient of the total frictional
power ``D(q) = sum_i mu_i N_i |s_i(q)|`` with ``s_i = (vx - wz y_i - u_i, vy + wz x_i)`` (u_i
the rim speed of the contact's wheel), so the steady twist is the minimiser of a convex
function: found here with SciPy, whatever the number of contacts, loads and layout. A common
``mu`` scales D and drops out; D is positively homogeneous in the rim speeds, so the twist
scales with the command and a replay needs the solution on one circle of (left, right)
commands only (:class:`CoulombTable`).

The contact layout and loads come from the robot description (:func:`contact_layout`, through
:class:`simpick.inputs.robot.RobotSpec`): each wheel's contact points across its width under its
centre, and static loads from the whole robot's mass and centre of mass, shared among the
contact points as a rigid body on equally stiff contacts does (the minimum-norm load set that
balances weight and the two tipping moments: loads linear in position; exact for three
contacts, the statically indeterminate four or more shared as for the Husky). A robot on a passive
suspension (rockers, bogies) also balances each free motion of its mechanism, which fixes the loads a
rigid body leaves open: each rocker is a lever about its pivot, and a differential coupling two
rockers passes the same torque to both (:func:`_suspended_loads`; the Warthog: 616 N on each front
wheel, 659 N on each back one). A caster on a
swivel is frictionless (it turns to roll wherever it is pushed: load, no force); a passive wheel
without a swivel rolls freely but resists lateral slip; ``caster_friction`` replaces both by
sliding friction of that fraction of the ground's. For a two-wheel differential drive on
frictionless casters no contact need slip, and the gain is 1 (up to the scuffing across each
wheel's width).

Anisotropic (elliptic) friction: a wheel contact may resist sliding across the wheel
less (or more) than along it, ``mu_lat = r mu_long`` in the wheel's frame (its rolling direction,
here the base's x: no wheel is steered). The friction force is the one that maximises the
dissipated power on the ellipse (F_long / mu_long)^2 + (F_lat / mu_lat)^2 <= N^2, so the contact
dissipates ``mu_long N sqrt(s_long^2 + r^2 s_lat^2)`` and D stays convex and homogeneous: the same
solver, with that norm. ``r = 1`` is isotropic Coulomb; ``r -> 0`` lets the contacts slide
sideways freely (the gain tends to the no-slip kinematics of the contacts' lateral positions).
For four equally loaded contacts at (+-a, +-b) a pure spin gives the closed form
``w = u b / (b^2 + r^2 a^2)`` (tests/test_coulomb.py). Skids and ball casters have no wheel
frame and stay isotropic.

Slip compliance (ODE's force-dependent slip, Gazebo's <slip1>/<slip2>): a contact point
with compliance k ((m/s)/N) slides at k x its friction force until that force reaches Coulomb's
bound, F = -min(rho / k, mu N) along the (elliptic) slip. Its dissipation potential is then the
Huber function of the slip (quadratic rho^2 / 2k below the saturation slip c = k mu N, linear
beyond), still convex: the same minimisation, but no longer homogeneous in the rim speeds, so the
twist depends on the command's size and on mu (slow commands: the viscous limit, every contact
below saturation, loads irrelevant; fast ones: Coulomb). :class:`CoulombTable` refuses it.

The same elliptic law on locked wheels sliding down a slope is :mod:`simpick.slope`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from simpick.errors import InputError
from simpick.inputs.motions import side_speeds
from simpick.inputs.robot import SKID_REACH, RobotSpec, load_robot

GRAVITY = 9.81


@dataclass(frozen=True)
class ContactLayout:
    """Ground contact points in the base frame's horizontal plane and their normal loads."""

    points: np.ndarray  # (n, 2) x, y in m, relative to the base frame
    loads: np.ndarray  # (n,) N
    wheel: np.ndarray  # (n,) index into ``sides`` of the wheel each point belongs to
    com: tuple[float, float]  # x, y of the whole robot's centre of mass, m
    mass: float  # kg
    # per wheel: "left"/"right" (driven, in the robot's command order) or "caster"
    sides: tuple[str, ...] = ("left", "right", "left", "right")
    # (n,) friction of each point relative to the ground's (0: frictionless caster)
    friction: np.ndarray | None = None
    # (n,) True where the wheel rolls freely (a passive wheel: friction across it only)
    free_roll: np.ndarray | None = None
    # (n,) lateral / longitudinal friction ratio of each point in its wheel's frame (None: 1,
    # isotropic); see the module docstring
    lateral_ratio: np.ndarray | None = None
    # (n,) slip compliance of each point, (m/s)/N (None: rigid Coulomb); see the module docstring
    slip_compliance: np.ndarray | None = None

    def load_shares(self) -> np.ndarray:
        """Fraction of the weight on each wheel (command order, then casters)."""
        return np.bincount(self.wheel, weights=self.loads, minlength=len(self.sides)) / self.loads.sum()

    def rim_speeds(self, left, right) -> np.ndarray:
        """Rim speed per wheel (0 for casters) for the sides' rim speeds."""
        return np.array([left if s == "left" else right if s == "right" else 0.0 for s in self.sides], dtype=float)


def mass_distribution(urdf: str | Path) -> tuple[float, np.ndarray]:
    """Total mass and centre of mass (in the base frame, joints at zero) of every link."""
    robot = load_robot(urdf)
    return robot.mass, np.asarray(robot.com)


def contact_layout(
    robot: RobotSpec,
    points_per_wheel: int | None = None,
    caster_friction: float | None = None,
    friction_ratio: float = 1.0,
) -> ContactLayout:
    """Wheel contact points and static loads of ``robot`` on flat ground.

    ``points_per_wheel``: None spreads pressure uniformly across each wheel's width (the line
    contact of a rigid cylinder on a plane, here 21 points); 1 puts one point under the wheel
    centre; 2 one at each edge (what several engines generate for a cylinder on a plane). A
    sphere wheel has one point. ``caster_friction``: see the module docstring.
    """
    n = 21 if points_per_wheel is None else int(points_per_wheel)
    points, wheel, friction, free = [], [], [], []
    sides = []
    for index, w in enumerate(robot.wheels):
        x, y, _ = w.position
        offsets = [0.0] if (n == 1 or w.shape == "sphere") else np.linspace(-w.width / 2, w.width / 2, n)
        if w.driven:
            mu, rolls = 1.0, False
        elif caster_friction is not None:
            mu, rolls = float(caster_friction), False
        else:
            mu, rolls = (0.0, False) if w.swivel else (1.0, True)
        for dy in offsets:
            points.append((x, y + dy))
            wheel.append(index)
            friction.append(mu)
            free.append(rolls)
        sides.append(w.side if w.driven else "caster")
    for skid in robot.skids:  # a skid or ball caster fixed to the base slides: the ground's friction
        points.append(skid.position[:2])
        wheel.append(len(sides))
        friction.append(1.0 if caster_friction is None else float(caster_friction))
        free.append(False)
        sides.append("skid")
    points = np.asarray(points)
    mass, com = robot.mass, robot.com
    # Rigid body on equally stiff contacts: loads are linear in position, the minimum-norm
    # solution of (sum N = W, sum N x = W xc, sum N y = W yc).
    a = np.vstack([np.ones(len(points)), points[:, 0], points[:, 1]])
    if np.linalg.matrix_rank(a) < 3:  # every contact on one line: two wheels and nothing else touching
        raise InputError(
            str(robot.source),
            "the robot stands on one line of contacts (its driven wheels' axle) "
            f"with no caster or skid within {SKID_REACH * 1000:.0f} mm of the ground: it would tip",
            "give it a caster wheel on a swivel, or a collision shape reaching the ground",
        )
    weight = mass * GRAVITY
    if robot.suspension:  # rockers: the mechanism's own equilibrium decides what the rigid body leaves open
        loads = _suspended_loads(robot, points, np.asarray(wheel), a, weight * np.array([1.0, com[0], com[1]]))
    else:
        loads = a.T @ np.linalg.solve(a @ a.T, weight * np.array([1.0, com[0], com[1]]))
    if np.any(loads <= 0):
        lifted = sorted({robot.wheels[i].joint for i in np.asarray(wheel)[loads <= 0]})
        raise InputError(
            str(robot.source),
            f"the centre of mass ({com[0]:.3f}, {com[1]:.3f}) m lies outside the "
            f"wheels' support polygon: wheels {lifted} would lift",
        )
    casters = any(not w.driven for w in robot.wheels) or bool(robot.skids)
    layout = ContactLayout(
        points=points,
        loads=loads,
        wheel=np.asarray(wheel),
        com=(com[0], com[1]),
        mass=mass,
        sides=tuple(sides),
        friction=np.asarray(friction) if casters else None,
        free_roll=np.asarray(free) if casters else None,
    )
    return with_friction_ratio(layout, friction_ratio)


def _suspended_loads(robot: RobotSpec, points: np.ndarray, wheel: np.ndarray, a: np.ndarray, b: np.ndarray):
    """Static contact loads of a robot on passive suspension joints (rockers, bogies), resting on
    flat ground with every joint at zero.

    A rigid robot gives three equations (weight, and its moments about x and y) for its contact
    loads. A suspension adds one equation per free motion of its mechanism: with the chassis held,
    turning a free joint by a small angle moves the bodies below it, and at rest neither the
    contact loads nor gravity may do work along that motion (the joints are free: their friction
    only holds a pose, it sets none). Joint j turning by dq moves a point p below it by
    dq a_j x (p - o_j) (a_j its axis, o_j its origin), so the equation of a free motion k, which
    turns joint j by w_kj dq, is

        sum_j w_kj [ sum_{contacts i below j} N_i (a_j x (p_i - o_j))_z - g M_j (a_j x (c_j - o_j))_z ] = 0

    with M_j, c_j the mass and centre of mass of everything below j (:class:`Suspension`). An
    uncoupled joint is a motion of its own (w = 1); coupled joints move together: the leader by 1,
    the follower by the coupling's multiplier.

    For a lateral axis the bracket is the rocker's lever balance about its pivot: the moment of its
    wheels' loads about the pivot equals the moment of its own weight (wheels included). A free
    rocker's two wheels thus share the load at its pivot in inverse proportion to their distance
    from it. Two rockers coupled by a differential (multiplier -1, the Warthog) form one motion,
    left rocker down where the right one goes up: their lever balances need not vanish each, only
    their difference, so the differential carries a torque, the same on both rockers; the chassis'
    pitch balance (the rigid body's moment about y) makes the two torques together hold the
    chassis' weight moment about the pivots' line, so each rocker's lever carries half of it (for
    any lateral distribution of the weight: the differential passes torque, not load), and the
    pivots carry the chassis' weight as its roll balance shares it between the two sides.

    Loads beyond those equations (more contact points than equations, e.g. several across a wheel's
    width) are shared as for a rigid robot: the minimum-norm solution, which is the one on equally
    stiff contacts. With uncoupled rockers on both sides there are more equations than the contacts
    can meet: the chassis has no resting pitch and tips onto the joint limits, which is refused.
    """
    index = {w.joint: i for i, w in enumerate(robot.wheels)}
    ground = -robot.base_height
    # with every joint at zero the lowest wheel sets the resting height (the description's, even where the
    # config overrides that figure)
    lowest = max(w.radius - w.position[2] for w in robot.wheels)
    off_ground = [w.joint for w in robot.wheels if w.mount is not None and lowest - (w.radius - w.position[2]) > 2e-3]
    if off_ground:
        raise InputError(
            str(robot.source),
            f"wheels {off_ground} on the suspension do not touch flat ground with every joint at zero: "
            "the resting pose turns the rockers, and the Coulomb reference reads the loads at zero",
            "give the description its resting pose (every wheel on the ground with the rocker joints at zero)",
        )
    followers = {c.joint: c for c in robot.couplings}
    rows, rhs = [], []
    for leader in (s for s in robot.suspension if s.joint not in followers):
        weights = {leader.joint: 1.0}
        weights.update({c.joint: c.multiplier for c in robot.couplings if c.leader == leader.joint})
        row, value = np.zeros(len(points)), 0.0
        for sus in (s for s in robot.suspension if s.joint in weights):
            axis, pivot = np.asarray(sus.axis), np.asarray(sus.position)
            below = np.isin(wheel, [index[j] for j in sus.wheels if j in index])
            arm = np.column_stack([points, np.full(len(points), ground)]) - pivot
            row += weights[sus.joint] * np.where(below, np.cross(axis, arm)[:, 2], 0.0)
            value += weights[sus.joint] * GRAVITY * sus.mass * np.cross(axis, np.asarray(sus.com) - pivot)[2]
        rows.append(row)
        rhs.append(value)
    system = np.vstack([a, rows])
    target = np.concatenate([b, rhs])
    loads = np.linalg.lstsq(system, target, rcond=None)[0]  # the minimum-norm solution
    residual = np.abs(system @ loads - target).max()
    if residual > 1e-6 * b[0]:
        free = [s.joint for s in robot.suspension if s.joint not in followers]
        raise InputError(
            str(robot.source),
            f"the suspension joints {free} leave the robot no resting pose on flat ground: the chassis tips "
            "onto the joint limits (the rockers are not coupled, or their mechanism cannot balance the weight)",
            "couple the rockers as the robot's own linkage does: a <mimic> on the follower joint in the "
            "description, or robot.couplings in the config (a differential bar: multiplier -1)",
        )
    return loads


def _checked_ratio(ratio: float) -> float:
    ratio = float(ratio)
    if not (math.isfinite(ratio) and ratio > 0):
        raise InputError(
            "friction_ratio",
            f"{ratio!r} is not a positive finite number",
            "give the lateral/longitudinal friction ratio, e.g. 0.63 (1: isotropic)",
        )
    return ratio


def with_friction_ratio(layout: ContactLayout, ratio: float) -> ContactLayout:
    """The same layout with every wheel contact's lateral/longitudinal friction ratio set to
    ``ratio`` (skids stay isotropic); 1 gives back an isotropic layout."""
    ratio = _checked_ratio(ratio)
    if ratio == 1.0:
        lateral = None
    else:
        is_wheel = np.array([layout.sides[k] != "skid" for k in layout.wheel])
        lateral = np.where(is_wheel, ratio, 1.0)
    return ContactLayout(
        points=layout.points,
        loads=layout.loads,
        wheel=layout.wheel,
        com=layout.com,
        mass=layout.mass,
        sides=layout.sides,
        friction=layout.friction,
        free_roll=layout.free_roll,
        lateral_ratio=lateral,
        slip_compliance=layout.slip_compliance,
    )


def with_slip_compliance(layout: ContactLayout, per_wheel: float) -> ContactLayout:
    """The same layout with every wheel's contact points sharing a slip compliance of
    ``per_wheel`` (m/s)/N for the wheel as a whole: its n points in parallel each get n x that
    (skids get the same per point). 0: rigid Coulomb. An engine with m contacts per wheel, each of
    compliance k (ODE's contact_slip), has per_wheel = k / m."""
    per_wheel = float(per_wheel)
    if not (math.isfinite(per_wheel) and per_wheel >= 0):
        raise InputError(
            "slip_compliance",
            f"{per_wheel!r} is not a finite number >= 0",
            "give the wheel's slip compliance in (m/s)/N, 0 for rigid Coulomb",
        )
    compliance = None
    if per_wheel > 0:
        count = np.bincount(layout.wheel)
        compliance = per_wheel * count[layout.wheel].astype(float)
    return ContactLayout(
        points=layout.points,
        loads=layout.loads,
        wheel=layout.wheel,
        com=layout.com,
        mass=layout.mass,
        sides=layout.sides,
        friction=layout.friction,
        free_roll=layout.free_roll,
        lateral_ratio=layout.lateral_ratio,
        slip_compliance=compliance,
    )


def equal_loads(layout: ContactLayout) -> ContactLayout:
    """The same contact points with the weight shared equally (a centred centre of mass)."""
    loads = np.full(len(layout.loads), layout.loads.sum() / len(layout.loads))
    return ContactLayout(
        points=layout.points,
        loads=loads,
        wheel=layout.wheel,
        com=(0.0, 0.0),
        mass=layout.mass,
        sides=layout.sides,
        friction=layout.friction,
        free_roll=layout.free_roll,
        lateral_ratio=layout.lateral_ratio,
        slip_compliance=layout.slip_compliance,
    )


def steady_twist(layout: ContactLayout, rim_speeds, mu: float = 1.0) -> np.ndarray:
    """Body twist (vx, vy, wz) at the base frame under rim speeds per wheel (layout.sides) in m/s.
    ``mu``, the ground's friction coefficient, matters only with slip compliance."""
    from scipy.optimize import minimize

    u = np.asarray(rim_speeds, dtype=float)[layout.wheel]
    scale = float(np.abs(u).max())
    if scale == 0.0:
        return np.zeros(3)
    x, y = layout.points[:, 0], layout.points[:, 1]
    weights = layout.loads / layout.loads.sum()
    if layout.friction is not None:  # casters: their own friction (0: load, no force)
        weights = weights * layout.friction
    along = 1.0 if layout.free_roll is None else (~layout.free_roll).astype(float)
    r2 = 1.0 if layout.lateral_ratio is None else layout.lateral_ratio**2  # elliptic friction
    eps = 1e-9  # slip speed (relative) below which |s| is rounded: keeps D differentiable
    un = u / scale

    def power(q):
        sx = (q[0] - q[2] * y - un) * along
        sy = q[1] + q[2] * x
        norm = np.sqrt(sx * sx + r2 * sy * sy + eps * eps)
        ex, ey = weights * sx / norm, weights * r2 * sy / norm
        return float(weights @ norm), np.array([ex.sum(), ey.sum(), (ex * -y + ey * x).sum()])

    if layout.slip_compliance is not None:  # Huber potential, saturation slip c = k mu N (relative units)
        friction = 1.0 if layout.friction is None else layout.friction
        saturation = layout.slip_compliance * float(mu) * layout.loads * friction / scale
        saturation = np.maximum(saturation, 1e-300)

        def power(q):  # noqa: F811 (the compliant potential replaces the rigid one)
            sx = (q[0] - q[2] * y - un) * along
            sy = q[1] + q[2] * x
            norm = np.sqrt(sx * sx + r2 * sy * sy + eps * eps)
            below = norm < saturation
            value = np.where(below, norm * norm / (2 * saturation), norm - saturation / 2)
            slope = np.where(below, 1.0 / saturation, 1.0 / norm)
            ex, ey = weights * sx * slope, weights * r2 * sy * slope
            return float(weights @ value), np.array([ex.sum(), ey.sum(), (ex * -y + ey * x).sum()])

    start = np.array([un.mean(), 0.0, 0.0])
    result = minimize(
        power,
        start,
        jac=True,
        method="BFGS",
        options={"gtol": 1e-12, "maxiter": 500 if layout.slip_compliance is None else 2000},
    )
    return result.x * scale


def yaw_rate_gain(
    layout: ContactLayout, v: float, w: float, track: float, wheel_radius: float | None = None, mu: float = 1.0
) -> float:
    """Steady yaw rate / commanded w under the paper's controller (Eq. 1, effective track);
    ``mu`` matters only with slip compliance."""
    left, right = side_speeds(v, w, track)
    return float(steady_twist(layout, layout.rim_speeds(left, right), mu)[2] / w)


def ratio_for_gain(
    layout: ContactLayout, gain: float, v: float, w: float, track: float, bounds: tuple[float, float] = (0.02, 2.0)
) -> float:
    """The lateral/longitudinal friction ratio at which the anisotropic Coulomb gain at (v, w) is
    ``gain`` (the gain falls monotonically with the ratio); NaN when ``gain`` lies outside the
    gains at ``bounds``."""
    from scipy.optimize import brentq

    def excess(r: float) -> float:
        return yaw_rate_gain(with_friction_ratio(layout, r), v, w, track) - gain

    lo, hi = excess(bounds[0]), excess(bounds[1])
    if not (math.isfinite(gain) and lo >= 0 >= hi):
        return math.nan
    return float(brentq(excess, *bounds, xtol=1e-4))


def wheel_separation_multiplier(gain: float, track: float, separation: float) -> float:
    """What a ROS diff_drive_controller user sets as ``wheel_separation_multiplier`` for a robot
    whose yaw rate is ``gain`` x (v_right - v_left) / ``track``: the controller commands
    v_right - v_left = w x multiplier x ``separation`` (the wheels' geometric separation), so the
    robot turns at w when multiplier = track / (gain x separation). Clearpath's 1.875 for the
    Husky (separation 0.5708 m) is a gain of 0.519 against track 0.555."""
    return float(track / (gain * separation)) if gain > 0 else math.inf


class CoulombTable:
    """Steady twist for any (left, right) rim speed pair, from solutions on the unit circle.

    D is positively homogeneous of degree one in the rim speeds, so the twist for
    ``r (cos a, sin a)`` is ``r`` times the twist for angle ``a``: solved once on a fine
    circle of angles and interpolated linearly in between.
    """

    def __init__(self, layout: ContactLayout, angles: int = 1440):
        if layout.slip_compliance is not None:
            raise InputError(
                "slip_compliance",
                "a compliant layout's twist is not homogeneous in the rim speeds, "
                "so it cannot be tabled on the unit circle",
                "solve each command with steady_twist",
            )
        self.angles = np.linspace(-math.pi, math.pi, angles + 1)
        self.twists = np.array([steady_twist(layout, layout.rim_speeds(math.cos(a), math.sin(a))) for a in self.angles])

    def twist(self, left, right) -> np.ndarray:
        """(n, 3) twists for arrays of left and right rim speeds (m/s)."""
        left, right = np.asarray(left, dtype=float), np.asarray(right, dtype=float)
        radius = np.hypot(left, right)
        angle = np.arctan2(right, left)
        out = np.stack([np.interp(angle, self.angles, self.twists[:, k]) for k in range(3)], axis=-1)
        return out * radius[..., None]


def load_layout(urdf: str | Path, points_per_wheel: int | None = None) -> ContactLayout:
    return contact_layout(load_robot(urdf), points_per_wheel)


def braking_deceleration(robot: RobotSpec, mu: float) -> tuple[float, str | None]:
    """Steady deceleration (m/s^2) of ``robot`` sliding forward on its locked driven wheels,
    casters rolling free, with the pitch load transfer of a rigid body; and why it does not
    apply (None if it does).

    Every wheel locked (no casters): mu g. With casters, only the driven wheels' load N_d brakes:
    moments about the centre of mass (height h above ground) give, for driven wheels at x_d and
    casters at x_c, N_d = m g (x_c - x_g) / (x_c - x_d + mu h) and a = mu N_d / m.
    """
    casters = robot.casters
    x_g, h = robot.com[0], robot.com[2] + robot.base_height
    if not casters:  # every contact slides (skids too): mu g, if none lifts
        # moments about the centre of mass: the centre of pressure moves forward by mu h, which
        # must stay behind the front-most contact, else the robot pitches onto its nose
        front = max([w.position[0] for w in robot.driven] + [s.position[0] for s in robot.skids])
        if x_g + mu * h > front:
            return math.nan, (
                f"braking at mu {mu:g} moves the centre of pressure {mu * h:.3f} m forward, ahead of "
                f"the front-most contact (x = {front:.3f} m, centre of mass at {x_g:.3f} m, {h:.3f} m "
                "high): the robot pitches onto its nose, which the sliding case does not describe"
            )
        return mu * GRAVITY, None
    if robot.skids:
        return math.nan, (
            "the robot has both free casters and sliding skids, for which the sliding case has no analytic value here"
        )
    driven = robot.driven
    x_d = float(np.mean([w.position[0] for w in driven]))
    x_c = float(np.mean([w.position[0] for w in casters]))
    share = (x_c - x_g) / (x_c - x_d + mu * h)
    if not 0 < share < 1:
        return math.nan, (
            f"braking on the driven wheels alone lifts the {'casters' if share >= 1 else 'driven wheels'} "
            f"(driven-wheel load share {share:.2f} with the centre of mass {h:.3f} m high): the robot "
            "pitches over, which the sliding case does not describe"
        )
    return mu * GRAVITY * share, None


__all__ = [
    "ContactLayout",
    "CoulombTable",
    "braking_deceleration",
    "contact_layout",
    "equal_loads",
    "load_layout",
    "mass_distribution",
    "ratio_for_gain",
    "steady_twist",
    "wheel_separation_multiplier",
    "with_friction_ratio",
    "with_slip_compliance",
    "yaw_rate_gain",
]
