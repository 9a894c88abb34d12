"""Reading a robot description into a :class:`~simpick.inputs.robot.spec.RobotSpec`: the one entry
point (:func:`load_robot`, and :func:`load_from_config` for the config's ``robot`` block).

It puts the parts found in the description together with the whole robot's figures (mass, centre
of mass, wheel radius, track, wheelbase, resting height, IMU mount), applies the config's
overrides and, where engines would read the file differently, loads it through a normalised copy."""

from __future__ import annotations

import logging
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from simpick.errors import InputError
from simpick.inputs.robot.parts import _couplings, _find_skids, _find_wheels, _suspension_joint
from simpick.inputs.robot.rigid import _rigid_model
from simpick.inputs.robot.spec import RobotSpec
from simpick.inputs.urdf import inertial, needs_rewrite, normalised_urdf, read_description, tree_of, write_cached

LOG = logging.getLogger(__package__)  # the package's name, as every warning of the robot reader


OVERRIDABLE = ("wheel_radius", "track", "wheelbase", "mass", "com", "base_height", "imu_mount")


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
