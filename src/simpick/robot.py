"""The robot description every engine loads, and the few facts simpick reads from it.

The URDF under ``resources/robot`` is the single source of truth: the engines load the
file itself, and the controller and the IMU mount read their figures from it here, so
a wheel radius or a sensor offset cannot drift between engines.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

from simpick.errors import InputError

# Wheel order used everywhere in simpick: commands, measured speeds and actuators.
WHEEL_SIDES = ("left", "right", "left", "right")


@dataclass(frozen=True)
class RobotSpec:
    urdf: Path
    base_link: str
    wheel_joints: tuple[str, str, str, str]  # front-left, front-right, rear-left, rear-right
    wheel_radius: float
    imu_mount: tuple[float, float, float]  # IMU origin in base_link, metres
    base_height: float  # base_link above flat ground when resting on the wheels


def _floats(text: str | None, n: int, where: str) -> tuple[float, ...]:
    try:
        values = tuple(float(v) for v in (text or "").split())
    except ValueError:
        values = ()
    if len(values) != n:
        raise InputError(where, f"expected {n} numbers, got {text!r}")
    return values


def load_robot(urdf: str | Path) -> RobotSpec:
    """Read the wheel joints, wheel radius and IMU mount from a Husky-layout URDF."""
    urdf = Path(urdf)
    try:
        root = ET.parse(urdf).getroot()
    except (OSError, ET.ParseError) as exc:
        raise InputError(str(urdf), f"cannot read the robot description: {exc}") from None
    joints = {j.get("name"): j for j in root.iter("joint")}
    links = {lk.get("name"): lk for lk in root.iter("link")}

    names = tuple(f"{pos}_{side}_wheel_joint" for pos in ("front", "rear") for side in ("left", "right"))
    missing = [n for n in names + ("imu_joint",) if n not in joints]
    if missing:
        raise InputError(str(urdf), f"joints {missing} are missing; simpick expects the Husky layout "
                         "(front/rear x left/right wheel joints and an imu_joint)")

    wheel_link = links[joints[names[0]].find("child").get("link")]
    cylinder = wheel_link.find("collision/geometry/cylinder")
    if cylinder is None:
        raise InputError(str(urdf), "the front-left wheel has no cylinder collision to read its radius from")
    radius = float(cylinder.get("radius"))
    wheel_z = _floats(joints[names[0]].find("origin").get("xyz"), 3, f"{urdf}: {names[0]} origin")[2]
    imu = _floats(joints["imu_joint"].find("origin").get("xyz"), 3, f"{urdf}: imu_joint origin")
    base = joints["imu_joint"].find("parent").get("link")
    return RobotSpec(urdf=urdf, base_link=base, wheel_joints=names, wheel_radius=radius,
                     imu_mount=imu, base_height=radius - wheel_z)
