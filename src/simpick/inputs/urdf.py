"""Reading a URDF (or xacro) description: its link tree with every joint's origin, rounded right
angles snapped (:data:`SNAP_TOLERANCE_DEG`), the rigid bodies an engine builds (fixed-joint chains
folded), and the normalised copy every engine loads when the file is not already in a form they all
read alike. :mod:`simpick.inputs.robot` reads the robot's facts from this.
"""

from __future__ import annotations

import hashlib
import math
import os
import tempfile
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from simpick.errors import InputError


def floats(text: str | None, n: int, where: str, default: float = 0.0) -> np.ndarray:
    if text is None:
        return np.full(n, default)
    try:
        values = [float(v) for v in text.split()]
    except ValueError:
        values = []
    if len(values) != n:
        raise InputError(where, f"expected {n} numbers, got {text!r}")
    return np.asarray(values)


def rpy_matrix(rpy) -> np.ndarray:
    """URDF rpy (fixed axes x, then y, then z) -> rotation matrix."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def matrix_rpy(m: np.ndarray) -> np.ndarray:
    """Rotation matrix -> URDF rpy (the inverse of :func:`rpy_matrix`)."""
    pitch = math.asin(max(-1.0, min(1.0, -m[2, 0])))
    if abs(m[2, 0]) < 1 - 1e-12:
        roll, yaw = math.atan2(m[2, 1], m[2, 2]), math.atan2(m[1, 0], m[0, 0])
    else:  # gimbal lock: roll folded into yaw
        roll, yaw = 0.0, math.atan2(-m[0, 1], m[1, 1])
    return np.array([roll, pitch, yaw])


def origin(element, where: str) -> tuple[np.ndarray, np.ndarray]:
    """(xyz, rotation) of an element's <origin> child; identity when absent."""
    o = element.find("origin") if element is not None else None
    if o is None:
        return np.zeros(3), np.eye(3)
    return floats(o.get("xyz"), 3, f"{where} origin xyz"), rpy_matrix(floats(o.get("rpy"), 3, f"{where} origin rpy"))


def joint_axis(joint, where: str) -> np.ndarray:
    """A joint's unit axis (URDF default x when absent); a zero axis is an InputError naming ``where``."""
    a = joint.find("axis")
    axis = floats(a.get("xyz") if a is not None else None, 3, f"{where} axis", 0.0)
    if a is None:
        axis = np.array([1.0, 0.0, 0.0])  # the URDF default
    norm = np.linalg.norm(axis)
    if norm == 0:
        raise InputError(where, "the joint axis is zero")
    return axis / norm


# Real descriptions carry rounded angles (rpy="3.14 0 0" for pi, 1.5708 for pi/2): a joint origin's
# rotation or a joint axis within this of a right-angle one is snapped to it and reported, so the
# rounding of a maker's file never decides whether simpick can study the robot.
SNAP_TOLERANCE_DEG = 0.5


def snapped_rotation(rot: np.ndarray) -> tuple[np.ndarray, float] | None:
    """The right-angle rotation (a signed permutation) within SNAP_TOLERANCE_DEG of ``rot`` and the
    angle between them (degrees), or None when there is none."""
    target = np.round(rot)
    if not (np.allclose(target @ target.T, np.eye(3)) and np.linalg.det(target) > 0):
        return None
    angle = math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(target.T @ rot) - 1) / 2))))
    return (target, angle) if angle <= SNAP_TOLERANCE_DEG else None


def snapped_axis(axis: np.ndarray) -> tuple[np.ndarray, float] | None:
    """The coordinate axis (signed) within SNAP_TOLERANCE_DEG of the unit ``axis``, and the angle."""
    i = int(np.argmax(np.abs(axis)))
    target = np.zeros(3)
    target[i] = math.copysign(1.0, axis[i])
    angle = math.degrees(math.acos(max(-1.0, min(1.0, float(target @ axis)))))
    return (target, angle) if angle <= SNAP_TOLERANCE_DEG else None


@dataclass
class Tree:
    root: Any
    links: dict
    joints: dict  # name -> element
    child_joint: dict  # child link -> joint element
    children: dict  # link -> [joint elements]
    base: str
    pose: dict  # link -> (position, rotation) in the base frame, joints at zero
    origins: dict  # joint name -> (xyz, rotation) of its origin, a rounded right angle snapped
    notes: list  # what was snapped
    axes: dict = field(default_factory=dict)  # joint name -> its snapped axis (wheels only, _find_wheels)


def tree_of(root, where: str) -> Tree:
    links = {lk.get("name"): lk for lk in root.findall("link")}
    joints = {j.get("name"): j for j in root.findall("joint")}
    if not links:
        raise InputError(where, "the description has no <link>: not a robot URDF")
    child_joint, children = {}, {name: [] for name in links}
    for name, j in joints.items():
        parent, child = j.find("parent"), j.find("child")
        if parent is None or child is None or parent.get("link") not in links or child.get("link") not in links:
            raise InputError(f"{where}: joint {name!r}", "its parent or child link is missing from the description")
        child_joint[child.get("link")] = j
        children[parent.get("link")].append(j)
    roots = [name for name in links if name not in child_joint]
    if len(roots) != 1:
        raise InputError(where, f"expected one root link, found {roots}")
    origins, notes = {}, []
    for name, j in joints.items():
        xyz, rot = origin(j, f"{where}: joint {name!r}")
        snap = snapped_rotation(rot)
        if snap is not None and snap[1] > 1e-7:
            rot = snap[0]
            notes.append(
                f"joint {name!r}: origin rpy {j.find('origin').get('rpy')!r} is {snap[1]:.3f} deg from a "
                f"right angle (within {SNAP_TOLERANCE_DEG} deg), snapped to rpy "
                f"{fmt(np.round(matrix_rpy(rot), 6))}"
            )
        origins[name] = (xyz, rot)
    pose = {roots[0]: (np.zeros(3), np.eye(3))}
    stack = [roots[0]]
    while stack:
        name = stack.pop()
        p, r = pose[name]
        for j in children[name]:
            xyz, rot = origins[j.get("name")]
            child = j.find("child").get("link")
            pose[child] = (p + r @ xyz, r @ rot)
            stack.append(child)
    return Tree(root, links, joints, child_joint, children, roots[0], pose, origins, notes)


def inertial(link, where: str) -> tuple[float, np.ndarray, np.ndarray] | None:
    """(mass, com, inertia about com) in the link frame, or None."""
    element = link.find("inertial")
    if element is None or element.find("mass") is None:
        return None
    mass = float(element.find("mass").get("value", "0"))
    xyz, rot = origin(element, f"{where}: link {link.get('name')!r} inertial")
    t = element.find("inertia")
    g = {k: float(t.get(k, 0.0)) if t is not None else 0.0 for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
    local = np.array([[g["ixx"], g["ixy"], g["ixz"]], [g["ixy"], g["iyy"], g["iyz"]], [g["ixz"], g["iyz"], g["izz"]]])
    return mass, xyz, rot @ local @ rot.T


def wheel_shape(link, axis: np.ndarray, where: str) -> tuple[str, float, float] | None:
    """("cylinder"|"sphere", radius, width) of a link's wheel collision, None if it has none;
    refuses a cylinder not aligned with the joint axis (``axis`` in the link frame)."""
    for collision in link.findall("collision"):
        geometry = collision.find("geometry")
        if geometry is None:
            continue
        _, rot = origin(collision, where)
        cyl, sph = geometry.find("cylinder"), geometry.find("sphere")
        if cyl is not None:
            cyl_axis = rot @ np.array([0.0, 0.0, 1.0])
            if abs(abs(cyl_axis @ axis) - 1) > 1e-3:
                raise InputError(
                    where,
                    f"wheel link {link.get('name')!r}: its collision cylinder's axis "
                    f"{np.round(cyl_axis, 3).tolist()} is not the joint axis {np.round(axis, 3).tolist()}",
                )
            return "cylinder", float(cyl.get("radius")), float(cyl.get("length"))
        if sph is not None:
            return "sphere", float(sph.get("radius")), 0.0
    return None


def has_collision(link) -> bool:
    return link.find("collision") is not None


@dataclass
class Body:
    """A rigid body as an engine builds it, in the frame of its (main) URDF link: a moving link
    with every link hung on it by fixed joints folded in."""

    link: str
    mass: float = 0.0
    com: np.ndarray = field(default_factory=lambda: np.zeros(3))
    inertia: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))  # about com, link axes
    shapes: list = field(default_factory=list)  # (kind, dims, position, rotation) in the link frame

    def add(self, link, position: np.ndarray, rotation: np.ndarray, where: str) -> None:
        """Fold ``link`` (placed at position/rotation in this body's frame) into the body."""
        name = f"{where}: link {link.get('name')!r}"
        inertial = link.find("inertial")
        if inertial is not None and inertial.find("mass") is not None:
            xyz, rot = origin(inertial, f"{name} inertial")
            m = float(inertial.find("mass").get("value"))
            t = inertial.find("inertia")
            g = {k: float(t.get(k, 0.0)) if t is not None else 0.0 for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
            local = np.array(
                [[g["ixx"], g["ixy"], g["ixz"]], [g["ixy"], g["iyy"], g["iyz"]], [g["ixz"], g["iyz"], g["izz"]]]
            )
            r = rotation @ rot
            self._combine(m, position + rotation @ xyz, r @ local @ r.T)
        for collision in link.findall("collision"):
            geometry = collision.find("geometry")
            if geometry is None:
                continue
            xyz, rot = origin(collision, f"{name} collision")
            box, cyl, sph = geometry.find("box"), geometry.find("cylinder"), geometry.find("sphere")
            if box is not None:
                shape = ("box", tuple(floats(box.get("size"), 3, f"{name} box size")))
            elif cyl is not None:
                shape = ("cylinder", (float(cyl.get("radius")), float(cyl.get("length"))))
            elif sph is not None:
                shape = ("sphere", (float(sph.get("radius")),))
            else:  # a mesh: dropped, as normalised_urdf drops it (with its note)
                continue
            self.shapes.append((*shape, position + rotation @ xyz, rotation @ rot))

    def _combine(self, m: float, c: np.ndarray, inertia: np.ndarray) -> None:
        total = self.mass + m
        com = (self.mass * self.com + m * c) / total

        def shifted(mass, at, tensor):
            d = at - com
            return tensor + mass * (d @ d * np.eye(3) - np.outer(d, d))

        self.inertia = shifted(self.mass, self.com, self.inertia) + shifted(m, c, inertia)
        self.mass, self.com = total, com


@dataclass(frozen=True)
class RigidModel:
    """The robot as rigid bodies and moving joints, every fixed-joint chain folded into the moving
    link above it (its base included): what an engine that builds bodies itself needs."""

    chassis: Body  # the base with everything fixed to it
    # driven wheels in command order: (joint position in the chassis frame, joint rotation, axis
    # in the wheel link frame, Body)
    wheels: tuple
    # every other moving link (casters, swivels), parents before children: (joint position and
    # rotation in the parent body's frame, axis, Body, parent: -1 the chassis, else an index into this)
    passive: tuple = ()
    # passive suspension links (rockers), parents before children: (joint position and rotation in
    # the parent body's frame, axis, Body, parent: -1 the chassis, else an index into this,
    # simpick.inputs.robot.Suspension)
    suspension: tuple = ()
    # per driven wheel (command order), the body it hangs on: -1 the chassis, else an index into suspension
    wheel_parents: tuple = ()


# A base collision whose lowest point is within this of the ground (robot level on its wheels) is a


# --- reading -------------------------------------------------------------------------------


PACKAGES_FIX = (
    "give each package the description names in $(find PKG) as robot.packages: {PKG: FOLDER} in the config, "
    "FOLDER the package's own folder (the one holding its urdf/ and meshes/ folders)"
)


@contextmanager
def _packages_found(packages: Mapping[str, str | Path], where: str):
    """xacro's ``$(find PKG)`` (and ``find()`` in ``$(eval)``) answered from ``packages`` instead of a ROS
    installation: xacro resolves both through ``xacro.substitution_args._eval_find`` (ament_index in
    xacro 2), which is replaced for the expansion and restored after. A package not in ``packages``
    is one InputError naming robot.packages."""
    from xacro import substitution_args

    unknown: list[InputError] = []

    def find(package: str) -> str:
        if package not in packages:
            unknown.append(
                InputError(
                    "robot.packages",
                    f"{where} includes $(find {package}), and robot.packages gives no folder for {package!r} "
                    f"(it gives: {sorted(packages) or 'none'})",
                    PACKAGES_FIX,
                )
            )
            raise unknown[-1]
        return str(Path(packages[package]).resolve())

    saved = substitution_args._eval_find, substitution_args._eval_dict.get("find")
    substitution_args._eval_find = substitution_args._eval_dict["find"] = find
    try:
        yield
    except Exception:
        if unknown:  # xacro may wrap the error in its own: the package's line, not xacro's
            raise unknown[0] from None
        raise
    finally:
        substitution_args._eval_find, substitution_args._eval_dict["find"] = saved


def read_description(path: str | Path, packages: Mapping[str, str | Path] | None = None) -> ET.Element:
    """The description's XML root; a xacro file (``.xacro`` or a root holding xacro tags) is
    expanded first, its ``$(find PKG)`` answered from ``packages`` (package name -> folder: the
    config's robot.packages; no ROS installation is needed or read). Anything unreadable raises
    InputError naming the file (or robot.packages, for a package it names)."""
    path = Path(path)
    packages = dict(packages or {})
    for name, folder in packages.items():
        if not Path(folder).is_dir():
            raise InputError(
                f"robot.packages.{name}",
                f"{folder} is not a folder",
                "give the package's folder (relative to the folder snakemake runs in, or absolute)",
            )
    try:
        text = path.read_text()
    except OSError as exc:
        raise InputError(str(path), f"cannot read the robot description: {exc}") from None
    if path.suffix == ".xacro" or "xmlns:xacro" in text:
        try:
            import xacro
        except ImportError:
            raise InputError(
                str(path), "is a xacro file and the xacro package is not installed", "pip install xacro"
            ) from None
        try:
            with _packages_found(packages, str(path)):
                text = xacro.process_file(str(path)).toprettyxml(indent="  ")
        except InputError:
            raise
        except Exception as exc:  # xacro raises its own and plain exceptions for bad input
            message = str(exc)
            inside = [n for n, folder in packages.items() if f"{Path(folder).resolve()}{os.sep}" in message]
            if inside:  # a file the description expects in a package folder is not there
                raise InputError(
                    f"robot.packages.{inside[0]}",
                    f"{path}: xacro could not expand it: {message}",
                    f"point robot.packages.{inside[0]} to the folder of the package {inside[0]!r} that holds "
                    "the files the description includes",
                ) from None
            if "find" in message and ("ament" in message or "package" in message.lower()):
                raise InputError(
                    "robot.packages", f"{path}: xacro could not expand it: {message}", PACKAGES_FIX
                ) from None
            raise InputError(str(path), f"xacro could not expand it: {message}") from None
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise InputError(
            str(path), f"cannot read the robot description: not XML ({exc})", "point robot.urdf to a URDF or xacro file"
        ) from None
    if root.tag != "robot":
        raise InputError(str(path), f"the root element is <{root.tag}>, not <robot>: not a URDF")
    return root


def needs_rewrite(root, source: Path, tree: Tree) -> bool:
    """True unless every engine can load the file as it is: plain URDF, no meshes, every link
    with a mass (Bullet gives a massless link 1 kg), no angle snapped, and every moving joint hung
    on a moving link or the base (not on a link fixed below one, such as a chassis link: engines
    fold such chains each their own way, so they all get the folded form)."""
    if source.suffix == ".xacro" or root.find(".//mesh") is not None or tree.notes or tree.axes:
        return True
    for j in tree.joints.values():
        parent = j.find("parent").get("link")
        if j.get("type") != "fixed" and parent in tree.child_joint and tree.child_joint[parent].get("type") == "fixed":
            return True
    for link in root.findall("link"):
        inertial = link.find("inertial")
        if inertial is None or inertial.find("mass") is None or float(inertial.find("mass").get("value", 0)) <= 0:
            return True
    return False


def normalised_urdf(root, tree: Tree, name: str) -> tuple[str, list[str]]:
    """The description with every fixed-joint child fused into its parent link (masses and
    inertias combined, primitive collisions kept), visuals and meshes dropped; and notes."""
    notes: list[str] = []
    where = name

    def body_of(link: str) -> str:  # the moving body a link belongs to
        while link in tree.child_joint and tree.child_joint[link].get("type") == "fixed":
            link = tree.child_joint[link].find("parent").get("link")
        return link

    def relative(link: str, body: str) -> tuple[np.ndarray, np.ndarray]:
        (pb, rb), (pl, rl) = tree.pose[body], tree.pose[link]
        return rb.T @ (pl - pb), rb.T @ rl

    bodies = [lk for lk in tree.links if body_of(lk) == lk]
    out = ET.Element("robot", {"name": name})
    out.append(ET.Comment(" written by simpick.inputs.urdf.normalised_urdf: fixed links fused, visuals dropped "))
    for body in bodies:
        mass, moment, parts = 0.0, np.zeros(3), []
        collisions = []
        for lk in tree.links:
            if body_of(lk) != body:
                continue
            pos, rot = relative(lk, body)
            inert = inertial(tree.links[lk], where)
            if inert is not None and inert[0] > 0:
                m, c, inertia = inert
                parts.append((m, pos + rot @ c, rot @ inertia @ rot.T))
                mass += m
                moment += m * (pos + rot @ c)
            elif lk == body and inert is None and body != tree.base:
                notes.append(f"link {lk!r} has no mass")
            for collision in tree.links[lk].findall("collision"):
                geometry = collision.find("geometry")
                if geometry is None:
                    continue
                shape = next((g for g in geometry if g.tag in ("box", "cylinder", "sphere")), None)
                if shape is None:
                    notes.append(
                        f"link {lk!r}: a {[g.tag for g in geometry]} collision was dropped "
                        "(only box, cylinder and sphere are simulated alike in every engine)"
                    )
                    continue
                xyz, r = origin(collision, f"{where}: link {lk!r} collision")
                collisions.append((pos + rot @ xyz, rot @ r, shape))
        link = ET.SubElement(out, "link", {"name": body})
        if mass > 0:
            com = moment / mass
            inertia = np.zeros((3, 3))
            for m, c, i in parts:
                d = c - com
                inertia += i + m * (d @ d * np.eye(3) - np.outer(d, d))
            block = ET.SubElement(link, "inertial")
            ET.SubElement(block, "origin", {"xyz": fmt(com), "rpy": "0 0 0"})
            ET.SubElement(block, "mass", {"value": repr(float(mass))})
            ET.SubElement(
                block,
                "inertia",
                {
                    k: repr(float(inertia[a, b]))
                    for k, (a, b) in {
                        "ixx": (0, 0),
                        "ixy": (0, 1),
                        "ixz": (0, 2),
                        "iyy": (1, 1),
                        "iyz": (1, 2),
                        "izz": (2, 2),
                    }.items()
                },
            )
        for xyz, r, shape in collisions:
            col = ET.SubElement(link, "collision")
            ET.SubElement(col, "origin", {"xyz": fmt(xyz), "rpy": fmt(matrix_rpy(r))})
            geometry = ET.SubElement(col, "geometry")
            geometry.append(ET.Element(shape.tag, dict(shape.attrib)))
    for jname, j in tree.joints.items():
        if j.get("type") == "fixed":
            continue
        child = j.find("child").get("link")
        parent = body_of(j.find("parent").get("link"))
        pos, rot = relative(child, parent)
        new = ET.SubElement(out, "joint", {"name": jname, "type": j.get("type")})
        ET.SubElement(new, "parent", {"link": parent})
        ET.SubElement(new, "child", {"link": child})
        ET.SubElement(new, "origin", {"xyz": fmt(pos), "rpy": fmt(matrix_rpy(rot))})
        axis = tree.axes.get(jname)
        ET.SubElement(new, "axis", {"xyz": fmt(joint_axis(j, jname) if axis is None else axis)})
        for tag in ("limit", "dynamics", "mimic"):
            if j.find(tag) is not None:
                new.append(j.find(tag))
    ET.indent(out)
    return ET.tostring(out, encoding="unicode") + "\n", notes


def fmt(values) -> str:
    return " ".join(repr(float(round(v, 12)) + 0.0) for v in values)


def write_cached(text: str) -> Path:
    digest = hashlib.sha256(text.encode()).hexdigest()[:16]
    folder = Path(tempfile.gettempdir()) / "simpick-robots"
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{digest}.urdf"
    if not path.is_file() or path.read_text() != text:
        tmp = folder / f".{digest}.{os.getpid()}.tmp"
        tmp.write_text(text)
        tmp.replace(path)
    return path
