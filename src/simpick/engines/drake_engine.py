"""Drake (Toyota Research Institute) through ``pydrake``: a discrete-time MultibodyPlant.

- robot: the scenario's URDF through Drake's parser (a free-floating base link, continuous joints
  as revolute joints); masses, inertias and collision shapes as the URDF gives them. Any
  :class:`~simpick.inputs.robot.RobotSpec`: the driven wheels get actuators in command order (their
  joint's own sign), casters and swivels stay free revolute joints, a skid is a base collision
  with the robot's friction (point contact, not hydroelastic), and one robot's bodies never collide
  with each other (a collision filter; Drake itself excludes only bodies joined by a joint).
- wheels: one joint actuator per wheel joint with Drake's implicit PD control (proportional gain
  0, derivative gain ``wheel_drive_damping``) and effort limit ``scenario.max_wheel_torque``:
  the controller is solved inside the discrete contact problem, the counterpart of PhysX's
  implicit velocity drive and MuJoCo's servo, and of DART's SERVO joints. Implicit PD needs one
  of the SAP-family solvers (``discrete_approximation``).
- passive suspension (rockers): the parser's revolute joints with their limits (SAP limit constraints) and
  damping (implicit joint damping); the friction MultibodyPlant lacks as an actuator with implicit PD
  bounded by the friction (SUSPENSION_FRICTION_DAMPING); each coupling is the coupler constraint the
  parser adds for the <mimic> that :func:`simpick.engines.suspension.coupled_urdf` writes (SAP-family
  solvers only, which are all that ``discrete_approximation`` offers). Measured on the Warthog (1 kHz,
  mu 0.8, 500 N m): pitch -0.003 degrees at rest, base 1.1 mm below 0.41 m (the wheels' hydroelastic
  sag); uncoupled, on a rocker stop at 8.598 degrees; spin gain 0.590 (Coulomb 0.591).
- contact: compliant. ``contact_model: hydroelastic`` gives every wheel a compliant-hydroelastic
  collision (modulus ``hydroelastic_modulus``) and the ground and terrain rigid-hydroelastic
  ones, so a wheel presses a contact *patch* into the ground; ``point`` leaves Drake's point
  contact (one point per wheel, stiffness from Drake's 1 mm penetration allowance).
- friction: Drake combines two coefficients as 2 a b / (a + b). The robot's shapes get 1, every
  ground or terrain shape mu / (2 - mu), so a wheel contact has exactly the terrain's (or the
  ground's) mu (below 2) and robot-robot contacts 1.0, as in PyBullet and DART.
- IMU: none in Drake; :func:`simpick.engines.kinematics.imu_from_kinematics` from base_link kinematics. The
  floating base's generalized velocity is the angular velocity and the velocity of base_link's
  origin, both in the world frame, read from the state vector after each step.

Set-up, measured with drake 1.51.1 at 1 kHz on mu 0.8, 4 s runs, yaw-rate gain
(yaw rate / commanded w) averaged after 1 s, against the quasi-static Coulomb 0.478:
  contact, approximation                      (0.5,0.5)  (0,0.5)  (0.5,0.2)  wall for 4 s
  point, sap (damping 1e3 / 1e4 / 1e5)        0.38 / 0.39 / 0.39  0.39  0.44-0.45   0.7-1.5 s
  point, similar                              0.518      0.515    0.535      1.4 s
  point, lagged                               0.536      0.536    0.535      0.9-1.3 s
  hydroelastic 1e7 Pa, lagged                 0.471      0.477    0.473      3.5 s
  hydroelastic 1e6 Pa, lagged                 0.464      0.473    0.461      4.4-5.1 s
  hydroelastic 1e7 Pa, sap                    0.462      0.467    0.457      2.6-3.5 s
SAP under-turns with point contact: Drake's docs name the cause, SAP's and kSimilar's O(dt)
"gliding" in sliding contact. With point contact every approximation turns the robot as if the
four wheel loads were equal (equal-load Coulomb value 0.539): one point per wheel on a compliant
contact. Hydroelastic wheels carry a pressure patch whose centre shifts with the load, and turn
at the Coulomb value within 0.01, heading-independent; they cost about 3x the point contact's time.
Drake's own recommendation for robotics is ``lagged`` (DiscreteContactApproximation docs: "kLagged
is the preferred approximation when strong transients are not expected"; MultibodyPlantConfig's
default); TAMSI is deprecated for removal (2026-09-01) and cannot run implicit PD actuators.

The plant's own step (``time_step``; config.yaml: 4 ms in a 1 ms run, the state held between updates),
measured 2026-11-27 in process CPU on a loaded 2-core machine (bench/ENGINE_SPEED.md):
  time_step  Husky validation        Warthog validation            CPU: Husky valid.  a DRIVE step
  1 ms       every case passes       all but the parked creep      1                1 (5.6 s per 9 s)
  2 ms       every case passes       the same (creep 2.6 mm/s)     0.59             0.60
  4 ms       every case passes       the same (creep 2.6 mm/s)     0.32             0.37
Husky gains at 4 ms 0.4686 / 0.4773 / 0.4696 at (0.5, 0.5) / (0, 0.5) / (0.5, 0.2) (1 ms: 0.4707 / 0.4774 /
0.4730). Point contact costs 0.37x on DRIVE too, but turns at the equal-load 0.536 (above).
Where a step's time goes (perf, hydroelastic, lagged, 1 ms, a DRIVE step): the SAP solve 36 %, the
hydroelastic contact surfaces 23 %, setting up the contact problem 24 %, the rest 17 %.
"""

from __future__ import annotations

import importlib.metadata
import logging
from typing import Annotated, Literal

import numpy as np
from pydantic import Field

from simpick.engines.base import FRICTION, BaseStates, Calibratable, EngineSettings, Scenario, engine_step_multiple
from simpick.engines.runner import Adapter
from simpick.engines.suspension import coupled_urdf
from simpick.errors import InputError

SPAWN_CLEARANCE = 0.002  # m above resting height, as for the other engines
# N m s/rad, derivative gain of a suspension joint's friction actuator (an implicit PD with gain 0 on position,
# bounded by the joint's Coulomb friction): the bound is reached above friction / gain rad/s (5e-5 rad/s for the
# Warthog's 0.5 N m), so the joint sticks below that and slides against +-friction above it: Coulomb friction
# regularised over a band far below any rocker motion, solved implicitly with the contacts like the wheels' servo.
SUSPENSION_FRICTION_DAMPING = 1.0e4
ROBOT_FRICTION = 1.0  # the robot's coefficient; the terrain's is chosen so that the combination is its mu
# A wheel's compliant mesh is resolved to at most its radius / 8, so that a small wheel has as many
# sides as the Husky's (0.02 m on r 0.165: 52 sides; r / 8: 51 and more). Drake's mesh has
# 2 pi r / resolution sides: at a fixed 0.02 m a 33 mm wheel (a TurtleBot3-like skid robot)
# was an 11-sided prism and the robot, driven straight at 0.2 m/s for 1.5 s, yawed 0.38 rad and
# ended 5.0 cm sideways; at r / 4 (26 sides) 0.048 rad and 1.0 cm; at r / 8 0.023 rad and 0.75 cm,
# as with point contact (0.028 rad, 0.9 cm). The diff-drive robot's 50 mm wheel at 0.02 m (16 sides)
# turned it at 0.876 of w at (0.5, 0.5) and rolled it at 0.943 of the wheel speed; at r / 8 0.993
# and 0.996 (validation cases). The Jackal's (r 0.098 m, 31 -> 51 sides) gains moved by <= 0.004.
WHEEL_MESH_PER_RADIUS = 8


class DrakeSettings(EngineSettings):
    """config ``engines.drake``; the measurements behind each choice are in the module docstring."""

    # "hydroelastic": compliant-hydroelastic wheels on rigid-hydroelastic ground and terrain (a
    # pressure patch per wheel), the Coulomb gain within 0.01; "point": Drake's point contact, one
    # point per wheel, gain 0.536 (as if the four loads were equal) with "lagged"
    contact_model: Literal["hydroelastic", "point"] = "hydroelastic"
    # MultibodyPlant discrete contact approximation: "lagged", Drake's default and its documented
    # choice for robotics; "similar" and "sap" add O(dt) gliding in sliding contact (Drake's docs):
    # sap turned the Husky at 0.38-0.39 with point contact. TAMSI (deprecated) cannot run implicit PD.
    discrete_approximation: Literal["lagged", "similar", "sap"] = "lagged"
    # Pa, the wheels' hydroelastic modulus ("hydroelastic" only): 1e7 rests base_link 0.5 mm low,
    # 1e6 2.3 mm (a tyre's deflection is of that order) with gains within 0.01 and 1.3-1.4x the time
    hydroelastic_modulus: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 1.0e7
    # m, the resolution hint of the wheels' compliant mesh (at most radius / WHEEL_MESH_PER_RADIUS)
    # and of the terrain's spheres (at most a quarter of the radius) ("hydroelastic" only): 2 cm
    # gives a 52-sided wheel of radius 0.165 m; measured 5 mm: torque-bound acceleration 0.641 for
    # 0.652 (Drake's default dissipation).
    # 4 cm half-sunk stones meshed at 2 cm lifted an axle 37.8 mm, at r/4 38.6-38.7 mm (exact: 40)
    mesh_resolution: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 0.02
    # N m s/rad, derivative gain of the wheels' implicit PD controllers (proportional gain 0):
    # 1e3 / 1e4 / 1e5 gave the same turning gains within 0.01 (point, sap); 1e4 tracks within 1 %
    wheel_drive_damping: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 1.0e4
    # s/m, Hunt-Crossley dissipation of the wheels' contact (lagged and similar): it is the tyre's
    # rolling resistance. With the wheel torque bound at 2 N m the Husky accelerates at 0.765 /
    # 0.764 / 0.759 / 0.749 m/s^2 for 0 / 0.1 / 1 / 5 s/m (analytic, no rolling resistance: 0.768);
    # left unset, Drake's default gave 0.652 (-15 %). 0.2: the turning gains in the docstring.
    wheel_dissipation: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 0.2
    # m/s, the regularised friction's stiction tolerance (lagged and similar): Drake's default
    stiction_tolerance: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 1.0e-4
    # s, the plant's own discrete step, a whole multiple of physics.timestep (simpick.engines.base.
    # engine_step_multiple: the run still records every physics step, the plant's state held between its
    # updates); None: physics.timestep. Measured in docs/engines.md (Drake: its step) and config.yaml.
    time_step: Annotated[float, Field(gt=0, allow_inf_nan=False)] | None = None


def _terrain_friction(mu: float, where: str) -> float:
    """The coefficient that, combined with the robot's 1.0 by Drake's 2ab/(a+b), gives ``mu``."""
    if not 0 <= mu < 2 * ROBOT_FRICTION:
        raise InputError(
            where,
            f"friction {mu} cannot be represented in Drake's combination with the robot's {ROBOT_FRICTION}",
            "use a coefficient below 2",
        )
    return mu * ROBOT_FRICTION / (2 * ROBOT_FRICTION - mu)


class DrakeEngine(Adapter):
    calibratable = {
        "friction": FRICTION,
        # Tyre stiffness (hydroelastic): from a soft 1e5 Pa (a few cm of sag) to a near-rigid 1e8;
        # log scale. Measured gains at 1e6 and 1e7 within 0.01 of each other (module docstring).
        "hydroelastic_modulus": Calibratable(
            1.0e5, 1.0e8, log=True, why="soft rubber (1e5 Pa) to near-rigid (1e8 Pa); 1e6-1e7 measured"
        ),
    }
    name = "drake"
    settings_model = DrakeSettings
    simulates_suspension = True

    def version(self) -> str:
        return importlib.metadata.version("drake")

    def build(self, scenario: Scenario) -> DrakeWorld:
        """The simulator of the plant, a logger sampling the plant's state every step."""
        from pydrake.geometry import (
            AddCompliantHydroelasticProperties,
            AddContactMaterial,
            AddRigidHydroelasticProperties,
            Box,
            CollisionFilterDeclaration,
            HalfSpace,
            ProximityProperties,
            RoleAssign,
            Sphere,
        )
        from pydrake.math import RigidTransform, RotationMatrix
        from pydrake.multibody.parsing import Parser
        from pydrake.multibody.plant import (
            AddMultibodyPlantSceneGraph,
            ContactModel,
            CoulombFriction,
            DiscreteContactApproximation,
        )
        from pydrake.multibody.tree import PdControllerGains
        from pydrake.systems.analysis import Simulator
        from pydrake.systems.framework import DiagramBuilder
        from pydrake.systems.primitives import LogVectorOutput, TrajectorySource
        from pydrake.trajectories import PiecewisePolynomial

        settings = DrakeSettings.of(scenario.settings, self.name)
        hydro = settings.contact_model == "hydroelastic"
        builder = DiagramBuilder()
        plant_step = scenario.timestep * engine_step_multiple(settings.time_step, scenario.timestep)
        plant, scene_graph = AddMultibodyPlantSceneGraph(builder, time_step=plant_step)
        plant.set_discrete_contact_approximation(
            getattr(DiscreteContactApproximation, "k" + settings.discrete_approximation.capitalize())
        )
        plant.set_contact_model(ContactModel.kHydroelasticWithFallback if hydro else ContactModel.kPoint)
        plant.set_stiction_tolerance(settings.stiction_tolerance)
        plant.mutable_gravity_field().set_gravity_vector(np.asarray(scenario.gravity, dtype=float))

        def surface(mu: float, where: str, resolution: float | None = None) -> ProximityProperties:
            props = ProximityProperties()
            f = _terrain_friction(mu, where)
            # Drake's CoulombFriction is isotropic (static, dynamic): no lateral/longitudinal ratio
            AddContactMaterial(friction=CoulombFriction(f, f), properties=props)
            if hydro:  # a sphere's rigid mesh needs a resolution; boxes and the half space are exact
                AddRigidHydroelasticProperties(resolution, props) if resolution else AddRigidHydroelasticProperties(
                    props
                )
            return props

        world = plant.world_body()
        terrain = scenario.terrain
        mu = float(terrain.friction)
        for k, (x, y, z, yaw, sx, sy, sz) in enumerate(terrain.boxes):
            plant.RegisterCollisionGeometry(
                world,
                RigidTransform(RotationMatrix.MakeZRotation(yaw), [x, y, z]),
                Box(sx, sy, sz),
                f"box{k}",
                surface(mu, "terrain friction"),
            )
        for k, (x, y, z, r) in enumerate(terrain.spheres):
            plant.RegisterCollisionGeometry(
                world,
                RigidTransform([x, y, z]),
                Sphere(r),
                f"sphere{k}",
                surface(mu, "terrain friction", min(settings.mesh_resolution, r / 4)),
            )
        # The ground plane last: with the HalfSpace registered first, registering the gravel strip's
        # 485 stones on the world body crashed Drake 1.51.1 (segmentation fault after 300-380 of them,
        # hydroelastic or not); registered after them, it does not.
        plant.RegisterCollisionGeometry(
            world, RigidTransform(), HalfSpace(), "ground", surface(scenario.ground_friction, "physics.ground_friction")
        )

        robot = scenario.robot
        parser = Parser(plant)
        parser.SetAutoRenaming(True)
        robots = []
        drake_log = logging.getLogger("drake")
        # the robot's file with its <mimic> elements exactly the spec's couplings: Drake's parser turns each into
        # a coupler constraint (MultibodyPlant.AddCouplerConstraint: q1 = multiplier q0 + offset, a SAP constraint
        # acting on both joints), so every coupling is applied once; checked below
        urdf = coupled_urdf(robot)
        for _start in scenario.starts:
            constraints = plant.num_constraints()
            drake_log.addFilter(_applied_friction)
            try:
                (instance,) = parser.AddModels(str(urdf))
            except (RuntimeError, ValueError) as exc:
                raise InputError(str(robot.urdf), f"Drake's URDF parser could not read the robot: {exc}") from None
            finally:
                drake_log.removeFilter(_applied_friction)
            wheels = []
            radius = {}  # wheel body name -> its radius, for the compliant mesh's resolution
            for wheel in robot.driven:
                joint = plant.GetJointByName(wheel.joint, instance)
                actuator = plant.AddJointActuator(f"{wheel.joint}_drive", joint, scenario.max_wheel_torque)
                actuator.set_controller_gains(PdControllerGains(p=0.0, d=settings.wheel_drive_damping))
                wheels.append(joint)
                radius[joint.child_body().name()] = wheel.radius
            _suspend(plant, instance, robot, plant.num_constraints() - constraints)
            for body in plant.GetBodyIndices(instance):
                for geometry in plant.GetCollisionGeometriesForBody(plant.get_body(body)):
                    props = ProximityProperties()
                    is_wheel = plant.get_body(body).name() in radius
                    AddContactMaterial(
                        dissipation=settings.wheel_dissipation if is_wheel else None,
                        friction=CoulombFriction(ROBOT_FRICTION, ROBOT_FRICTION),
                        properties=props,
                    )
                    if hydro and is_wheel:
                        AddCompliantHydroelasticProperties(
                            min(settings.mesh_resolution, radius[plant.get_body(body).name()] / WHEEL_MESH_PER_RADIUS),
                            settings.hydroelastic_modulus,
                            props,
                        )
                    scene_graph.AssignRole(plant.get_source_id(), geometry, props, RoleAssign.kReplace)
            # a robot's own links never touch each other, as in the other engines; Drake filters only
            # bodies joined by a joint, so the diff-drive robot's caster wheel (the chassis's
            # grandchild, its top level with the chassis's underside) was in contact with the chassis
            bodies = [plant.get_body(b) for b in plant.GetBodyIndices(instance)]
            scene_graph.collision_filter_manager().Apply(
                CollisionFilterDeclaration().ExcludeWithin(plant.CollectRegisteredGeometries(bodies))
            )
            robots.append((instance, wheels))
        plant.Finalize()
        # the state after every physics step, sampled inside Drake (at 0, dt, 2 dt ...; with a time_step of several
        # physics steps the state between two plant updates is held): the runner advances once per command
        # change instead of once per step (per-step AdvanceTo ran at 0.6x the bare loop)
        logger = LogVectorOutput(plant.get_state_output_port(), builder, scenario.timestep)
        # each robot's desired state (the PD actuators' targets) from a trajectory inside the diagram: a whole
        # run of commands is one AdvanceTo (DrakeWorld.rollout), where a replay whose command changes every step
        # (DRIVE's interpolated wheel speeds) took an AdvanceTo and a FixValue per step
        sources = []
        for instance, _ in robots:
            width = plant.get_desired_state_input_port(instance).size()
            source = builder.AddSystem(TrajectorySource(PiecewisePolynomial(np.zeros((width, 1)))))
            builder.Connect(source.get_output_port(), plant.get_desired_state_input_port(instance))
            sources.append(source)
        diagram = builder.Build()
        level = drake_log.level
        drake_log.setLevel(logging.ERROR)  # "half spaces are not supported for deformable contact": none here
        try:
            simulator = Simulator(diagram)
            context = plant.GetMyMutableContextFromRoot(simulator.get_mutable_context())
            for (instance, _), (x, y, yaw) in zip(robots, scenario.starts):
                base = plant.GetBodyByName(robot.base_link, instance)
                plant.SetFreeBodyPose(
                    context,
                    base,
                    RigidTransform(RotationMatrix.MakeZRotation(yaw), [x, y, robot.base_height + SPAWN_CLEARANCE]),
                )
                plant.get_actuation_input_port(instance).FixValue(context, np.zeros(plant.num_actuated_dofs(instance)))
            simulator.Initialize()
        finally:
            drake_log.setLevel(level)
        return DrakeWorld(simulator, plant, context, robots, logger, scenario, sources)


def _applied_friction(record: logging.LogRecord) -> bool:
    """Drops the parser's warning that MultibodyPlant has no joint friction: _suspend applies it."""
    return "'friction' attribute of a joint/dynamics tag" not in record.getMessage()


def _suspend(plant, instance, robot, couplers: int) -> None:
    """One robot's passive suspension joints: limits, the description's damping, Coulomb friction through a
    bounded implicit-PD actuator (after the wheels' actuators, so the wheels keep the first rows), couplings."""
    from pydrake.multibody.tree import PdControllerGains

    # Drake's parser adds a coupler constraint per <mimic> with the SAP-family solvers (every
    # discrete_approximation offered here; with TAMSI it warns and ignores the element)
    if couplers != len(robot.couplings):
        raise RuntimeError(f"drake: {couplers} coupler constraints for the robot's {len(robot.couplings)} couplings")
    for sus in robot.suspension:
        joint = plant.GetJointByName(sus.joint, instance)
        # The parser reads <limit> and <dynamics damping>; set from the spec all the same. A discrete plant
        # enforces position limits as SAP limit constraints; the damping is joint damping, integrated
        # implicitly by the discrete solver.
        joint.set_position_limits([sus.lower], [sus.upper])
        joint.set_default_damping(sus.damping)
        if sus.friction > 0:
            # MultibodyPlant has no joint friction (its parser warns and drops <dynamics friction>): an
            # actuator with implicit PD, position gain 0, derivative gain SUSPENSION_FRICTION_DAMPING towards
            # zero speed, its effort limited to the friction, is a regularised Coulomb friction
            actuator = plant.AddJointActuator(f"{sus.joint}_friction", joint, sus.friction)
            actuator.set_controller_gains(PdControllerGains(p=0.0, d=SUSPENSION_FRICTION_DAMPING))


class DrakeWorld:
    """One Drake simulator (simpick.engines.base.World) whose logger records the plant's state every
    step (``logs_states``) and whose wheel targets come from a trajectory source inside the diagram:
    ``rollout`` runs a whole command array as one AdvanceTo. The floating base's generalized velocity is
    the angular velocity and the velocity of base_link's origin, both in the world frame."""

    logs_states = True

    def __init__(self, simulator, plant, context, robots: list, logger, scenario: Scenario, sources: list):
        self.simulator, self.plant, self.context, self.robots, self.logger = simulator, plant, context, robots, logger
        self.sources = sources
        self.dt, self.k = scenario.timestep, 0
        self.friction_actuators = sum(1 for s in scenario.robot.suspension if s.friction > 0)
        instance, wheels = robots[scenario.recorded_robot]
        base = plant.GetBodyByName(scenario.robot.base_link, instance)
        if not base.is_floating_base_body():
            raise InputError(str(scenario.robot.urdf), f"{scenario.robot.base_link} is not a free body in Drake")
        q0, v0 = base.floating_positions_start(), base.floating_velocities_start_in_v()
        nq = plant.num_positions()
        wheel_v = [nq + j.velocity_start() for j in wheels]
        self.columns = np.r_[q0 : q0 + 7, nq + v0 : nq + v0 + 6, wheel_v]  # quaternion w x y z, position; w, v; wheels

    def _desired(self, speeds: np.ndarray) -> np.ndarray:
        """(..., robots, 2 x actuators) desired states of ``speeds`` (..., robots, wheels): positions
        (ignored, gain 0), then speeds; the suspension's friction actuators follow the wheels' (speed 0)."""
        zeros = np.zeros((*speeds.shape[:-1], speeds.shape[-1] + self.friction_actuators))
        velocity = zeros.copy()
        velocity[..., : speeds.shape[-1]] = speeds
        return np.concatenate([zeros, velocity], axis=-1)

    def _hold(self, desired: np.ndarray) -> None:
        """Each robot's source holds ``desired`` (steps, robots, width) from step self.k on: sample i over
        [(k + i - 1/2) dt, (k + i + 1/2) dt), so the discrete update at (k + i) dt reads sample i whatever
        the roundoff of Drake's event times (a break on the update time could fall either side of it)."""
        from pydrake.trajectories import PiecewisePolynomial

        n = desired.shape[0]
        breaks = (self.k - 0.5 + np.arange(n + 1)) * self.dt
        for r, source in enumerate(self.sources):
            samples = desired[:, r, :].T
            source.UpdateTrajectory(PiecewisePolynomial.ZeroOrderHold(breaks, np.hstack([samples, samples[:, -1:]])))
        # the source's output is cached against the context's time, not its trajectory: invalidate it
        root = self.simulator.get_mutable_context()
        root.SetTime(root.get_time())

    def set_wheel_targets(self, speeds: np.ndarray) -> None:
        self._hold(self._desired(np.asarray(speeds, dtype=float))[None])

    def rollout(self, commands: np.ndarray) -> BaseStates:
        """The whole (steps, robots, wheels) command array as one trajectory and one AdvanceTo."""
        self._hold(self._desired(np.asarray(commands, dtype=float)))
        self.step(commands.shape[0])
        return self.states([])

    def step(self, n: int = 1) -> None:
        self.k += n
        self.simulator.AdvanceTo(self.k * self.dt)

    def _state(self) -> np.ndarray:
        log = self.logger.FindLog(self.simulator.get_context())
        if log.num_samples() != self.k + 1:  # one sample at t = 0, then one after each step
            raise RuntimeError(f"drake: logged {log.num_samples()} states for {self.k} steps")
        return log.data().T[1:, self.columns]

    def read(self) -> tuple:
        return tuple(self._state()[-1])

    def states(self, samples: list) -> BaseStates:
        state = self._state()
        quat = state[:, 0:4] / np.linalg.norm(state[:, 0:4], axis=1, keepdims=True)
        quat *= np.where(quat[:, :1] < 0, -1.0, 1.0)
        return BaseStates(
            position=state[:, 4:7].copy(),
            quaternion=quat,
            linear_velocity=state[:, 10:13],
            angular_velocity=state[:, 7:10],
            wheel_speed=state[:, 13:].copy(),
        )
