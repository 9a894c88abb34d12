"""What simpick knows of a robot, as plain frozen records: the wheels, suspension joints, couplings and
skids, and the :class:`RobotSpec` that holds them with the robot's figures.

They stand apart from the code that reads a description so that an engine adapter, the controller
and the Coulomb model depend on the shape of the facts only, and the records and their derived
views (driven wheels, joint speeds from rim speeds) read as one place."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from simpick.inputs.urdf import RigidModel


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
