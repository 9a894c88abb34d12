"""Gazebo (gz-sim) through Gazebo's own physics layer: Ignition Physics 5's dartsim plugin with sdformat 12,
the physics layer of Gazebo Fortress (ROS 2 Humble's Gazebo), as Debian packages it.

The world is an SDF file, built and stepped by a small compiled program (``src/simpick/engines/gz``,
built by ``make gzphysics`` into ``build/gz/gzphysics_run``) that does what gz-sim's Physics system does
with it: the engine plugin loaded by ``ignition::plugin::Loader``, the world made by the plugin's own
``ConstructSdfWorld``, the ``<physics><dart>`` options set through its world features, a velocity command
per wheel joint every step through ``SetJointVelocityCommandFeature`` (what gz-sim's DiffDrive and
JointController systems write), one ``ForwardStep`` per step. The program's comments give the gz-sim and
gz-physics file and line of each. This module writes the SDF, starts the program and reads its answers.

- robot: the study's URDF converted by sdformat's own URDF parser (the program's ``convert``; fixed joints
  lumped, as gz-sim reads a URDF), one ``<model>`` per robot, named ``robot0``, ``robot1``, ... Each driven
  wheel joint's ``<limit><effort>`` is ``scenario.max_wheel_torque``: dartsim turns it into the bound of
  DART's SERVO actuator (gz-physics dartsim/src/SDFFeatures.cc:138-139, JointFeatures.cc:162-165), the
  same torque-bounded velocity servo as the DART adapter's.
- terrain: one static model whose link carries the ground plane and every box and sphere. dartsim builds a
  plane as a 2100 m box (dartsim/src/SDFFeatures.cc:281-303) and never collides shapes of one skeleton
  (self-collision off), so a stone is never paired with its bed, as in the DART adapter.
- friction (each value an SDF element; DART combines two shapes by the minimum, per direction: DART 6.12
  ContactConstraint.cpp, mPrimaryFrictionCoeff / mSecondaryFrictionCoeff = min of the two shapes'): the
  ground and terrain carry ``<mu>`` = their coefficient and ``<mu2>`` = ``friction_ratio`` x that; the robot's
  collisions mu = mu2 = max(1, terrain, ground), so the surface governs, as in the DART adapter, unless the
  wheels' own ``<mu>``/``<mu2>`` (``wheel_mu``, ``wheel_mu2``: the maker's tags) are lower. ``<fdir1>`` on a
  wheel's collision is read in that collision's frame (DART's first friction direction with no frame set is
  rotated by the shape node's world transform: ContactConstraint.cpp computeWorldFirstFrictionDir), and
  DART's first tangent, which takes the primary coefficient, is fdir1 projected on the contact plane
  (getTangentBasisMatrixODE: T.col(0) is n x (n x fdir1) turned back, "the same as mFirstFrictionalDirection").
  Without fdir1 DART's default direction is +z, parallel to a level ground's normal, and the tangents fall
  back to the world's x and y (the same function): the friction box is aligned with the world.
- slip: the wheels' ``<slip1>``/``<slip2>`` are DART's primary/secondary slip compliance (SDFFeatures.cc:818-825),
  the two shapes' summed, added as slip / dt to the friction rows' diagonal of DART's impulse LCP
  (ContactConstraint::getVelocityChange): a sliding speed of slip x friction force, whatever the step. Without
  slip the ground's ratio only switches the Husky's turn (gain 0.810 up to 0.7, 0 from 0.8, with fdir1); with
  both set (slip1 1e-3) the contact forces stay inside DART's box and the gain follows slip2 / slip1 smoothly
  (0.37 at slip2 5e-4, 0.674 at 2e-3, 0.868 at 1e-2 at mu 0.6-0.8), the same at every command: what Gazebo's
  calibrated profile fits, the ratio fixed at 1 (resources/simulators/calibration.yaml; the measurements in
  docs/gazebo_slip_grid.csv).
- IMU: dartsim has none that the physics layer exposes; :func:`simpick.engines.kinematics.imu_from_kinematics`.

Not read here because dartsim reads them nowhere (gz-physics dartsim/src at ignition-physics5_5.1.0 and at
gz-physics9: no ``kp``, ``kd``, ``soft_cfm`` or ``max_vel`` lookup): the surface's ``<contact><ode><kp>``/``<kd>``.
Clearpath's Husky sets kp 1e7, kd 1; under gz-sim's DART the contacts stay DART's rigid ones all the same,
which ``tests/test_gzphysics.py`` checks by running both.
"""

from __future__ import annotations

import functools
import os
import shutil
import subprocess
import tempfile
from pathlib import Path
from typing import Annotated, Literal
from xml.etree import ElementTree as ET

import numpy as np
from pydantic import Field, model_validator

from simpick.engines import runner
from simpick.engines.base import (
    FRICTION,
    FRICTION_RATIO,
    BaseState,
    BaseStates,
    EngineSettings,
    PhysicsRecord,
    Scenario,
)
from simpick.engines.runner import Adapter
from simpick.errors import InputError

ROOT = Path(__file__).resolve().parents[3]
# the program's sources (gzphysics_run.cc, CMakeLists.txt). Named here as the string "gz" so that the code
# version of every job that reaches this adapter hashes them (simpick.codeversion.data_files: a folder beside a
# reached module that the module names): editing the program reruns the Gazebo jobs, and no other engine's
SOURCE = ROOT / "src" / "simpick" / "engines" / "gz"
# where `make gzphysics` builds it; SIMPICK_GZPHYSICS names another build
PROGRAM = Path(os.environ.get("SIMPICK_GZPHYSICS", ROOT / "build" / "gz" / "gzphysics_run"))
SPAWN_CLEARANCE = 0.002  # m above resting height, as for the other engines
# the engine library by the name gz-sim's Physics system looks for by default (gz-sim ign-gazebo6
# src/systems/physics/Physics.cc:726-729). Its Bullet plugin is not offered: Ignition Physics 5.1.0's bullet plugin
# has no GetEntities features (bullet/src/plugin.cc:36-44 lists none), which the program uses to find the robot's
# links and joints in the world ConstructSdfWorld built; gz-sim keeps the entities its per-entity construct calls
# return instead.
PLUGIN = "libignition-physics-dartsim-plugin.so"


def require_program() -> None:
    """Raise, with the fix, where the program is not built (simpick.engines.unavailable calls this)."""
    if not PROGRAM.is_file() or not os.access(PROGRAM, os.X_OK):
        raise FileNotFoundError(
            f"{PROGRAM} is not built (Gazebo Fortress's physics layer: Debian's libignition-physics-dev, "
            f"libignition-physics5-dartsim-plugin5 and libsdformat-dev); build it from {SOURCE} with `make gzphysics`"
        )


class GzPhysicsSettings(EngineSettings):
    """A Gazebo (gz-sim) profile's settings (simulators.yaml): each field an SDF element that gz-sim
    reads, where the program writes it, and the default Gazebo applies when it is not written."""

    # <physics><dart><collision_detector>
    collision_detector: Literal["ode", "fcl", "bullet", "dart"] = Field(
        "ode",
        description="<physics><dart><collision_detector>, set through the world's CollisionDetector feature "
        "(gz-physics ignition-physics5_5.1.0 dartsim/src/WorldFeatures.cc:40-73). Gazebo's default is 'ode': "
        "gz-sim applies the element only where written (gz-sim ign-gazebo6 src/SdfEntityCreator.cc:303-310), "
        "and otherwise the world keeps the ODE detector of dartsim's ConstructEmptyWorld "
        "(dartsim/src/EntityManagementFeatures.cc:720-725), so SDF's own default 'fcl' never applies. Written "
        "always: 'ode' written makes the same detector",
    )
    # <physics><dart><solver><solver_type>
    solver_type: Literal["dantzig", "pgs"] = Field(
        "dantzig",
        description="<physics><dart><solver><solver_type>, set through the world's Solver feature "
        "(dartsim/src/WorldFeatures.cc:100-138; gz-sim src/SdfEntityCreator.cc:311-319). Gazebo's default is "
        "DART's own: a Dantzig boxed LCP with PGS as its fallback (DART 6.12 BoxedLcpConstraintSolver); "
        "'dantzig' written replaces the primary solver by the same one",
    )
    # the wheels' <surface><friction><ode><fdir1>
    fdir1: Literal["wheel_x", "none"] = Field(
        "none",
        description="<surface><friction><ode><fdir1> on the driven wheels' collisions: 'wheel_x' writes "
        "'1 0 0' (Clearpath's tag; in the collision's frame, turned pi/2 about x from the wheel link, so the "
        "wheel's rolling direction: dartsim/src/SDFFeatures.cc:826-831); 'none' writes nothing, and DART "
        "boxes the friction along the world's x and y",
    )
    # the wheels' <surface><friction><ode><mu>
    wheel_mu: Annotated[float, Field(gt=0, allow_inf_nan=False)] | None = Field(
        None,
        description="<surface><friction><ode><mu> on the driven wheels' collisions (dartsim/src/SDFFeatures.cc:813); "
        "None: max(1, terrain, ground), so the ground's coefficient governs the contact (DART takes the minimum)",
    )
    # the wheels' <surface><friction><ode><mu2>
    wheel_mu2: Annotated[float, Field(gt=0, allow_inf_nan=False)] | None = Field(
        None,
        description="<surface><friction><ode><mu2> on the driven wheels' collisions "
        "(dartsim/src/SDFFeatures.cc:814-817): the coefficient across fdir1; None: the wheels' mu",
    )
    # the ground's and terrain's <mu2> / <mu>
    friction_ratio: Annotated[float, Field(gt=0, allow_inf_nan=False)] = Field(
        1.0,
        description="the ground's and terrain's <mu2> over their <mu> (dartsim/src/SDFFeatures.cc:814-817): with "
        "fdir1 'wheel_x' the contact's coefficient across the wheel is this times the one along it "
        "(the anisotropic Coulomb model's r, simpick.coulomb with_friction_ratio), unless the wheels' own "
        "mu2 is lower (DART takes the minimum per direction)",
    )
    # the wheels' <surface><friction><ode><slip1>
    slip1: Annotated[float, Field(ge=0, allow_inf_nan=False)] | None = Field(
        None,
        description="<surface><friction><ode><slip1> on the driven wheels' collisions, m/s per N: DART's primary "
        "slip compliance, along fdir1 (dartsim/src/SDFFeatures.cc:818-821); None: not written, DART's default "
        "(no slip)",
    )
    # the wheels' <surface><friction><ode><slip2>
    slip2: Annotated[float, Field(ge=0, allow_inf_nan=False)] | None = Field(
        None,
        description="<surface><friction><ode><slip2> on the driven wheels' collisions, m/s per N: DART's secondary "
        "slip compliance, across fdir1 (dartsim/src/SDFFeatures.cc:822-825); None: not written",
    )
    # the wheels' <surface><contact><ode><kp> (read by no dartsim source)
    contact_kp: Annotated[float, Field(gt=0, allow_inf_nan=False)] | None = Field(
        None,
        description="<surface><contact><ode><kp> on the driven wheels' collisions, N/m: written as the maker "
        "tags it, read by no dartsim source (ignition-physics5_5.1.0, gz-physics9): no effect under gz-sim's DART",
    )
    # the wheels' <surface><contact><ode><kd> (read by no dartsim source)
    contact_kd: Annotated[float, Field(ge=0, allow_inf_nan=False)] | None = Field(
        None,
        description="<surface><contact><ode><kd> on the driven wheels' collisions, N s/m: written, read by no "
        "dartsim source (as contact_kp)",
    )

    @model_validator(mode="after")
    def _ratio_along_the_wheel(self):
        # <mu2> is the coefficient across <fdir1>: without fdir1 DART boxes friction along the world's axes, and a
        # wheel <mu2> of its own caps the ground's, so the ratio would not be the contact's
        if self.friction_ratio != 1.0 and self.fdir1 != "wheel_x":
            raise ValueError("friction_ratio needs fdir1: wheel_x (without <fdir1> <mu2> acts along the world's y)")
        wheel_mu = 1.0 if self.wheel_mu is None else self.wheel_mu  # None: at least 1 (world_sdf)
        if self.friction_ratio != 1.0 and self.wheel_mu2 is not None and self.wheel_mu2 < wheel_mu:
            raise ValueError(
                "friction_ratio with a wheel_mu2 below the wheels' mu: the wheels' <mu2> caps the contact's, so the "
                "ratio would not be the contact's; leave wheel_mu2 out (or at the wheels' mu) or friction_ratio at 1"
            )
        return self


def _text(parent: ET.Element, tag: str, value) -> ET.Element:
    element = ET.SubElement(parent, tag)
    element.text = value if isinstance(value, str) else " ".join(repr(float(v)) for v in np.atleast_1d(value))
    return element


def _surface(collision: ET.Element, mu: float, mu2: float, extra: dict | None = None, contact: dict | None = None):
    surface = collision.find("surface")
    if surface is not None:
        collision.remove(surface)
    surface = ET.SubElement(collision, "surface")
    ode = ET.SubElement(ET.SubElement(surface, "friction"), "ode")
    _text(ode, "mu", mu)
    _text(ode, "mu2", mu2)
    for tag, value in (extra or {}).items():
        _text(ode, tag, value)
    if contact:
        ode_contact = ET.SubElement(ET.SubElement(surface, "contact"), "ode")
        for tag, value in contact.items():
            _text(ode_contact, tag, value)


@functools.lru_cache(maxsize=8)
def converted_model(urdf: str, mtime_ns: int) -> str:
    """The robot's ``<model>`` as sdformat 12's URDF parser writes it (the program's ``convert``)."""
    require_program()
    done = subprocess.run([str(PROGRAM), "convert", urdf], capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise InputError(urdf, f"sdformat 12 could not convert the URDF: {done.stderr.strip()}")
    return done.stdout


def world_sdf(scenario: Scenario, settings: GzPhysicsSettings) -> str:
    """The scenario as one SDF world: physics, the terrain's static model and a model per robot."""
    return ET.tostring(world_tree(scenario, settings), encoding="unicode")


def world_tree(scenario: Scenario, settings: GzPhysicsSettings) -> ET.Element:
    """:func:`world_sdf`'s ``<sdf>`` element, which the model a user opens (simpick.engines.simulator_models.gazebo)
    writes with what drives it added and nothing else changed."""
    robot, terrain = scenario.robot, scenario.terrain
    model_xml = ET.fromstring(converted_model(str(robot.urdf), robot.urdf.stat().st_mtime_ns)).find("model")
    if model_xml is None:
        raise InputError(str(robot.urdf), "sdformat's conversion has no <model>")
    root = ET.Element("sdf", version="1.9")
    world = ET.SubElement(root, "world", name="simpick")
    _text(world, "gravity", scenario.gravity)
    physics = ET.SubElement(world, "physics", name="simpick", type="dart")
    _text(physics, "max_step_size", scenario.timestep)
    _text(physics, "real_time_factor", 0.0)
    dart = ET.SubElement(physics, "dart")
    _text(dart, "collision_detector", settings.collision_detector)
    _text(ET.SubElement(dart, "solver"), "solver_type", settings.solver_type)

    r = settings.friction_ratio
    ground = ET.SubElement(world, "model", name="terrain")
    _text(ground, "static", "true")
    link = ET.SubElement(ground, "link", name="ground")
    plane = ET.SubElement(link, "collision", name="plane")
    shape = ET.SubElement(ET.SubElement(plane, "geometry"), "plane")
    _text(shape, "normal", (0.0, 0.0, 1.0))
    _text(shape, "size", (100.0, 100.0))
    _surface(plane, scenario.ground_friction, r * scenario.ground_friction)
    mu = float(terrain.friction)
    for i, (x, y, z, yaw, sx, sy, sz) in enumerate(terrain.boxes):
        box = ET.SubElement(link, "collision", name=f"box{i}")
        _text(box, "pose", (x, y, z, 0.0, 0.0, yaw))
        _text(ET.SubElement(ET.SubElement(box, "geometry"), "box"), "size", (sx, sy, sz))
        _surface(box, mu, r * mu)
    for i, (x, y, z, radius) in enumerate(terrain.spheres):
        sphere = ET.SubElement(link, "collision", name=f"sphere{i}")
        _text(sphere, "pose", (x, y, z, 0.0, 0.0, 0.0))
        _text(ET.SubElement(ET.SubElement(sphere, "geometry"), "sphere"), "radius", radius)
        _surface(sphere, mu, r * mu)

    robot_mu = max(1.0, mu, float(scenario.ground_friction))
    wheel_mu = settings.wheel_mu if settings.wheel_mu is not None else robot_mu
    wheel_mu2 = settings.wheel_mu2 if settings.wheel_mu2 is not None else wheel_mu
    wheel_extra = {k: getattr(settings, k) for k in ("slip1", "slip2") if getattr(settings, k) is not None}
    if settings.fdir1 == "wheel_x":
        wheel_extra["fdir1"] = (1.0, 0.0, 0.0)
    contact = {
        tag: value for tag, value in (("kp", settings.contact_kp), ("kd", settings.contact_kd)) if value is not None
    }
    joints = {j.get("name"): j for j in model_xml.findall("joint")}
    wheel_links = set()
    for name in robot.wheel_joints:
        joint = joints.get(name)
        if joint is None:
            raise InputError(str(robot.urdf), f"sdformat's conversion has no joint {name!r}")
        wheel_links.add(joint.findtext("child"))
        limit = joint.find("axis/limit")
        if limit is None:
            limit = ET.SubElement(joint.find("axis"), "limit")
        for old in limit.findall("effort"):
            limit.remove(old)
        _text(limit, "effort", scenario.max_wheel_torque)
    for link_xml in model_xml.findall("link"):
        wheel = link_xml.get("name") in wheel_links
        for collision in link_xml.findall("collision"):
            if wheel:
                _surface(collision, wheel_mu, wheel_mu2, wheel_extra, contact)
            else:
                _surface(collision, robot_mu, robot_mu)
    model_text = ET.tostring(model_xml, encoding="unicode")
    for i, (x, y, yaw) in enumerate(scenario.starts):
        model = ET.fromstring(model_text)
        model.set("name", f"robot{i}")
        for old in model.findall("pose"):
            model.remove(old)
        pose = ET.Element("pose")
        pose.text = " ".join(repr(float(v)) for v in (x, y, robot.base_height + SPAWN_CLEARANCE, 0.0, 0.0, yaw))
        model.insert(0, pose)
        world.append(model)
    return root


class GzPhysicsEngine(Adapter):
    name = "gzphysics"
    settings_model = GzPhysicsSettings
    # the ground's coefficient, and the lateral/longitudinal ratio that <mu2> with <fdir1> sets
    calibratable = {"friction": FRICTION, "friction_ratio": FRICTION_RATIO}

    def version(self) -> str:
        require_program()
        return subprocess.run([str(PROGRAM), "version"], capture_output=True, text=True, check=True).stdout.strip()

    def build(self, scenario: Scenario) -> GzPhysicsWorld:
        settings = GzPhysicsSettings.of(scenario.settings, self.name)
        require_program()
        self.built = GzPhysicsWorld(scenario, world_sdf(scenario, settings))
        return self.built

    def simulate(self, scenario: Scenario, wheel_commands) -> PhysicsRecord:
        record = runner.simulate(self, scenario, wheel_commands)
        # the steps run in the program's process, whose CPU the runner's process_time does not count: the
        # program's own wall and CPU seconds of the stepping (simpick.engines.isolated does the same for its
        # workers by timing inside them)
        record.wall_time, record.cpu_time = self.built.wall, self.built.cpu
        return record


class GzPhysicsWorld:
    """One world in its own gzphysics_run process (simpick.engines.base.World). ``rollout`` sends the whole
    command array and reads every step's state back in one exchange; ``step``/``read`` do the same a span at
    a time (the conformance check and the bare loop)."""

    def __init__(self, scenario: Scenario, sdf: str):
        robot = scenario.robot
        self.wheels = len(robot.wheel_joints)
        self.robots = len(scenario.starts)
        self.row = 13 + self.wheels
        self.folder = Path(tempfile.mkdtemp(prefix="simpick-gz-"))
        path = self.folder / "world.sdf"
        path.write_text(sdf)
        self.stderr = open(self.folder / "stderr.txt", "w+b")  # noqa: SIM115 (closed in close())
        self.process = subprocess.Popen(
            [
                str(PROGRAM),
                "run",
                str(path),
                PLUGIN,
                f"robot{scenario.recorded_robot}",
                robot.base_link,
                *robot.wheel_joints,
            ],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=self.stderr,
        )
        ready = self.process.stdout.readline().decode().split()
        if ready[:1] != ["ready"] or ready[1:] != [str(self.robots), str(self.wheels)]:
            self.process.wait(timeout=30)
            error = self._error()
            self.close()
            raise RuntimeError(f"gzphysics_run did not build the world: {error}")
        self.targets = np.zeros(self.robots * self.wheels)
        self.last = None
        self.wall = self.cpu = 0.0  # s, the program's own, of every step so far

    def _error(self) -> str:
        self.stderr.flush()
        self.stderr.seek(0)
        return self.stderr.read().decode(errors="replace").strip()

    def _exchange(self, commands: np.ndarray) -> np.ndarray:
        steps = commands.shape[0]
        request = b"R" + np.int64(steps).tobytes() + np.ascontiguousarray(commands, dtype=np.float64).tobytes()
        try:
            self.process.stdin.write(request)
            self.process.stdin.flush()
            raw = self.process.stdout.read(8 * (steps * self.row + 2))
        except BrokenPipeError:
            raw = b""
        if len(raw) != 8 * (steps * self.row + 2):
            raise RuntimeError(f"gzphysics_run stopped: {self._error()}")
        values = np.frombuffer(raw, dtype=np.float64)
        self.wall += float(values[-2])
        self.cpu += float(values[-1])
        return values[:-2].reshape(steps, self.row)

    def set_wheel_targets(self, speeds: np.ndarray) -> None:
        self.targets = np.asarray(speeds, dtype=float).ravel().copy()

    def step(self, n: int = 1) -> None:
        self.last = self._exchange(np.broadcast_to(self.targets, (n, self.targets.size)))[-1]

    def read(self) -> BaseState:
        s = self.last
        return BaseState(s[0:3], s[3:7], s[7:10], s[10:13], s[13:])

    def rollout(self, commands: np.ndarray) -> BaseStates:
        rows = self._exchange(commands.reshape(commands.shape[0], -1))
        return BaseStates(
            position=rows[:, 0:3].copy(),
            quaternion=rows[:, 3:7] / np.linalg.norm(rows[:, 3:7], axis=1, keepdims=True),
            linear_velocity=rows[:, 7:10].copy(),
            angular_velocity=rows[:, 10:13].copy(),
            wheel_speed=rows[:, 13:].copy(),
        )

    def close(self) -> None:
        if self.process.poll() is None:
            try:
                self.process.stdin.write(b"Q")
                self.process.stdin.close()
            except BrokenPipeError:
                pass
            self.process.wait(timeout=30)
        self.process.stdout.close()
        self.stderr.close()
        shutil.rmtree(self.folder, ignore_errors=True)
