"""Quasi-static skid-steer on flat rigid ground with Coulomb friction (METHOD.md section 6).

At steady state a skid-steered robot's body twist (vx, vy, wz) is the one for which the
friction forces of all wheel contacts, each ``-mu N_i`` times the unit slip vector of its
contact point, and their yaw moment sum to zero. Those sums are the gradient of the total
frictional power ``D(q) = mu sum_i N_i |s_i(q)|`` with ``s_i = (vx - wz y_i - u_i,
vy + wz x_i)`` (u_i the rim speed of the contact's wheel), so the steady twist is the
minimiser of a convex function: found here with SciPy, whatever the loads and layout.
``mu`` scales D and drops out; D is positively homogeneous in the rim speeds, so the twist
scales with the command and a replay needs the solution on one circle of (left, right)
commands only (:class:`CoulombTable`).

The contact layout and loads come from the robot description itself
(:func:`contact_layout`): each wheel's contact points across its width under its joint, and
static loads from the mass distribution of every link, shared among the contact points as
a rigid body on equally stiff contacts does (the minimum-norm load set that balances weight
and the two tipping moments: loads linear in position).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from simpick.errors import InputError
from simpick.motions import side_speeds
from simpick.robot import RobotSpec, load_robot

WHEEL_SIDES = ("left", "right", "left", "right")  # the Husky's order (FL, FR, RL, RR)

GRAVITY = 9.81


@dataclass(frozen=True)
class ContactLayout:
    """Ground contact points in base_link's horizontal plane and their normal loads."""

    points: np.ndarray  # (n, 2) x, y in m, relative to base_link
    loads: np.ndarray  # (n,) N
    wheel: np.ndarray  # (n,) index 0..3 (FL, FR, RL, RR) of the wheel each point belongs to
    com: tuple[float, float]  # x, y of the whole robot's centre of mass, m
    mass: float  # kg

    def load_shares(self) -> np.ndarray:
        """Fraction of the weight on each wheel (FL, FR, RL, RR)."""
        return np.bincount(self.wheel, weights=self.loads, minlength=4) / self.loads.sum()


def _xyz(element, attribute: str = "xyz") -> np.ndarray:
    origin = element.find("origin") if element is not None else None
    if origin is None or origin.get(attribute) is None:
        return np.zeros(3)
    return np.array([float(v) for v in origin.get(attribute).split()])


def mass_distribution(urdf: str | Path) -> tuple[float, np.ndarray]:
    """Total mass and centre of mass (in base_link, joints at zero) of every link."""
    root = ET.parse(urdf).getroot()
    joints = {j.find("child").get("link"): j for j in root.iter("joint")}
    total, moment = 0.0, np.zeros(3)
    for link in root.iter("link"):
        inertial = link.find("inertial")
        if inertial is None:
            continue
        mass = float(inertial.find("mass").get("value"))
        # Link frame origin in base_link: sum of joint offsets up the tree (no joint rotates
        # a child's origin in this robot; a joint rpy would need composing here).
        position, name = _xyz(inertial), link.get("name")
        while name in joints:
            joint = joints[name]
            if np.any(_xyz(joint, "rpy")):
                raise InputError(str(urdf), f"joint {joint.get('name')!r} has a rotated origin, which the "
                                 "Coulomb model's load computation does not handle")
            position = position + _xyz(joint)
            name = joint.find("parent").get("link")
        total += mass
        moment += mass * position
    return total, moment / total


def contact_layout(robot: RobotSpec, points_per_wheel: int | None = None) -> ContactLayout:
    """Wheel contact points and static loads of ``robot`` on flat ground.

    ``points_per_wheel``: None spreads pressure uniformly across each wheel's width (the line
    contact of a rigid cylinder on a plane, here 21 points); 1 puts one point under the wheel
    centre; 2 one at each edge (what several engines generate for a cylinder on a plane).
    """
    root = ET.parse(robot.urdf).getroot()
    joints = {j.get("name"): j for j in root.iter("joint")}
    links = {lk.get("name"): lk for lk in root.iter("link")}
    mass, com = mass_distribution(robot.urdf)
    n = 21 if points_per_wheel is None else int(points_per_wheel)
    points, wheel = [], []
    for index, name in enumerate(robot.wheel_joints):
        x, y, _ = _xyz(joints[name])
        cylinder = links[joints[name].find("child").get("link")].find("collision/geometry/cylinder")
        width = float(cylinder.get("length"))
        offsets = [0.0] if n == 1 else np.linspace(-width / 2, width / 2, n)
        for dy in offsets:
            points.append((x, y + dy))
            wheel.append(index)
    points = np.asarray(points)
    # Rigid body on equally stiff contacts: loads are linear in position, the minimum-norm
    # solution of (sum N = W, sum N x = W xc, sum N y = W yc).
    a = np.vstack([np.ones(len(points)), points[:, 0], points[:, 1]])
    weight = mass * GRAVITY
    loads = a.T @ np.linalg.solve(a @ a.T, weight * np.array([1.0, com[0], com[1]]))
    if np.any(loads <= 0):
        raise InputError(str(robot.urdf), "the centre of mass lies outside the wheelbase: a wheel would lift")
    return ContactLayout(points=points, loads=loads, wheel=np.asarray(wheel), com=(com[0], com[1]), mass=mass)


def equal_loads(layout: ContactLayout) -> ContactLayout:
    """The same contact points with the weight shared equally (a centred centre of mass)."""
    loads = np.full(len(layout.loads), layout.loads.sum() / len(layout.loads))
    return ContactLayout(points=layout.points, loads=loads, wheel=layout.wheel, com=(0.0, 0.0), mass=layout.mass)


def steady_twist(layout: ContactLayout, rim_speeds) -> np.ndarray:
    """Body twist (vx, vy, wz) at base_link under rim speeds (FL, FR, RL, RR) in m/s."""
    from scipy.optimize import minimize

    u = np.asarray(rim_speeds, dtype=float)[layout.wheel]
    scale = float(np.abs(u).max())
    if scale == 0.0:
        return np.zeros(3)
    x, y = layout.points[:, 0], layout.points[:, 1]
    weights = layout.loads / layout.loads.sum()
    eps = 1e-9  # slip speed (relative) below which |s| is rounded: keeps D differentiable
    un = u / scale

    def power(q):
        sx = q[0] - q[2] * y - un
        sy = q[1] + q[2] * x
        norm = np.sqrt(sx * sx + sy * sy + eps * eps)
        ex, ey = weights * sx / norm, weights * sy / norm
        return float(weights @ norm), np.array([ex.sum(), ey.sum(), (ex * -y + ey * x).sum()])

    start = np.array([un.mean(), 0.0, 0.0])
    result = minimize(power, start, jac=True, method="BFGS", options={"gtol": 1e-12, "maxiter": 500})
    return result.x * scale


def yaw_rate_gain(layout: ContactLayout, v: float, w: float, track: float, wheel_radius: float | None = None) -> float:
    """Steady yaw rate / commanded w under the paper's controller (Eq. 1, effective track)."""
    left, right = side_speeds(v, w, track)
    return float(steady_twist(layout, [left, right, left, right])[2] / w)


class CoulombTable:
    """Steady twist for any (left, right) rim speed pair, from solutions on the unit circle.

    D is positively homogeneous of degree one in the rim speeds, so the twist for
    ``r (cos a, sin a)`` is ``r`` times the twist for angle ``a``: solved once on a fine
    circle of angles and interpolated linearly in between.
    """

    def __init__(self, layout: ContactLayout, angles: int = 1440):
        self.angles = np.linspace(-math.pi, math.pi, angles + 1)
        self.twists = np.array([steady_twist(layout, [math.cos(a), math.sin(a)] * 2) for a in self.angles])

    def twist(self, left, right) -> np.ndarray:
        """(n, 3) twists for arrays of left and right rim speeds (m/s)."""
        left, right = np.asarray(left, dtype=float), np.asarray(right, dtype=float)
        radius = np.hypot(left, right)
        angle = np.arctan2(right, left)
        out = np.stack([np.interp(angle, self.angles, self.twists[:, k]) for k in range(3)], axis=-1)
        return out * radius[..., None]


def load_layout(urdf: str | Path, points_per_wheel: int | None = None) -> ContactLayout:
    return contact_layout(load_robot(urdf), points_per_wheel)


__all__ = ["ContactLayout", "CoulombTable", "contact_layout", "equal_loads", "load_layout", "mass_distribution",
           "steady_twist", "yaw_rate_gain", "WHEEL_SIDES"]
