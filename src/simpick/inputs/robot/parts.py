"""Finding the moving parts of a parsed description: the wheels (driven or caster, their side and
forward sign), the passive suspension joints, their couplings and the base's skids.

Each finder reads the joint tree and either returns records or refuses the description with a
message naming the joint or link; keeping them together keeps every rule of what simpick accepts
(see :mod:`simpick.inputs.robot`) in one module, apart from the figures computed from them."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from simpick.errors import InputError
from simpick.inputs.robot.spec import SKID_REACH, Coupling, Skid, Suspension, Wheel
from simpick.inputs.urdf import (
    SNAP_TOLERANCE_DEG,
    Tree,
    floats,
    fmt,
    inertial,
    joint_axis,
    origin,
    snapped_axis,
    wheel_shape,
)


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
