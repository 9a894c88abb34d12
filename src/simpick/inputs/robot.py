"""The robot description every engine loads, and the facts simpick reads from it.

Any wheeled ground robot described by a URDF (or a xacro file, expanded with the ``xacro``
package; its ``$(find PKG)`` includes resolved from the config's ``robot.packages``, without ROS)
can be studied. :func:`load_robot` reads the description once, at planning time and
in every job, and returns a :class:`RobotSpec`: the one interface through which the engines,
the controller, the IMU mount and the Coulomb model see the robot. Nothing else parses the URDF
for robot facts (an adapter may read the file :attr:`RobotSpec.urdf` for the shapes and
inertias its engine builds, as every engine's own URDF loader does).

What is found and how:

- **Wheels**: a ``continuous`` joint whose child link collides as a cylinder (its axis along the
  joint axis) or a sphere. A wheel hanging on the base through fixed joints only is *driven*; one
  below a continuous joint with a vertical axis (a swivel) is a *caster*, passive. The config may
  instead name the driven joints (``robot.wheels``: joint and side); every other wheel is passive.
- **Side and forward direction** from geometry: side is the sign of the wheel centre's y in the
  base frame; the joint axis, expressed in the base frame through every joint origin's rotation,
  gives ``axis_sign`` (+1 when a positive joint speed rolls the robot towards +x), so rotated or
  mirrored joint frames all drive the robot forward.
- **Base**: the URDF root link. A root without mass (a footprint) is fine: whenever the file is
  not already in the form every engine reads alike (xacro, meshes, massless links), it is rewritten
  (:func:`simpick.inputs.urdf.normalised_urdf`) with each link hung on a fixed joint fused into its parent: masses and
  inertias combined, box/cylinder/sphere collisions kept, visuals and mesh collisions dropped (with a
  note), into a file in the temporary folder named by its content hash. The Husky's file needs no
  rewrite and is loaded as it is.
- **Figures**: mass, centre of mass (whole robot, joints at zero), driven wheel radius, track
  (mean left minus mean right wheel y), wheelbase (front-most minus rear-most driven axle), the
  base's height above flat ground resting on its wheels, the IMU mount; each may be overridden in
  the config (``robot.overrides``); the overridden values feed the controller and the mechanics,
  the engines always simulate the description.

- **Passive suspension**: a ``revolute`` joint with finite limits and a lateral axis (a rocker or
  bogie pitching about y) between the base and driven wheels is a :class:`Suspension` joint: free,
  limited, with the description's ``<dynamics>`` damping and friction. Two such joints may be
  coupled (:class:`Coupling`): by URDF's ``<mimic>`` on the follower, or by the config's
  ``robot.couplings`` for a maker's description that leaves the linkage out (the Warthog's
  differential bar). Every engine enforces the coupling with its own constraint.

Refused, with one message naming the joint or link: prismatic, planar or floating joints, revolute
joints that hold no wheel, are unlimited or not lateral (steering, legs, arms), continuous joints
whose child has no collision, wheel axes
that are neither lateral nor (for a swivel) vertical, no driven wheels (tracks), a driven wheel
count other than 2, 4 or 6 or unequal sides, a description that is not XML.
"""

from __future__ import annotations

import logging
import math
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from simpick.errors import InputError
from simpick.inputs.urdf import (
    SNAP_TOLERANCE_DEG,
    Body,
    RigidModel,
    Tree,
    floats,
    fmt,
    inertial,
    joint_axis,
    needs_rewrite,
    normalised_urdf,
    origin,
    read_description,
    snapped_axis,
    tree_of,
    wheel_shape,
    write_cached,
)

LOG = logging.getLogger(__name__)


@dataclass(frozen=True)
class Wheel:
    """One wheel of the robot (driven or caster), in the base frame with every joint at zero."""

    joint: str  # the continuous joint it spins about
    link: str  # the joint's child link, which carries the collision
    side: str  # "left" (y > 0) or "right" (y < 0); a caster on the centre line: "centre"
    radius: float  # m, of the collision cylinder or sphere
    width: float  # m, the cylinder's length; 0.0 for a sphere
    shape: str  # "cylinder" or "sphere"
    position: tuple[float, float, float]  # wheel centre in the base frame, m
    axis_sign: int  # +1: a positive joint speed rolls the robot towards base +x; -1: towards -x
    driven: bool  # True: velocity-servoed by the controller; False: passive (a caster)
    swivel: str | None = None  # a caster's vertical continuous joint, if it has one
    mount: str | None = None  # the suspension joint nearest above the wheel (None: fixed to the base)


@dataclass(frozen=True)
class Suspension:
    """A passive suspension joint (a rocker or bogie): revolute, limited, about a lateral axis,
    between the base and driven wheels; free in every engine but for its limits, damping, friction
    and any coupling. Figures in the base frame with every joint at zero."""

    joint: str
    link: str  # its child link
    parent: str  # the link it hangs on (the base, or through fixed joints a link fixed to it)
    position: tuple[float, float, float]  # joint origin in the base frame, m
    axis: tuple[float, float, float]  # joint axis in the base frame (lateral: 0, +-1, 0)
    lower: float  # rad
    upper: float  # rad
    damping: float  # N m s/rad, the description's <dynamics damping> (0 if absent)
    friction: float  # N m, its <dynamics friction> (0 if absent)
    wheels: tuple[str, ...]  # the wheel joints hanging below it
    # what the joint carries: the child link and every link below it (wheels, nested rockers);
    # the Coulomb reference's static loads need its weight and where it acts
    mass: float = 0.0  # kg
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)  # its centre of mass in the base frame, m


@dataclass(frozen=True)
class Coupling:
    """Two suspension joints linked mechanically: ``q(joint) = multiplier * q(leader) + offset``
    (rad). A differential bar between left and right rockers is multiplier -1: one rocker turns by
    minus the other, and the chassis pitches by their mean."""

    joint: str  # the follower
    leader: str
    multiplier: float
    offset: float = 0.0
    source: str = ""  # where it was declared: "<mimic> in FILE" or "robot.couplings"


@dataclass(frozen=True)
class Skid:
    """A collision shape of the base (a skid or ball caster fixed to it) that reaches the ground
    when the robot rests on its wheels: it slides, with the friction the engines give the robot."""

    link: str
    shape: str  # "box", "sphere" or "cylinder"
    position: tuple[float, float, float]  # lowest point (its shape's centre in x, y) in the base frame, m
    clearance: float  # m above flat ground with the robot level on its wheels (<= SKID_REACH)


# skid: TurtleBot3's box caster is 0.5 mm up and touches once the robot tips onto it.
SKID_REACH = 0.005


@dataclass(frozen=True)
class RobotSpec:
    """What simpick knows of the robot; every engine adapter reads the robot only through this.

    Commands and measured wheel speeds are arrays over :attr:`driven` (joint speeds in rad/s,
    in the joint's own sign: a mirrored wheel turns at minus its neighbour's speed), ordered front
    to back, left before right (the Husky: FL, FR, RL, RR). Passive wheels (casters) are loaded
    and left free, as the description says.
    """

    urdf: Path  # the file every engine loads (the user's own, or its normalised copy)
    source: Path  # the file the config names (URDF or xacro)
    name: str  # <robot name="...">
    base_link: str  # the root link: the pose and velocity the study records are this frame's
    wheels: tuple[Wheel, ...]  # driven wheels in command order, then passive ones
    mass: float  # kg, whole robot
    com: tuple[float, float, float]  # whole robot's centre of mass in the base frame, m
    imu_link: str
    imu_mount: tuple[float, float, float]  # IMU origin in the base frame, m (axes = base axes)
    base_height: float  # base frame origin above flat ground when resting on the wheels, m
    wheel_radius: float  # m, driven wheels' (they must agree to 1 mm)
    track: float  # m, geometric: mean left minus mean right driven wheel y (not the controller's tau)
    wheelbase: float  # m, front-most minus rear-most driven wheel x (0 for two driven wheels)
    notes: tuple[str, ...] = ()  # what was assumed or dropped while reading the description
    overridden: tuple[str, ...] = ()  # figures the config set instead of the description
    skids: tuple[Skid, ...] = ()  # base shapes that reach the ground (sliding supports)
    suspension: tuple[Suspension, ...] = ()  # passive suspension joints, parents before children
    couplings: tuple[Coupling, ...] = ()  # linked suspension joints
    # the rigid bodies and moving joints, fixed-joint chains folded (for an adapter that builds the
    # robot body by body rather than through its engine's URDF loader: ODE)
    rigid: RigidModel | None = field(default=None, compare=False, repr=False)

    @property
    def driven(self) -> tuple[Wheel, ...]:
        return tuple(w for w in self.wheels if w.driven)

    @property
    def casters(self) -> tuple[Wheel, ...]:
        return tuple(w for w in self.wheels if not w.driven)

    @property
    def wheel_joints(self) -> tuple[str, ...]:
        """Driven wheel joints, in command order."""
        return tuple(w.joint for w in self.driven)

    @property
    def passive_joints(self) -> tuple[str, ...]:
        """Every continuous joint that no motor drives (caster wheels and swivels)."""
        out = []
        for w in self.casters:
            out += [w.joint] + ([w.swivel] if w.swivel else [])
        return tuple(out)

    @property
    def sides(self) -> tuple[str, ...]:
        return tuple(w.side for w in self.driven)

    @property
    def wheel_count(self) -> int:
        return len(self.driven)

    def joint_speeds(self, left, right) -> np.ndarray:
        """(..., n_driven) joint speeds, rad/s, for left and right rim speeds in m/s."""
        left, right = np.asarray(left, dtype=float), np.asarray(right, dtype=float)
        cols = [(left if w.side == "left" else right) * w.axis_sign / w.radius for w in self.driven]
        return np.stack(np.broadcast_arrays(*cols), axis=-1)

    def rim_speeds(self, joint_speeds) -> np.ndarray:
        """(..., n_driven) forward rim speeds, m/s, from joint speeds (the inverse of the above)."""
        signs = np.array([w.axis_sign * w.radius for w in self.driven])
        return np.asarray(joint_speeds, dtype=float) * signs

    def side_mean(self, joint_speeds, side: str) -> np.ndarray:
        """Mean forward-signed angular speed (rad/s) of one side's driven wheels."""
        cols = [i for i, w in enumerate(self.driven) if w.side == side]
        signs = np.array([self.driven[i].axis_sign for i in cols], dtype=float)
        return (np.asarray(joint_speeds, dtype=float)[..., cols] * signs).mean(axis=-1)


def _suspension_joint(tree: Tree, jname: str, where: str) -> Suspension | None:
    """The joint as a passive suspension joint, or None when it is not one (see the module docstring)."""
    j = tree.joints[jname]
    if j.get("type") != "revolute":
        return None
    child = j.find("child").get("link")
    below = [k for k in _subtree_joints(tree, child) if tree.joints[k].get("type") == "continuous"]
    limit = j.find("limit")
    if not below or limit is None:
        return None
    lower, upper = (float(limit.get(k, "0")) for k in ("lower", "upper"))
    if not (math.isfinite(lower) and math.isfinite(upper) and lower < upper):
        return None
    _, rot = tree.pose[child]
    axis = rot @ joint_axis(j, f"{where}: joint {jname!r}")
    if abs(abs(axis[1]) - 1) > 1e-3:
        return None
    dynamics = j.find("dynamics")
    position, _ = tree.pose[child]
    mass, moment = 0.0, np.zeros(3)
    for link in [child] + [tree.joints[k].find("child").get("link") for k in _subtree_joints(tree, child)]:
        inert = inertial(tree.links[link], where)
        if inert is not None:
            p, r = tree.pose[link]
            mass += inert[0]
            moment += inert[0] * (p + r @ inert[1])
    return Suspension(
        joint=jname,
        link=child,
        parent=j.find("parent").get("link"),
        position=tuple(float(v) for v in position),
        axis=tuple(float(round(v, 12)) + 0.0 for v in axis),
        lower=lower,
        upper=upper,
        damping=float(dynamics.get("damping", "0")) if dynamics is not None else 0.0,
        friction=float(dynamics.get("friction", "0")) if dynamics is not None else 0.0,
        wheels=tuple(below),
        mass=float(mass),
        com=tuple(float(v) for v in (moment / mass if mass > 0 else position)),
    )


def _find_wheels(tree: Tree, where: str, declared: Mapping[str, str] | None) -> tuple[list[Wheel], list[str]]:
    notes = []
    wheels = []
    for jname, j in tree.joints.items():
        kind = j.get("type")
        child = j.find("child").get("link")
        jw = f"{where}: joint {jname!r}"
        if kind == "fixed":
            continue
        if kind == "revolute" and _suspension_joint(tree, jname, where) is not None:
            continue
        if kind != "continuous":
            holds_wheel = any(tree.joints[k].get("type") == "continuous" for k in _subtree_joints(tree, child))
            what = "a steered or sprung wheel" if holds_wheel else "a steering, leg or arm joint"
            rocker = holds_wheel and kind == "revolute"
            raise InputError(
                jw,
                f"is {kind}: {what}, which simpick does not simulate (it studies wheeled robots: "
                "driven and caster wheels on continuous joints, passive rockers on limited revolute "
                "joints about a lateral axis)",
                "make it a fixed joint in the description if it does not move while driving"
                + (", or give a rocker finite <limit>s and a lateral axis" if rocker else ""),
            )
        axis_local = joint_axis(j, jw)
        snap = snapped_axis(axis_local)
        if snap is not None and snap[1] > 1e-7:
            tree.notes.append(
                f"joint {jname!r}: axis {j.find('axis').get('xyz')!r} is {snap[1]:.3f} deg from "
                f"{fmt(snap[0])} (within {SNAP_TOLERANCE_DEG} deg), snapped"
            )
            axis_local = tree.axes[jname] = snap[0]
        _, rot = tree.pose[child]
        axis = rot @ axis_local  # in the base frame
        link = tree.links[child]
        if abs(axis[2]) > 1 - 1e-3:  # a vertical continuous joint: a caster's swivel
            if not any(tree.joints[k].get("type") == "continuous" for k in _subtree_joints(tree, child)):
                raise InputError(jw, "spins about a vertical axis and carries no wheel: not a wheel or a caster swivel")
            continue
        shape = wheel_shape(link, axis_local, jw)
        if shape is None:
            raise InputError(
                jw,
                f"is continuous but its child link {child!r} has no cylinder or sphere collision: "
                "a wheel needs one for the engines to roll on",
                "add a <collision> with a cylinder (axis along the joint) or a sphere",
            )
        if abs(axis[2]) > 1e-3 or abs(axis[0]) > 1e-3:
            raise InputError(
                jw,
                f"spins about {np.round(axis, 3).tolist()} in the base frame: a wheel must spin "
                "about the base's y axis (a steered, cambered or omni wheel is not supported)",
            )
        kind_, radius, width = shape
        position, _ = tree.pose[child]
        # rolling without slip: the base moves at r w (a x z) for joint speed w about a
        axis_sign = 1 if axis[1] > 0 else -1
        swivel = mount = None
        parent = j.find("parent").get("link")
        link_up = parent
        while link_up in tree.child_joint:
            pj = tree.child_joint[link_up]
            if pj.get("type") == "continuous":
                swivel = pj.get("name")
                break
            if pj.get("type") == "revolute" and mount is None:
                mount = pj.get("name")
            link_up = pj.find("parent").get("link")
        y = float(position[1])
        side = "left" if y > 1e-3 else "right" if y < -1e-3 else "centre"
        if declared is not None:
            driven = jname in declared
            if driven:
                side = declared[jname]
        else:
            # on a swivel, or on the centre line (a ball caster's spinning sphere): passive
            driven = swivel is None and side != "centre"
        if driven and side == "centre":
            raise InputError(
                jw,
                f"a driven wheel on the centre line (y = {y:.4f} m): its side is unknown",
                "declare it under robot.wheels with its side",
            )
        wheels.append(
            Wheel(
                joint=jname,
                link=child,
                side=side,
                radius=radius,
                width=width,
                shape=kind_,
                position=tuple(float(v) for v in position),
                axis_sign=axis_sign,
                driven=driven,
                swivel=swivel,
                mount=mount,
            )
        )
    if declared is not None:
        missing = sorted(set(declared) - {w.joint for w in wheels})
        if missing:
            raise InputError(
                "robot.wheels", f"joints {missing} are not wheel joints of {where} (found: {[w.joint for w in wheels]})"
            )
    driven = [w for w in wheels if w.driven]
    if not driven:
        raise InputError(
            where,
            "no driven wheel found (a continuous joint on the base whose child collides as "
            "a cylinder or sphere); tracked and legged robots are not supported",
            "declare the driven joints under robot.wheels if the description has them",
        )
    left = [w for w in driven if w.side == "left"]
    right = [w for w in driven if w.side == "right"]
    if len(driven) not in (2, 4, 6) or len(left) != len(right):
        raise InputError(
            where,
            f"{len(left)} left and {len(right)} right driven wheels "
            f"({[w.joint for w in driven]}): simpick drives 2, 4 or 6 wheels, as many on each side",
        )
    radii = [w.radius for w in driven]
    if max(radii) - min(radii) > 1e-3:
        raise InputError(
            where,
            f"driven wheel radii differ ({dict((w.joint, w.radius) for w in driven)}): "
            "a differential controller needs one radius",
        )
    # command order: front to back, left before right
    driven.sort(key=lambda w: (-round(w.position[0], 4), w.side != "left"))
    return driven + [w for w in wheels if not w.driven], notes


def _find_skids(tree: Tree, where: str, base_height: float) -> tuple[Skid, ...]:
    """Collision shapes of links rigidly fixed to the base whose lowest point, the robot level on
    its wheels, is within SKID_REACH of the ground."""

    def on_base(link: str) -> bool:
        while link in tree.child_joint:
            joint = tree.child_joint[link]
            if joint.get("type") != "fixed":
                return False
            link = joint.find("parent").get("link")
        return True

    found = []
    for name, link in tree.links.items():
        if not on_base(name):
            continue
        p, r = tree.pose[name]
        for collision in link.findall("collision"):
            geometry = collision.find("geometry")
            if geometry is None:
                continue
            xyz, rot = origin(collision, f"{where}: link {name!r} collision")
            centre, m = p + r @ xyz, r @ rot
            box, sph, cyl = geometry.find("box"), geometry.find("sphere"), geometry.find("cylinder")
            if box is not None:
                half = floats(box.get("size"), 3, f"{where}: link {name!r} box size") / 2
                low, kind = centre[2] - float(np.abs(m[2]) @ half), "box"
            elif sph is not None:
                low, kind = centre[2] - float(sph.get("radius")), "sphere"
            elif cyl is not None:
                c = abs(m[2, 2])
                low = centre[2] - (
                    c * float(cyl.get("length")) / 2 + math.sqrt(max(0.0, 1 - c * c)) * float(cyl.get("radius"))
                )
                kind = "cylinder"
            else:
                continue
            clearance = low + base_height
            if clearance <= SKID_REACH:
                found.append(
                    Skid(
                        link=name,
                        shape=kind,
                        position=(float(centre[0]), float(centre[1]), float(low)),
                        clearance=float(clearance),
                    )
                )
    return tuple(found)


def _subtree_joints(tree: Tree, link: str) -> list[str]:
    out, stack = [], [link]
    while stack:
        for j in tree.children[stack.pop()]:
            out.append(j.get("name"))
            stack.append(j.find("child").get("link"))
    return out


def _rigid_model(
    tree: Tree, where: str, wheels: list[Wheel], snapped_axes: dict, suspension: tuple[Suspension, ...] = ()
) -> RigidModel:
    """The bodies and moving joints of ``tree``: each moving link with every link hung on it by
    fixed joints folded in (breadth first, in the description's joint order)."""

    def body_of(link: str) -> tuple[str, np.ndarray, np.ndarray]:
        """The moving link ``link`` belongs to, and ``link``'s frame in that link's frame."""
        pos, rot = np.zeros(3), np.eye(3)
        chain = []
        while link in tree.child_joint and tree.child_joint[link].get("type") == "fixed":
            chain.append(tree.child_joint[link])
            link = tree.child_joint[link].find("parent").get("link")
        for joint in reversed(chain):
            xyz, r = tree.origins[joint.get("name")]
            pos, rot = pos + rot @ xyz, rot @ r
        return link, pos, rot

    def body(link_name: str) -> Body:
        part = Body(link_name)
        queue = [(link_name, np.zeros(3), np.eye(3))]
        while queue:
            name, pos, rot = queue.pop(0)
            part.add(tree.links[name], pos, rot, where)
            for joint in tree.children[name]:
                if joint.get("type") == "fixed":
                    xyz, r = tree.origins[joint.get("name")]
                    queue.append((joint.find("child").get("link"), pos + rot @ xyz, rot @ r))
        return part

    def mount(joint) -> tuple[str, np.ndarray, np.ndarray, np.ndarray]:
        name = joint.get("name")
        parent, pos, rot = body_of(joint.find("parent").get("link"))
        xyz, r = tree.origins[name]
        if parent != joint.find("parent").get("link"):  # hung on a fixed chain: the chain folded in
            xyz, r = pos + rot @ xyz, rot @ r
        axis = snapped_axes.get(name)
        return parent, xyz, r, axis if axis is not None else joint_axis(joint, f"{where}: joint {name!r}")

    rockers, at = [], {}
    for sus in suspension:  # parents before children
        parent, xyz, r, axis = mount(tree.joints[sus.joint])
        at[sus.link] = len(rockers)
        rockers.append((xyz, r, axis, body(sus.link), at.get(parent, -1), sus))
    driven, wheel_parents = [], []
    for wheel in (w for w in wheels if w.driven):
        parent, xyz, r, axis = mount(tree.joints[wheel.joint])
        driven.append((xyz, r, axis, body(wheel.link)))
        wheel_parents.append(at.get(parent, -1))
    passive, index = [], {}
    moving = [w for w in wheels if not w.driven]
    names = []
    for w in moving:
        names += [w.joint] + ([w.swivel] if w.swivel else [])
    for name in names[::-1]:  # (caster joint, its swivel): the swivel first
        joint = tree.joints[name]
        parent, xyz, r, axis = mount(joint)
        if parent != tree.base and parent not in index:
            raise InputError(
                f"{where}: joint {name!r}", f"hangs on {parent!r}, which is neither the base nor a caster's swivel link"
            )
        child = joint.find("child").get("link")
        index[child] = len(passive)
        passive.append((xyz, r, axis, body(child), -1 if parent == tree.base else index[parent]))
    return RigidModel(body(tree.base), tuple(driven), tuple(passive), tuple(rockers), tuple(wheel_parents))


OVERRIDABLE = ("wheel_radius", "track", "wheelbase", "mass", "com", "base_height", "imu_mount")


def _couplings(
    tree: Tree, where: str, suspension: tuple[Suspension, ...], declared: list[Mapping[str, Any]] | None
) -> tuple[Coupling, ...]:
    """The couplings the description's <mimic> elements and the config's robot.couplings declare."""
    names = {s.joint for s in suspension}
    found: list[Coupling] = []
    for jname, j in tree.joints.items():
        mimic = j.find("mimic")
        if mimic is None:
            continue
        found.append(
            Coupling(
                joint=jname,
                leader=mimic.get("joint", ""),
                multiplier=float(mimic.get("multiplier", "1")),
                offset=float(mimic.get("offset", "0")),
                source=f"<mimic> in {where}",
            )
        )
    for i, c in enumerate(declared or ()):
        found.append(
            Coupling(
                joint=str(c["joint"]),
                leader=str(c["leader"]),
                multiplier=float(c.get("multiplier", -1.0)),
                offset=float(c.get("offset", 0.0)),
                source=f"robot.couplings[{i}]",
            )
        )
    seen: set[str] = set()
    for c in found:
        field_ = c.source if c.source.startswith("robot.") else f"{where}: joint {c.joint!r} <mimic>"
        bad = [j for j in (c.joint, c.leader) if j not in names]
        if bad:
            raise InputError(
                field_,
                f"couples {bad}, which are not passive suspension joints of {where} (those are: {sorted(names)})",
                "couple two limited revolute rocker joints",
            )
        if c.joint == c.leader or not math.isfinite(c.multiplier) or c.multiplier == 0:
            raise InputError(field_, f"{c.joint!r} follows {c.leader!r} x {c.multiplier}: not a linkage")
        for j in (c.joint, c.leader):
            if j in seen:
                raise InputError(field_, f"joint {j!r} is coupled twice", "declare each linkage once")
            seen.add(j)
    return tuple(found)


def load_robot(
    urdf: str | Path,
    *,
    imu_link: str | None = None,
    wheels: Mapping[str, str] | None = None,
    overrides: Mapping[str, Any] | None = None,
    couplings: list[Mapping[str, Any]] | None = None,
    packages: Mapping[str, str | Path] | None = None,
) -> RobotSpec:
    """Read any wheeled robot's URDF or xacro; see the module docstring for the rules.

    ``imu_link``: the link whose origin is the IMU (default: the first link with "imu" in its
    name, else the base). ``wheels``: driven joint -> side ("left"/"right"), instead of finding
    them. ``overrides``: figures from :data:`OVERRIDABLE` replacing the description's.
    ``couplings``: suspension linkages the description leaves out (joint, leader, multiplier, offset).
    ``packages``: package name -> folder, answering a xacro's ``$(find PKG)`` (no ROS needed).
    """
    source = Path(urdf)
    where = str(source)
    root = read_description(source, packages)
    tree = tree_of(root, where)
    if wheels is not None:
        bad = {j: s for j, s in wheels.items() if s not in ("left", "right")}
        if bad:
            raise InputError("robot.wheels", f"sides must be 'left' or 'right', got {bad}")
    found, notes = _find_wheels(tree, where, wheels)
    notes = tree.notes + notes
    # suspension joints, parents before children (the tree's breadth order from the base)
    order = {}
    queue = [tree.base]
    while queue:
        link = queue.pop(0)
        for j in tree.children[link]:
            order[j.get("name")] = len(order)
            queue.append(j.find("child").get("link"))
    suspension = tuple(
        sorted(
            (s for s in (_suspension_joint(tree, n, where) for n in tree.joints) if s is not None),
            key=lambda s: order[s.joint],
        )
    )
    linked = _couplings(tree, where, suspension, couplings)

    # mass and centre of mass of the whole robot, joints at zero
    mass, moment = 0.0, np.zeros(3)
    for name, link in tree.links.items():
        inert = inertial(link, where)
        if inert is None:
            continue
        p, r = tree.pose[name]
        mass += inert[0]
        moment += inert[0] * (p + r @ inert[1])
    if mass <= 0:
        raise InputError(where, "no link has a mass: the robot's weight is unknown", "add <inertial> blocks")
    com = moment / mass
    # every rigid body an engine builds (the base, each moving link, with what is fixed to it) needs
    # a mass: Bullet would give a massless one 1 kg, ODE refuses it
    body_mass: dict[str, float] = {}
    for name, link in tree.links.items():
        body = name
        while body in tree.child_joint and tree.child_joint[body].get("type") == "fixed":
            body = tree.child_joint[body].find("parent").get("link")
        inert = inertial(link, where)
        body_mass[body] = body_mass.get(body, 0.0) + (inert[0] if inert else 0.0)
    massless = sorted(b for b, m in body_mass.items() if m <= 0)
    if massless:
        raise InputError(
            where,
            f"links {massless} (with the links fixed to them) have no mass: each moving part and the base needs one",
            "add an <inertial> with the part's mass",
        )

    if imu_link is None:
        imu_link = next((n for n in tree.links if "imu" in n.lower()), tree.base)
    elif imu_link not in tree.links:
        raise InputError("robot.imu_link", f"{imu_link!r} is not a link of {where} (links: {sorted(tree.links)})")
    imu_pos, imu_rot = tree.pose[imu_link]
    if not np.allclose(imu_rot, np.eye(3), atol=1e-6):
        notes.append(f"IMU link {imu_link!r} is rotated relative to the base; the simulated IMU's axes are the base's")

    driven = [w for w in found if w.driven]
    radius = driven[0].radius
    # resting height: the lowest point of any wheel on the ground
    base_height = max(w.radius - w.position[2] for w in found)
    for w in found:
        gap = (w.radius - w.position[2]) - base_height
        if gap < -2e-3:
            notes.append(f"wheel {w.joint!r} clears the ground by {-gap * 1000:.1f} mm at rest")
    left = [w.position[1] for w in driven if w.side == "left"]
    right = [w.position[1] for w in driven if w.side == "right"]
    xs = [w.position[0] for w in driven]
    figures = {
        "wheel_radius": radius,
        "track": float(np.mean(left) - np.mean(right)),
        "wheelbase": float(max(xs) - min(xs)),
        "mass": float(mass),
        "com": tuple(float(c) for c in com),
        "base_height": float(base_height),
        "imu_mount": tuple(float(c) for c in imu_pos),
    }
    overridden = []
    for key, value in (overrides or {}).items():
        if value is None:
            continue
        if key not in OVERRIDABLE:
            raise InputError(f"robot.overrides.{key}", f"unknown figure; overridable: {list(OVERRIDABLE)}")
        figures[key] = tuple(float(v) for v in value) if key in ("com", "imu_mount") else float(value)
        overridden.append(key)

    skids = _find_skids(tree, where, float(base_height))
    for s in skids:
        notes.append(
            f"link {s.link!r}: a {s.shape} {s.clearance * 1000:.1f} mm above the ground at rest, a "
            "sliding support (skid) with the ground's friction"
        )
    file = source
    for note in tree.notes:
        LOG.warning("%s: %s", where, note)
    # the rigid bodies of the file every engine loads: the description, or its normalised copy
    rigid = _rigid_model(tree, where, found, tree.axes, suspension)
    if needs_rewrite(root, source, tree):
        text, more = normalised_urdf(root, tree, root.get("name") or source.stem)
        notes += more
        file = write_cached(text)
        notes.append(f"loaded through a normalised copy ({file.name}): fixed links fused, visuals dropped")
        rigid = _rigid_model(tree_of(ET.fromstring(text), str(file)), str(file), found, {}, suspension)
    return RobotSpec(
        urdf=file,
        source=source,
        name=root.get("name") or source.stem,
        base_link=tree.base,
        wheels=tuple(found),
        imu_link=imu_link,
        notes=tuple(notes),
        overridden=tuple(overridden),
        skids=skids,
        suspension=suspension,
        couplings=linked,
        rigid=rigid,
        **figures,
    )


def load_from_config(robot: Mapping[str, Any]) -> RobotSpec:
    """The robot as the config's ``robot`` block names it (urdf, imu_link, wheels, overrides,
    couplings, packages)."""
    wheels = robot.get("wheels")
    if wheels is not None:
        wheels = {w["joint"]: w["side"] for w in wheels}
    overrides = {k: v for k, v in (robot.get("overrides") or {}).items() if v is not None}
    return load_robot(
        robot["urdf"],
        imu_link=robot.get("imu_link"),
        wheels=wheels,
        overrides=overrides,
        couplings=robot.get("couplings"),
        packages=robot.get("packages"),
    )


__all__ = [
    "OVERRIDABLE",
    "Coupling",
    "Suspension",
    "RobotSpec",
    "SKID_REACH",
    "SNAP_TOLERANCE_DEG",
    "Skid",
    "Wheel",
    "load_from_config",
    "load_robot",
]
