"""ODE (Open Dynamics Engine 0.16, the engine behind Gazebo Classic and Webots) via ctypes.

ODE is a C library with no maintained Python binding, so :mod:`simpick.engines._ode`
binds the few calls used here. The world is built from the same URDF and engine-neutral
terrain as every other engine:

- robot: one ODE body per URDF link that moves (base_link, four wheels); links hung on
  base_link by fixed joints (the 18 g IMU link) are folded into the chassis body. An ODE
  body's origin must be its centre of mass, so each body sits at its link's COM with the
  link's orientation, the full URDF inertia tensor (off-diagonal terms included) about that
  point, and its collision shapes offset from it. The record is converted back to base_link
  after the run (position - R c, velocity - w x R c), as the PyBullet adapter does.
- wheels: hinge joints whose velocity motor (dParamVel) is bounded by dParamFMax =
  ``scenario.max_wheel_torque``: ODE solves the motor as a constraint with a force limit,
  the same servo PyBullet's VELOCITY_CONTROL is.
- terrain: boxes, spheres and a plane as static geoms (no body).
- contacts: ``dSpaceCollide`` calls a Python callback for each pair whose bounding boxes
  overlap; it runs ``dCollide`` straight into a preallocated ``dContact`` array whose
  surface parameters are preset per friction value, and turns each contact into a contact
  joint. Friction: the robot's surfaces carry none of their own; a contact's mu is the
  terrain's (or the ground's, ``scenario.ground_friction``) coefficient, robot-robot
  contacts get 1.0 (what PyBullet's product 1.0 x 1.0 gives). Surface mode
  ``dContactApprox1``: the friction pyramid's bound is mu x normal force (Coulomb);
  without it ODE reads ``mu`` as a fixed force limit in newtons, not a coefficient.
  Webots' and Gazebo's ODE integrations set it too. ODE has no friction cone: each contact
  gets two friction rows, each bounded by mu x normal force on its own (a pyramid), along
  fdir1 and normal x fdir1. See ``OdeSettings.friction_direction`` for how fdir1 is chosen.
- category bits keep static terrain from being paired with itself (every stone overlaps its
  gravel bed; each pair would cost a Python callback per step) and keep a robot's own
  shapes apart; robots still collide with each other.

Settings: :class:`OdeSettings` (config ``engines.ode``), each with what was measured for it.

Determinism: ODE's only randomness is the constraint reordering of the quick stepper
(``dRandInt``); the seed is reset before every run, and geoms are created in a fixed
order, so the same inputs give identical arrays.
"""

from __future__ import annotations

import ctypes
import logging
import math
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from typing import Annotated, Literal

import numpy as np
from pydantic import Field, model_validator

from simpick.engines import _ode
from simpick.engines.base import (FRICTION, FRICTION_RATIO, Calibratable, EngineSettings, PhysicsRecord, Scenario,
                                  validated_commands)
from simpick.errors import InputError, SimulationFailure
from simpick.engines.kinematics import imu_from_kinematics, matrices_to_quaternions, rotation_matrices
from simpick.inputs.robot import joint_axis, origin, rpy_matrix

LOG = logging.getLogger(__name__)
SPAWN_CLEARANCE = 0.002  # m above resting height, as for the other engines
TERRAIN_BIT = 1  # category bit of static terrain; robot i gets bit i + 1
ROBOT_ROBOT_FRICTION = 1.0
class OdeSettings(EngineSettings):
    """config ``engines.ode``. Figures measured here, 1 kHz, one robot; steps/s are of the whole
    Python stepping loop, which on flat ground spends most of its time in the collision callback
    (4 geom pairs, 8 contacts per step)."""

    # "world" or "quick". dWorldStep solves the constraints exactly (Dantzig LCP); with one robot
    # the system is small (about 20 joint rows + 3 per contact), and it was the faster of the two:
    # flat 4 s at 0.5 m/s 35 600 against 27 700 steps/s for dWorldQuickStep with 50 iterations;
    # gravel strip 26 000 against 20 400. Both pass the conformance suite. The exact solver now and
    # then prints "LCP internal error, s <= 0" (a degenerate pivot it recovers from; 4 times in 10 s
    # on the bumps strip); the adapter counts these and logs them instead of letting them reach stderr.
    # Issue 17: only "quick" (50 iterations, with friction_direction_min_slip 5 mm/s) passes every
    # validation case: sliding down a slope at 45 degrees to the robot it yaws 0.0003 rad in 3 s and
    # slides at 1.015 m/s^2 (Coulomb 1.016; dWorldStep: 0.27 rad, 0.975). Its turning gains 0.478-0.491
    # at mu 0.8 / 0.2, left and right within 0.01 of each other, the same at every start heading.
    # Cost, CPU steps/s of the bare loop, lab straight 4 s, median of 3, quick / world: grass 13 160 /
    # 12 940, bumps 13 420 / 15 700, gravel 10 220 / 12 680; flat-ground turning about 0.55x.
    # config.yaml uses "quick"; the default stays ODE's own dWorldStep.
    stepper: Literal["world", "quick"] = "world"
    # quick stepper only; ODE's default is 20, Gazebo's 50
    quick_iterations: Annotated[int, Field(ge=1)] = 50
    # error reduction parameter, a fraction of the joint error corrected per step: 0.2, ODE's default
    erp: Annotated[float, Field(ge=0, le=1)] = 0.2
    # constraint force mixing: 1e-5 is Webots' WorldInfo default and ODE's default for
    # single-precision builds; Debian's double-precision build defaults to 1e-10, which we have
    # not validated
    cfm: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 1e-5
    # m, ODE's default 0. Gazebo's 0.001 lets the robot rest 1 mm deep: base_link at 0.13127 m
    # instead of 0.13228 m.
    contact_surface_layer: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 0.0
    # m/s (ODE's default is unlimited: .inf; Gazebo's 100 m/s). ODE pushes penetration out at
    # ERP x depth / dt; when a wheel meets a plywood edge of the bumps strip that is a kick:
    # unlimited, the base velocity jumped by 0.90 m/s within one step and the run failed the health
    # check (limit 0.5 m/s); 0.5 m/s -> 0.36 m/s, 0.1 m/s -> 0.24 m/s (PyBullet 0.49, DART 0.41,
    # MuJoCo 0.04 on the same strip). Other engines cap this too (DART: 1 mm/s; Bullet: split impulse).
    contact_max_correcting_vel: Annotated[float, Field(gt=0)] = 0.1
    # contact points per geom pair (8 gave identical runs: ODE's cylinder colliders return at most
    # 4 here; a wheel on the ground gets 2, across its width). dCollide takes the count in the
    # low 16 bits of its flags.
    max_contacts: Annotated[int, Field(ge=1, le=0xFFFF)] = 4
    # A hash space rebuilds its table every step, for every static stone: gravel strip 7 300
    # steps/s (hash) against 25 500 (quadtree with 0.4 m cells; 10 300 with 1.6 m cells, 24 700
    # with 0.2 m), flat ground the same either way.
    space: Literal["quadtree", "hash", "simple"] = "quadtree"
    quadtree_cell: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 0.4  # m, finest cell (space above)
    # "plane" leaves fdir1 to ODE, which takes dPlaneSpace of the normal: on flat ground the
    # world's x and y. A wheel sliding diagonally to them then meets friction up to sqrt(2) mu N,
    # not opposite its slip, and the skid-steered Husky hardly turns (issue 9, validation cases,
    # 6 s, mu 0.8): yaw-rate gain 0.115 at (v, w) = (0, 0.5), 0.207 at (0.5, 0.5), 0.028 at
    # (0.5, 0.2); mu 0.2: 0.219 / 0.388; Coulomb 0.478. Commanded to spin, it drove forward at
    # 0.135 m/s instead (the heavier right wheels rolled, the left ones slid). Parked on a
    # 1.2 atan(mu) slope it slides (1.015 m/s^2, Coulomb 1.016) when the slope runs along x, and
    # stays put when it runs along the world diagonal. Gazebo users see the same
    # (jackal_simulator#18, husky#105; gazebo-classic#2068, where a user fixes it by computing the
    # friction direction himself between collision and physics update).
    # "slip" does that: fdir1 = the contact's sliding direction (Bullet's default "velocity
    # dependent friction direction"), so a sliding contact gets mu N against its slip. Gains then
    # 0.483 / 0.484 / 0.482 (mu 0.8), 0.487 / 0.507 (mu 0.2), within 1-6 % of 0.478; the 45-degree
    # slope slides at 0.974 m/s^2. Cost: flat ground 26 200 -> 19 600 steps/s (bare loop), gravel
    # strip about 12 900 -> 11 100. Residual artefact of "slip": the second row (across the slip)
    # still holds up to mu N, so a robot sliding down a slope with locked wheels yaws (1.24 rad in
    # 3 s at 1.2 atan(0.5); Coulomb friction has no yaw moment there) and slides 3 % slower.
    # "coulomb" (the default) also frees that row (dContactMu2, mu2 = 0) while the contact slides
    # faster than friction_direction_min_slip: a sliding contact then gets exactly Coulomb's mu N
    # against its slip and nothing across it; a slower one keeps the full pyramid (sticking).
    # Measured: the same gains (0.482-0.487), slide down the slope 1.016 m/s^2 (Coulomb 1.016)
    # with 0.014 rad of yaw. Not cured: on a slope at 45 degrees to the robot it slides at 0.975
    # (4 % slow) and yaws 0.27 rad in 3 s (0.036 rad per metre); the other three engines yaw
    # < 0.01 rad there (validation case incline_slide_diagonal). With the quick stepper it does not
    # (0.0003 rad, 1.015 m/s^2; issue 17, stepper above).
    friction_direction: Literal["coulomb", "slip", "plane"] = "coulomb"
    # m/s, the stick/slip threshold of "coulomb" (below it fdir1 is dPlaneSpace's and both rows
    # hold). It must exceed the creep that ODE's constraint softness allows a sticking contact
    # (CFM x load: 0.27 mm/s measured on the 0.8 atan(mu) slope); at 1e-6 that creep counts as
    # sliding, the cross row is freed and the parked robot creeps 3.4 mm/s. 1e-3 and 3e-3 gave
    # identical validation figures with dWorldStep. The quick stepper's sticking contacts creep
    # faster: at 1e-3 the robot parked on the 0.8 atan(mu) slope crept 2.7 mm/s, at 5e-3 0.32 mm/s
    # (config.yaml: 5e-3 with "quick", issue 17).
    friction_direction_min_slip: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 1e-3
    # force-dependent slip of terrain contacts, (m/s)/N on both friction rows (ODE's
    # dContactSlip1/2: a contact slides at slip x friction force); Gazebo exposes it as
    # <slip1>/<slip2> and users tune it for skid-steer turning. 0: off (ODE's default).
    contact_slip: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 0.0
    # Issue 20: lateral / longitudinal friction ratio of the driven wheels' contacts, in each
    # wheel's frame (longitudinal = the rolling direction, normal x the hinge axis). 1: isotropic
    # (the default, today's behaviour, bit-identical). ODE's own anisotropy is mu along fdir1 and
    # mu2 across it, each row bounded on its own: a box, not Coulomb's ellipse. With
    # friction_direction "coulomb" the adapter gives a sliding wheel contact the elliptic force
    # instead (simpick.coulomb): fdir1 along (s_long, r^2 s_lat) in the wheel frame, bounded by
    # mu N |(s_long, r^2 s_lat)| / |(s_long, r s_lat)|, mu2 = 0; a sticking one gets the box (fdir1
    # along the wheel, mu along it, r mu across). Measured (quick stepper, mu 0.8, 6 s, (v, w) =
    # (0, 0.5) / (0.5, 0.5) / (0.5, -0.5), anisotropic Coulomb in brackets): r 1 0.488 / 0.484 / 0.483
    # (0.478), 0.8 0.600 / 0.598 / 0.597 (0.601), 0.63 0.694 / 0.694 / 0.696 (0.705), 0.5 0.761 /
    # 0.764 / 0.767 (0.781); the same 0.694-0.696 from start headings 112.5 and -135 degrees.
    friction_ratio: Annotated[float, Field(gt=0, le=2, allow_inf_nan=False)] = 1.0

    @model_validator(mode="after")
    def _ratio_needs_coulomb(self):
        if self.friction_ratio != 1.0 and self.friction_direction != "coulomb":
            raise ValueError(f"friction_ratio {self.friction_ratio} needs friction_direction 'coulomb' (got "
                             f"{self.friction_direction!r}): ODE's two rows alone form a box, not the ellipse")
        return self




# --- small rigid-body helpers ------------------------------------------------------------

def _floats(text: str | None, n: int, default: float = 0.0) -> np.ndarray:
    if text is None:
        return np.full(n, default)
    values = [float(v) for v in text.split()]
    if len(values) != n:
        raise ValueError(f"expected {n} numbers, got {text!r}")
    return np.asarray(values)


def _origin(element) -> tuple[np.ndarray, np.ndarray]:
    """(xyz, rotation) of an URDF <origin> child (identity when absent): simpick.inputs.robot.origin."""
    return origin(element, "the robot description")


@dataclass
class _Part:
    """A rigid body as ODE needs it, in the frame of its (main) URDF link."""
    mass: float = 0.0
    com: np.ndarray = field(default_factory=lambda: np.zeros(3))
    inertia: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))  # about com, link axes
    shapes: list = field(default_factory=list)  # (kind, dims, position, rotation) in the link frame

    def add(self, link, position: np.ndarray, rotation: np.ndarray) -> None:
        """Fold ``link`` (placed at position/rotation in this part's frame) into the part."""
        inertial = link.find("inertial")
        if inertial is not None:
            xyz, rot = _origin(inertial)
            m = float(inertial.find("mass").get("value"))
            t = inertial.find("inertia")
            g = {k: float(t.get(k, 0.0)) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
            local = np.array([[g["ixx"], g["ixy"], g["ixz"]], [g["ixy"], g["iyy"], g["iyz"]],
                              [g["ixz"], g["iyz"], g["izz"]]])
            r = rotation @ rot
            self._combine(m, position + rotation @ xyz, r @ local @ r.T)
        for collision in link.findall("collision"):
            xyz, rot = _origin(collision)
            geometry = collision.find("geometry")
            box, cyl, sph = geometry.find("box"), geometry.find("cylinder"), geometry.find("sphere")
            if box is not None:
                shape = ("box", tuple(_floats(box.get("size"), 3)))
            elif cyl is not None:
                shape = ("cylinder", (float(cyl.get("radius")), float(cyl.get("length"))))
            elif sph is not None:
                shape = ("sphere", (float(sph.get("radius")),))
            else:
                raise ValueError(f"link {link.get('name')!r}: only box, cylinder and sphere collisions are supported")
            self.shapes.append((*shape, position + rotation @ xyz, rotation @ rot))

    def _combine(self, m: float, c: np.ndarray, inertia: np.ndarray) -> None:
        total = self.mass + m
        com = (self.mass * self.com + m * c) / total

        def shifted(mass, at, tensor):
            d = at - com
            return tensor + mass * (d @ d * np.eye(3) - np.outer(d, d))

        self.inertia = shifted(self.mass, self.com, self.inertia) + shifted(m, c, inertia)
        self.mass, self.com = total, com


@dataclass
class _RobotModel:
    chassis: _Part
    # driven wheels in command order: (joint position in base_link, joint rotation, axis in the
    # wheel link frame, _Part)
    wheels: list
    # every other moving link (casters, swivels), parents before children: (joint position and
    # rotation in the parent link's frame, axis, _Part, parent: -1 the chassis, else an index
    # into this list)
    passive: list = field(default_factory=list)


def read_urdf(robot) -> _RobotModel:
    """Masses, inertias, collision shapes and joints of the robot (simpick.inputs.robot.RobotSpec):
    each moving link with every link hung on it by fixed joints folded in."""
    try:
        root = ET.parse(robot.urdf).getroot()
        links = {lk.get("name"): lk for lk in root.iter("link")}
        joints = {j.get("name"): j for j in root.iter("joint")}

        def part_of(link_name: str) -> _Part:
            # the link plus every link hung on it by fixed joints (breadth first)
            part = _Part()
            queue = [(link_name, np.zeros(3), np.eye(3))]
            while queue:
                name, pos, rot = queue.pop(0)
                part.add(links[name], pos, rot)
                for joint in joints.values():
                    if joint.get("type") == "fixed" and joint.find("parent").get("link") == name:
                        xyz, r = _origin(joint)
                        queue.append((joint.find("child").get("link"), pos + rot @ xyz, rot @ r))
            return part

        def axis_of(joint) -> np.ndarray:
            return joint_axis(joint, f"{robot.urdf}: joint {joint.get('name')!r}")

        chassis = part_of(robot.base_link)
        wheels = []
        for name in robot.wheel_joints:
            joint = joints[name]
            if joint.find("parent").get("link") != robot.base_link:
                raise ValueError(f"{name} does not hang on {robot.base_link}")
            xyz, rot = _origin(joint)
            wheels.append((xyz, rot, axis_of(joint), part_of(joint.find("child").get("link"))))
        passive, index = [], {}
        for name in robot.passive_joints[::-1]:  # (caster joint, its swivel): the swivel first
            joint = joints[name]
            parent = joint.find("parent").get("link")
            if parent != robot.base_link and parent not in index:
                raise ValueError(f"{name} hangs on {parent!r}, which is neither the base nor a passive link")
            xyz, rot = _origin(joint)
            index[joint.find("child").get("link")] = len(passive)
            passive.append((xyz, rot, axis_of(joint), part_of(joint.find("child").get("link")),
                            -1 if parent == robot.base_link else index[parent]))
    except (OSError, ET.ParseError, KeyError, AttributeError, TypeError, ValueError) as exc:
        raise InputError(str(robot.urdf), f"the ODE adapter cannot read the robot: {exc!r}") from None
    return _RobotModel(chassis, wheels, passive)


# --- the world ---------------------------------------------------------------------------

class _World:
    """One ODE world with terrain and robots; owns every ODE object it creates."""

    def __init__(self, lib, scenario: Scenario):
        self.lib = lib
        self.settings = OdeSettings.of(scenario.settings, OdeEngine.name)
        self.world = self.space = self.group = None
        self._keep = []  # ctypes objects whose memory ODE or the callback refers to
        try:
            self._build(scenario)
        except BaseException:
            self.destroy()
            raise

    def _build(self, scenario: Scenario) -> None:
        lib, s = self.lib, self.settings
        if len(scenario.starts) > 62:
            raise InputError("starts", "the ODE adapter supports at most 62 robots (one category bit each)")
        lib.dAllocateODEDataForThread(_ode.dAllocateMaskAll)
        lib.dRandSetSeed(0)
        self.world = lib.dWorldCreate()
        lib.dWorldSetGravity(self.world, *scenario.gravity)
        lib.dWorldSetERP(self.world, s.erp)
        lib.dWorldSetCFM(self.world, s.cfm)
        lib.dWorldSetContactSurfaceLayer(self.world, s.contact_surface_layer)
        lib.dWorldSetContactMaxCorrectingVel(self.world, s.contact_max_correcting_vel)
        lib.dWorldSetAutoDisableFlag(self.world, 0)
        lib.dWorldSetQuickStepNumIterations(self.world, s.quick_iterations)
        self.step_fn = lib.dWorldStep if s.stepper == "world" else lib.dWorldQuickStep

        if s.space == "hash":
            self.space = lib.dHashSpaceCreate(None)
        elif s.space == "quadtree":
            # Sized to the terrain and the starts plus a margin the robots may drive into;
            # depth chosen so that the finest cells are about quadtree_cell wide (0.4 m
            # measured fastest on the gravel strip: 25 500 steps/s against 10 300 with
            # 1.6 m cells and 7 300 for a hash space, whose table is rebuilt every step).
            terrain = scenario.terrain
            xs = [b[0] for b in terrain.boxes] + [p[0] for p in terrain.spheres] + [st[0] for st in scenario.starts]
            ys = [b[1] for b in terrain.boxes] + [p[1] for p in terrain.spheres] + [st[1] for st in scenario.starts]
            margin = 10.0
            centre = _ode.dVector3((min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2, 0.0)
            extent = _ode.dVector3(max(xs) - min(xs) + 2 * margin, max(ys) - min(ys) + 2 * margin, 2 * margin)
            cell = s.quadtree_cell
            depth = 1 + max(0, math.ceil(math.log2(max(extent[0], extent[1]) / cell)))
            self.space = lib.dQuadTreeSpaceCreate(None, centre, extent, min(depth, 9))
        else:  # "simple"
            self.space = lib.dSimpleSpaceCreate(None)
        self.group = lib.dJointGroupCreate(0)

        n_robots = len(scenario.starts)
        robot_bits = ((1 << (n_robots + 1)) - 1) & ~TERRAIN_BIT
        self.surface_of: dict[int, tuple] = {}  # static geom -> contact buffer with its friction
        self.body_of: dict[int, int] = {}  # robot geom -> its body
        self.max_contacts = s.max_contacts
        buffers: dict[float, tuple] = {}

        self.slip_directions = s.friction_direction in ("slip", "coulomb")
        self.coulomb = s.friction_direction == "coulomb"
        self.min_slip = s.friction_direction_min_slip
        slip = s.contact_slip
        mode = (_ode.dContactApprox1 | (_ode.dContactFDir1 if self.slip_directions else 0)
                | (_ode.dContactMu2 if self.coulomb else 0)
                | (_ode.dContactSlip1 | _ode.dContactSlip2 if slip > 0 else 0))

        def contacts_for(mu: float) -> tuple:
            if mu not in buffers:
                array = (_ode.dContact * self.max_contacts)()
                for c in array:
                    c.surface.mode = mode
                    c.surface.mu = c.surface.mu2 = mu  # both rows bounded by mu unless sliding ("coulomb")
                    c.surface.slip1 = c.surface.slip2 = slip
                self._keep.append(array)
                base = ctypes.addressof(array)
                size = ctypes.sizeof(_ode.dContact)
                # each contact also as a flat array of dReals, for the callback to read its
                # position and normal and write its fdir1 without building ctypes structs
                n_reals = size // ctypes.sizeof(_ode.dReal)
                views = tuple((_ode.dReal * n_reals).from_address(base + i * size)
                              for i in range(self.max_contacts))
                self._keep.append(views)
                buffers[mu] = (base + _ode.dContact.geom.offset,
                               tuple(base + i * size for i in range(self.max_contacts)), views, mu)
            return buffers[mu]

        def static(geom: int, mu: float) -> None:
            lib.dGeomSetCategoryBits(geom, TERRAIN_BIT)
            lib.dGeomSetCollideBits(geom, robot_bits)
            self.surface_of[geom] = contacts_for(float(mu))

        static(lib.dCreatePlane(self.space, 0.0, 0.0, 1.0, 0.0), scenario.ground_friction)
        terrain = scenario.terrain
        for x, y, z, yaw, sx, sy, sz in terrain.boxes:
            geom = lib.dCreateBox(self.space, sx, sy, sz)
            lib.dGeomSetPosition(geom, x, y, z)
            lib.dGeomSetQuaternion(geom, _ode.dQuaternion(math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)))
            static(geom, terrain.friction)
        for x, y, z, r in terrain.spheres:
            geom = lib.dCreateSphere(self.space, r)
            lib.dGeomSetPosition(geom, x, y, z)
            static(geom, terrain.friction)
        self.robot_contacts = contacts_for(ROBOT_ROBOT_FRICTION)

        model = read_urdf(scenario.robot)
        self.model = model
        self.robots = []  # per robot: (chassis body, [hinge joints], [wheel bodies])
        self.axles: dict[int, tuple] = {}  # driven wheel body -> (its rotation matrix, hinge axis in body frame)
        self.recorded = scenario.recorded_robot
        torque = float(scenario.max_wheel_torque)
        for i, (x, y, yaw) in enumerate(scenario.starts):
            own = 1 << (i + 1)
            yaw_rot = rpy_matrix((0.0, 0.0, yaw))
            base_pos = np.array([x, y, scenario.robot.base_height + SPAWN_CLEARANCE])

            def make_body(part: _Part, link_pos: np.ndarray, link_rot: np.ndarray) -> int:
                body = lib.dBodyCreate(self.world)
                mass = _ode.dMass()
                I = part.inertia
                lib.dMassSetParameters(ctypes.byref(mass), part.mass, 0.0, 0.0, 0.0,
                                       I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2])
                if not lib.dMassCheck(ctypes.byref(mass)):
                    raise InputError(str(scenario.robot.urdf), "a link's inertia is not positive definite")
                lib.dBodySetMass(body, ctypes.byref(mass))
                px, py, pz = link_pos + link_rot @ part.com
                lib.dBodySetPosition(body, px, py, pz)
                lib.dBodySetQuaternion(body, _ode.dQuaternion(*matrices_to_quaternions(link_rot[None])[0]))
                for kind, dims, pos, rot in part.shapes:
                    if kind == "box":
                        geom = lib.dCreateBox(self.space, *dims)
                    elif kind == "cylinder":  # ODE's cylinder axis is local z, like URDF's
                        geom = lib.dCreateCylinder(self.space, *dims)
                    else:
                        geom = lib.dCreateSphere(self.space, *dims)
                    lib.dGeomSetBody(geom, body)
                    ox, oy, oz = pos - part.com
                    lib.dGeomSetOffsetPosition(geom, ox, oy, oz)
                    lib.dGeomSetOffsetQuaternion(geom, _ode.dQuaternion(*matrices_to_quaternions(rot[None])[0]))
                    lib.dGeomSetCategoryBits(geom, own)
                    lib.dGeomSetCollideBits(geom, TERRAIN_BIT | (robot_bits & ~own))
                    self.body_of[geom] = body
                return body

            def hinge_between(child, parent, anchor, axis):
                hinge = lib.dJointCreateHinge(self.world, None)
                # body1 = child, body2 = parent: ODE's hinge rate is (w1 - w2) . axis, so this
                # order makes it the URDF joint velocity (child relative to parent).
                lib.dJointAttach(hinge, child, parent)
                lib.dJointSetHingeAnchor(hinge, *anchor)
                lib.dJointSetHingeAxis(hinge, *axis)
                return hinge

            chassis = make_body(model.chassis, base_pos, yaw_rot)
            hinges, wheel_bodies = [], []
            for xyz, rot, axis, part in model.wheels:
                link_pos, link_rot = base_pos + yaw_rot @ xyz, yaw_rot @ rot
                wheel = make_body(part, link_pos, link_rot)
                hinge = hinge_between(wheel, chassis, link_pos, link_rot @ axis)
                lib.dJointSetHingeParam(hinge, _ode.dParamVel, 0.0)
                lib.dJointSetHingeParam(hinge, _ode.dParamFMax, torque)
                hinges.append(hinge)
                wheel_bodies.append(wheel)
            # casters and swivels: free hinges (no motor), each on its parent link
            frames = []
            for xyz, rot, axis, part, parent in model.passive:
                parent_pos, parent_rot, parent_body = ((base_pos, yaw_rot, chassis) if parent < 0 else frames[parent])
                link_pos, link_rot = parent_pos + parent_rot @ xyz, parent_rot @ rot
                body = make_body(part, link_pos, link_rot)
                hinge_between(body, parent_body, link_pos, link_rot @ axis)
                frames.append((link_pos, link_rot, body))
            for (_xyz, _rot, axis, _part), wheel in zip(model.wheels, wheel_bodies):
                # the hinge axis in the wheel body's frame (the body keeps its link's orientation)
                self.axles[wheel] = ((_ode.dReal * 12).from_address(lib.dBodyGetRotation(wheel)),
                                     tuple(float(a) for a in axis))
            self.robots.append((chassis, hinges, wheel_bodies))
        self.all_hinges = [h for _, hs, _ in self.robots for h in hs]

    def destroy(self) -> None:
        lib = self.lib
        if self.group:
            lib.dJointGroupDestroy(self.group)
        if self.space:
            lib.dSpaceDestroy(self.space)  # destroys its geoms too (cleanup mode is on by default)
        if self.world:
            lib.dWorldDestroy(self.world)  # and the bodies and joints
        self.world = self.space = self.group = None

    def _near_callback(self):
        """The dSpaceCollide callback: contacts of one geom pair -> contact joints.

        With ``friction_direction`` "slip" or "coulomb" (the default) each contact's first friction
        direction (fdir1) is set to its sliding direction: the relative velocity of the two
        bodies at the contact point, projected onto the contact plane (Bullet's default
        "velocity dependent friction direction", btSequentialImpulseConstraintSolver). ODE's
        friction is a pyramid, two directions each bounded by mu N on its own; left to
        itself (dPlaneSpace of the normal) it aligns them with the world's x and y, so a
        wheel sliding diagonally meets up to sqrt(2) mu N, not opposite its slip, and the
        skid-steered Husky barely turns (see the module docstring). With fdir1 along the
        slip, a sliding contact's friction is mu N straight against its slip: Coulomb's law.
        Below ``friction_direction_min_slip`` (m/s: rolling or parked) the direction is
        undefined and fdir1 is dPlaneSpace's, i.e. ODE's own choice.
        """
        lib = self.lib
        surface_of, body_of = self.surface_of, self.body_of
        robot_contacts, max_contacts = self.robot_contacts, self.max_contacts
        stride = ctypes.sizeof(_ode.dContact)
        collide, create, attach = lib.dCollide, lib.dJointCreateContact, lib.dJointAttach
        world, group = self.world, self.group
        # each robot body's position, linear and angular velocity read straight from ODE's
        # memory (one dReal array over the span holding them): cheaper than dBodyGetPointVel
        state = {}
        for body in set(body_of.values()):
            a = [lib.dBodyGetPosition(body), lib.dBodyGetLinearVel(body), lib.dBodyGetAngularVel(body)]
            lo = min(a)
            view = (_ode.dReal * ((max(a) - lo) // ctypes.sizeof(_ode.dReal) + 3)).from_address(lo)
            state[body] = (view, *((x - lo) // ctypes.sizeof(_ode.dReal) for x in a))
        real = ctypes.sizeof(_ode.dReal)
        geom = _ode.dContact.geom.offset
        P = (geom + _ode.dContactGeom.pos.offset) // real  # indices into a contact's dReals
        N = (geom + _ode.dContactGeom.normal.offset) // real
        F = _ode.dContact.fdir1.offset // real
        min_slip2 = self.min_slip ** 2
        coulomb = self.coulomb
        MU = _ode.dContact.surface.offset // real + _ode.dSurfaceParameters.mu.offset // real
        MU2 = _ode.dContact.surface.offset // real + _ode.dSurfaceParameters.mu2.offset // real
        sqrt, half = math.sqrt, math.sqrt(0.5)
        ratio = self.settings.friction_ratio
        axles = self.axles if ratio != 1.0 else {}  # empty: the isotropic path, unchanged
        r2 = ratio * ratio

        if not self.slip_directions:
            def near(_data, g1, g2):
                # the pair's contact buffer: its surface (mode, mu) is preset, dCollide fills
                # the geometry of each dContact in place (stride = sizeof(dContact))
                contacts = surface_of.get(g1) or surface_of.get(g2) or robot_contacts
                n = collide(g1, g2, max_contacts, contacts[0], stride)
                if n:
                    b1, b2 = body_of.get(g1), body_of.get(g2)
                    for address in contacts[1][:n]:
                        attach(create(world, group, address), b1, b2)

            return _ode.dNearCallback(near)

        def near(_data, g1, g2):
            contacts = surface_of.get(g1) or surface_of.get(g2) or robot_contacts
            n = collide(g1, g2, max_contacts, contacts[0], stride)
            if n:
                b1, b2 = body_of.get(g1), body_of.get(g2)
                for i in range(n):
                    c = contacts[2][i]
                    px, py, pz, nx, ny, nz = c[P], c[P + 1], c[P + 2], c[N], c[N + 1], c[N + 2]
                    vx = vy = vz = 0.0
                    for body, sign in ((b1, 1.0), (b2, -1.0)):  # velocity of b1 relative to b2
                        if body:
                            b, x, v, w = state[body]
                            rx, ry, rz = px - b[x], py - b[x + 1], pz - b[x + 2]
                            wx, wy, wz = b[w], b[w + 1], b[w + 2]
                            vx += sign * (b[v] + wy * rz - wz * ry)
                            vy += sign * (b[v + 1] + wz * rx - wx * rz)
                            vz += sign * (b[v + 2] + wx * ry - wy * rx)
                    d = vx * nx + vy * ny + vz * nz
                    vx, vy, vz = vx - d * nx, vy - d * ny, vz - d * nz
                    s2 = vx * vx + vy * vy + vz * vz
                    if s2 > min_slip2:
                        k = 1.0 / sqrt(s2)
                        c[F], c[F + 1], c[F + 2] = vx * k, vy * k, vz * k
                        if coulomb:  # sliding: mu N against the slip, nothing across it
                            c[MU2] = 0.0
                    elif abs(nz) > half:  # dPlaneSpace (ODE's choice when fdir1 is not given)
                        k = 1.0 / sqrt(ny * ny + nz * nz)
                        c[F], c[F + 1], c[F + 2] = 0.0, -nz * k, ny * k
                    else:
                        k = 1.0 / sqrt(nx * nx + ny * ny)
                        c[F], c[F + 1], c[F + 2] = -ny * k, nx * k, 0.0
                    if coulomb and s2 <= min_slip2:  # sticking: the full pyramid holds it
                        c[MU2] = c[MU]
                    if axles:
                        wheel = axles.get(b1) or axles.get(b2)
                        if wheel is not None:
                            self._elliptic(c, wheel, contacts[3], nx, ny, nz, vx, vy, vz, s2 > min_slip2,
                                           ratio, r2, F, MU, MU2)
                        else:
                            c[MU] = contacts[3]
                            if s2 <= min_slip2:
                                c[MU2] = c[MU]
                    attach(create(world, group, contacts[1][i]), b1, b2)

        return _ode.dNearCallback(near)

    @staticmethod
    def _elliptic(c, wheel, mu, nx, ny, nz, vx, vy, vz, sliding, ratio, r2, F, MU, MU2) -> None:
        """A driven wheel's contact with friction ratio ``ratio`` (OdeSettings.friction_ratio):
        sliding, the elliptic Coulomb force along fdir1 alone; sticking, the box in the wheel frame."""
        R, (a0, a1, a2) = wheel
        # world hinge axis (dMatrix3: 3 rows of 4), its part in the contact plane = lateral t
        ax, ay, az = R[0] * a0 + R[1] * a1 + R[2] * a2, R[4] * a0 + R[5] * a1 + R[6] * a2, \
            R[8] * a0 + R[9] * a1 + R[10] * a2
        d = ax * nx + ay * ny + az * nz
        tx, ty, tz = ax - d * nx, ay - d * ny, az - d * nz
        k = 1.0 / math.sqrt(tx * tx + ty * ty + tz * tz)
        tx, ty, tz = tx * k, ty * k, tz * k
        lx, ly, lz = ny * tz - nz * ty, nz * tx - nx * tz, nx * ty - ny * tx  # rolling direction n x t
        if sliding:
            sl, st = vx * lx + vy * ly + vz * lz, vx * tx + vy * ty + vz * tz
            fl, ft = sl, r2 * st
            size = math.sqrt(fl * fl + ft * ft)
            c[F], c[F + 1], c[F + 2] = (fl * lx + ft * tx) / size, (fl * ly + ft * ty) / size, \
                (fl * lz + ft * tz) / size
            c[MU] = mu * size / math.sqrt(sl * sl + r2 * st * st)
            c[MU2] = 0.0
        else:
            c[F], c[F + 1], c[F + 2] = lx, ly, lz
            c[MU], c[MU2] = mu, ratio * mu

    def _set_wheels(self, speeds) -> None:
        set_param, vel = self.lib.dJointSetHingeParam, _ode.dParamVel
        for hinge, w in zip(self.all_hinges, speeds):
            set_param(hinge, vel, w)

    def bare_loop(self, dt: float, wheel_commands: np.ndarray) -> float:
        """Wall seconds for the steps alone (collision + solver), recording nothing."""
        lib = self.lib
        self._set_wheels(wheel_commands[0].ravel().tolist())
        callback = self._near_callback()
        space_collide, step, empty = lib.dSpaceCollide, self.step_fn, lib.dJointGroupEmpty
        space, world, group = self.space, self.world, self.group
        start = time.perf_counter()
        for _ in range(wheel_commands.shape[0]):
            space_collide(space, None, callback)
            step(world, dt)
            empty(group)
        return time.perf_counter() - start

    def run(self, dt: float, wheel_commands: np.ndarray):
        lib = self.lib
        steps, n_robots = wheel_commands.shape[:2]

        # The recorded robot's state is copied each step straight from ODE's body memory: one
        # memmove of the span holding a body's position, quaternion and velocities (addresses
        # from dBodyGet*), so the loop creates no Python objects for it.
        chassis, hinges, wheels = self.robots[self.recorded]
        getters = (lib.dBodyGetPosition, lib.dBodyGetQuaternion, lib.dBodyGetLinearVel, lib.dBodyGetAngularVel)
        chunks, layout, width = [], [], 0
        for body in [chassis] + wheels:
            addresses = [g(body) for g in getters]
            lo, hi = min(addresses), max(addresses) + 4 * 8
            if hi - lo <= 1024:  # one contiguous copy per body
                chunks.append((lo, hi - lo, width))
                layout.append([width + (a - lo) // 8 for a in addresses])
                width += (hi - lo) // 8
            else:  # body state not close together: copy each vector on its own
                cols = []
                for a in addresses:
                    chunks.append((a, 32, width))
                    cols.append(width)
                    width += 4
                layout.append(cols)
        buffer = np.zeros((steps, width))
        row_bytes = width * 8
        base = buffer.ctypes.data
        copies = tuple((src, size, off * 8) for src, size, off in chunks)

        callback = self._near_callback()
        changes = np.flatnonzero(np.any(np.diff(wheel_commands, axis=0, prepend=np.nan) != 0, axis=(1, 2)))
        change_set = set(changes.tolist())
        space_collide, step, empty, memmove = lib.dSpaceCollide, self.step_fn, lib.dJointGroupEmpty, ctypes.memmove
        space, world, group = self.space, self.world, self.group
        ok = 1

        _ode.messages.clear()
        cpu0, wall0 = time.process_time(), time.perf_counter()
        for k in range(steps):
            if k in change_set:
                self._set_wheels(wheel_commands[k].ravel().tolist())
            space_collide(space, None, callback)
            ok &= step(world, dt)
            empty(group)
            row = base + k * row_bytes
            for src, size, off in copies:
                memmove(row + off, src, size)
        wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
        if _ode.messages:
            LOG.warning("ODE messages during %d steps: %s", steps,
                        "; ".join(f"{n} x ODE message {num}: {text!r}" for (num, text), n in _ode.messages.items()))
        if not ok:
            raise SimulationFailure("ODE's stepper failed (dWorldStep/dWorldQuickStep returned 0: out of memory)")

        def columns(body_index: int, which: int, n: int) -> np.ndarray:
            c = layout[body_index][which]
            return buffer[:, c:c + n]

        com, quat = columns(0, 0, 3), columns(0, 1, 4).copy()
        com_v, omega = columns(0, 2, 3), columns(0, 3, 3).copy()
        quat /= np.linalg.norm(quat, axis=1, keepdims=True)
        rot = rotation_matrices(quat)
        offset = rot @ self.model.chassis.com
        position = com - offset
        velocity = com_v - np.cross(omega, offset)
        wheel_speed = np.empty((steps, len(self.model.wheels)))
        for j, (_, jrot, axis, _) in enumerate(self.model.wheels):
            axis_world = rot @ (jrot @ axis)
            wheel_speed[:, j] = np.einsum("ni,ni->n", columns(1 + j, 3, 3) - omega, axis_world)
        return position, quat, velocity, omega, wheel_speed, wall, cpu


class OdeEngine:
    name = "ode"
    settings_model = OdeSettings
    calibratable = {
        "friction": FRICTION,
        # Force-dependent slip, (m/s)/N: a Husky wheel's friction force is about mu x 170 N (up to
        # ~130 N at mu 0.75), so 5e-3 lets it creep at up to ~0.6 m/s, beyond the runs' 0.5 m/s:
        # the range spans rigid (0) to fully compliant.
        "contact_slip": Calibratable(0.0, 5.0e-3, why="0 (rigid) to creep beyond the runs' speeds"),
        # Global constraint force mixing (the softness of every constraint, contacts included): two
        # decades either side of ODE's and Webots' default 1e-5 (the ODE manual: larger is softer).
        "cfm": Calibratable(1.0e-7, 1.0e-3, log=True, why="two decades either side of the 1e-5 default"),
        # the turning parameter (issue 20): base.FRICTION_RATIO, the adapter's friction_ratio
        "friction_ratio": FRICTION_RATIO,
    }

    def version(self) -> str:
        return _ode.version()

    def bare_loop(self, scenario: Scenario, wheel_commands: np.ndarray) -> float:
        wheel_commands = validated_commands(scenario, wheel_commands)
        world = _World(_ode.load(), scenario)
        try:
            return world.bare_loop(scenario.timestep, wheel_commands)
        finally:
            world.destroy()

    def simulate(self, scenario: Scenario, wheel_commands: np.ndarray) -> PhysicsRecord:
        wheel_commands = validated_commands(scenario, wheel_commands)
        world = _World(_ode.load(), scenario)
        try:
            position, quat, velocity, omega, wheels, wall, cpu = world.run(scenario.timestep, wheel_commands)
        finally:
            world.destroy()
        dt = scenario.timestep
        steps = wheel_commands.shape[0]
        specific_force, gyro = imu_from_kinematics(quat, velocity, omega, scenario.robot.imu_mount, dt, scenario.gravity)
        return PhysicsRecord(time=dt * np.arange(1, steps + 1), position=position, quaternion=quat,
                             linear_velocity=velocity, angular_velocity=omega, wheel_speed=wheels,
                             imu_specific_force=specific_force, imu_gyro=gyro,
                             wall_time=wall, cpu_time=cpu, steps=steps)
