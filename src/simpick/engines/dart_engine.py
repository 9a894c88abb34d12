"""DART (Dynamic Animation and Robotics Toolkit, a Gazebo physics option) through ``dartpy``.

- robot: the same URDF through ``dart.utils.DartLoader``, whose default root joint is a
  FreeJoint (floating base). DART keeps a link's frame and its COM apart, so base_link's
  pose and the world velocity of its origin are read from the body node directly. The
  18 g IMU link stays a welded body.
- wheels: actuator type SERVO with force limits +-``scenario.max_wheel_torque``: a velocity
  constraint solved together with the contacts and bounded by the force limits, the same
  servo as PyBullet's VELOCITY_CONTROL and ODE's hinge motor. DART's VELOCITY actuator is
  *kinematic* (the joint velocity is prescribed whatever torque that takes), so the bound
  would be ignored and a wheel could never stall. ``World.step(False)``: by default DART
  zeroes the commands after every step.
- terrain: the ground plane, boxes and spheres as shapes of one static body. DART does not
  test shapes of one skeleton against each other (self collision is off), so a stone is
  never paired with its gravel bed.
- friction: DART takes the *minimum* of the two shapes' coefficients. Terrain shapes carry
  the terrain's coefficient, the plane ``scenario.ground_friction``, the robot's shapes
  max(1, terrain, ground): the contact's mu is the terrain's (or ground's), and
  robot-robot contacts get 1.0 (PyBullet's 1.0 x 1.0) as long as no terrain exceeds 1.
- passive suspension (rockers): the loader's revolute joints, PASSIVE, with limit enforcement switched on
  (the loader leaves it off), the description's damping (implicit joint damping) and friction (DART's
  joint Coulomb friction constraint); a coupling is DART's MIMIC joint, which the loader makes from the
  <mimic> that :func:`simpick.engines.suspension.coupled_urdf` writes for each of the spec's couplings.
  Measured on the Warthog (1 kHz, mu 0.8, 500 N m): level at rest (pitch 0.000 degrees, base 0.4100 m);
  uncoupled, the chassis rests on a rocker stop at 8.595 degrees (0.15 rad: 8.594); spin in place at
  rims (0.5, -0.5) m/s: yaw-rate gain 0.575 with DART's own NSGS stop, 0.564 with config.yaml's 1e-6 /
  200 sweeps (Coulomb 0.591), the base origin drifting at up to 0.15 m/s (Newton, Drake: below 0.01).
- IMU: DART has none; :func:`simpick.engines.kinematics.imu_from_kinematics` from base_link kinematics.

Measured with dartpy 6.20.0 on this project's machine (1 kHz, one robot; "flat": 4 s at
0.5 m/s, mu 0.95; "gravel": 10 s at 0.5 m/s from x = -0.8 m over the 4-tile gravel strip of
METHOD.md; "turn": 3 s at v = w = 0.5, yaw rate averaged over 1-3 s; steps/s of the
stepping loop; the machine is shared, so +-20 %):

collision detector (setting ``collision_detector``), with the NSGS Coulomb solver:
  detector  rest z   flat y drift  flat      gravel    turn      turn yaw rate
  fcl       0.13228  -2.4 mm       9 800/s   2 700/s   2 500/s   0.25 rad/s
  ode       0.13228  -2.7 mm       4 800/s   1 800/s     490/s   0.17 rad/s
  dart      0.13228  -2.7 mm      22 000/s   2 100/s   1 800/s   0.21 rad/s
  bullet    0.13228  -3.7 mm       8 700/s   2 800/s   2 200/s   0.27 rad/s
All rest at base_link's 0.13228 m and drive straight. FCL (analytic primitives) is the
default: one contact per wheel (not always at mid-width: see "Right turns" above), and
1.5x (gravel) to 5x (turning) faster than the ODE detector, whose two contacts across
each wheel's width make the friction problem statically indeterminate and the iterative
solver slow to converge. Not chosen: Bullet, because with DART's default Dantzig solver it
left the robot stuck at the 2 cm edge of the gravel bed (x = 0.14 m, wheels spinning at
their command); DART's own detector, because it puts each wheel's single contact on an
edge of the wheel, inner edge on the left wheels and outer edge on the right ones, which
biases turning.

contact solver (setting ``lcp_solver``): DART's default is a Dantzig boxed LCP whose
friction is a *pyramid* (box) aligned with the world x and y axes. With it the Husky,
whose centre of mass is 8.5 cm right of its centre line, hardly turns: the right wheels
grip, the robot goes straight at the right wheels' speed and the yaw rate only creeps up
(0.004 rad/s averaged over 1-3 s for a 0.5 rad/s command with the ODE detector, 0.0007
with FCL; MuJoCo with its elliptic cone: 0.13, PyBullet 0.056, ODE 0.031). DART 6.20's
NSGS solver with the Coulomb law solves the true friction cone (the choice the MuJoCo
adapter makes with ``cone: elliptic``), so it is the default; ``lcp_solver: dantzig`` gives
DART's stock (and Gazebo's) behaviour. NSGS is iterative: its sweeps stop at
``solver_tolerance`` or ``solver_sweeps`` (DART's defaults, 1e-5 and 100). A skid-steer turn
is sensitive to where it stops (yaw rate over 1-3 s 0.17 / 0.14 / 0.08 rad/s for
tolerance 1e-5 / 1e-5 with 1000 sweeps / 1e-7 with the ODE detector): contact forces of a
four-wheeled rigid robot are not unique, and the solver picks one solution.

Right turns. With DART's own NSGS stop (tolerance 1e-5, 100 sweeps) the Husky turned
left at 0.51 and right at 0.30-0.33 of the commanded rate (validation cases, mu 0.8, 6 s; Coulomb
0.478 both ways: the quasi-static solution is the same for w and -w, simpick.coulomb), at every
start heading (0 / 112.5 / -135 degrees: 0.511 / 0.504 / 0.503 left, 0.299 / 0.299 / 0.299 right).
Measured on (v, w) = (0.5, +-0.5), 4 s, solver statistics over 2-4 s (FrictionSolveStats):

  tolerance  sweeps  left gain (at cap, contacts/solve)  right gain (at cap, contacts/solve)
  1e-5       100     0.513 (0 %, 3.37)                   0.315 (43 %, 3.52)
  1e-5       300     0.511 (0 %, 3.38)                   0.359 (4 %, 3.95)
  1e-6       100     0.475                               0.320
  1e-6       150     -                                   0.485 (0 %, 4.00)
  1e-6       200     0.475 (0 %, 4.00)                   0.485 (0 %, 4.00)
  1e-7       1000    0.475                               0.485

Not the collision detector (right / left: FCL 0.315 / 0.513, Bullet 0.303 / 0.530, DART's 0.315 /
0.502; the ODE detector's two contacts per wheel give 0.293 / 0.306, symmetric and low), not the
heading (45 degrees: the same figures), not the sweep order alone: it follows the solver's stop.
A loose stop leaves the contact impulses short of the solution; a wheel then lifts off part of the
time (3.4 contacts per step instead of 4), the robot rocks on a diagonal, and how it rocks depends
on the side of its centre of mass (8.5 cm right of the centre line): with the COM moved to the
centre line the loose solve gives 0.508 / 0.539 (Coulomb with equal loads: 0.539), moved to the
left 0.460 / 0.401, neither the mirror image of the other. Tight enough (1e-6 with >= 150 sweeps
through the spin-up), all four wheels stay down, every solve converges in about 16 sweeps, and
the gains are 0.475 / 0.485 at every heading. FCL's one contact per wheel is not at mid-width: it
moves across the wheel's width (y within +-0.057 m of the wheel centre) as the wheel tilts.
config.yaml sets 1e-6 and 200 (twice the failing cap); the cost on the lab runs (CPU steps/s,
2 runs each): straight (4 s) grass 2 470 -> 1 180 (at the cap in 81 % of solves), bumps 2 740 ->
1 710, gravel 1 800 -> 1 270; circle (3 s) grass 1 360 -> 980, bumps 1 660 -> 870, gravel 1 440 ->
860.

Speed (with DART's own stop 1e-5 / 100 sweeps). What a step costs, from
``bench/dart_profile.py`` (lab straight run, medians of 3,
shared 2-core machine at load 4-5, so absolute figures are about 1.3-2x those of a quiet machine):

  terrain  step     with Dantzig  NSGS share  collision query  NSGS sweeps/step (at the 100 cap)  contacts
  grass    492 us   31 us         ~461 us     15 us            82 (63 % of steps)                  3.7
  bumps    471 us   49 us         ~422 us     40 us            80 (62 %)                           2.7
  gravel   573 us   171 us        ~403 us     151 us           59 (35 %)                           2.5

The friction-cone solve is 70-94 % of the step: NSGS starts every step from zero (a robot at
rest still takes 32 sweeps a step), and a sweep over 3-4 contacts and the 4 wheel servo rows costs
about 5.6 us. 10x real time at 1 kHz needs <= 100 us a step, i.e. <= ~12 sweeps. On gravel the
collision query is the rest: DART collides one group with itself, so the 485 terrain shapes'
overlapping pairs (bed boxes under stones, neighbouring stones, the plane) all reach DART's
filter each step: 176 us with no robot in the world. The recording loop adds ~3 % (job/bare
0.97). Tried and not adopted (same machine, single runs unless stated):
- ``solver_tolerance`` 1e-4 / 1e-3: grass 1.4x / 3.9x faster, but the validation fails (1e-4:
  gain_v0.5_w0.1 0.247, gain_spin_mu0.2 0.400; 1e-3: gain_spin_mu0.2 0.242, gain_v0.5_w0.5_mu0.2
  0.235; Coulomb 0.478): the loose solve settles on a non-turning set of forces.
- ``solver_sweeps`` 20 / 35 / 50: the validation passes (gains within 0.001 of 100 sweeps; parked
  creep 9.9e-4 / 3.4e-4 / 1.4e-4 m/s for 1.6e-5, tolerance 1e-3), grass 1.8x faster at 35. But
  the cap is where DART's answer is set (63 % of grass steps stop there): at 35 the grass straight
  run's IMU statistics move far beyond roundoff (1 %-trimmed acceleration range 3.1 m/s^2, gyro
  range 0.14 rad/s, against 0.11 and 0.0017 for a 1e-9 m start shift). Not the same physics.
- ``FbfFrictionSolver``: 4.7x slower on grass (16 of 3000 solves converged).
- Dantzig (``lcp_solver: dantzig``): 8-17x faster, but its world-aligned friction box barely turns
  the robot (above).
- detectors (3 s runs, NSGS): DART's 1 471 / 1 863 / 854, Bullet's 1 829 / 2 568 / 1 743 steps/s on
  grass / bumps / gravel against FCL's 2 244 / 1 995 / 1 492: no gain, other contact layouts (above).
- ``time_step`` 2 ms / 4 ms (the world's own step in a 1 ms run; 2026-11-27, process CPU, loaded
  machine, bench/ENGINE_SPEED.md): every Husky validation case passes at both, gains within 0.001 but for
  (0.5, 0.5) at mu 0.2 (0.479 -> 0.502 / 0.480), at 0.73x / 0.52x the validation's CPU (Warthog: every
  case too, 0.62x / 0.58x); a DRIVE step of the Warthog at 0.70x / 0.56x (NSGS needs more sweeps per
  larger step), and the turning DRIVE step's steady speed moved from -0.51 to -0.81 / -0.70 m/s (Drake:
  -0.48 / -0.48 / -0.44 at 1 / 2 / 4 ms): DART's answer there depends on where its solver stops. Not
  halving a DRIVE step's cost, and moving DRIVE's answers: left at 1 ms (docs/engines.md).
- only the terrain shapes within reach of the robot in the collision group (collision aspects
  switched per 0.25 m cell, every 20 steps): the query falls to 98 us for 200 of the 485 shapes,
  but re-syncing the group on each change eats it (gravel 1 228 -> 1 273 steps/s, n 3, within
  noise) and the traces part at roundoff.
"""

from __future__ import annotations

import importlib.metadata
import math
from typing import Annotated, Literal, get_args

import numpy as np
from pydantic import Field

from simpick.engines.base import FRICTION, BaseStates, EngineSettings, Scenario, engine_step_multiple
from simpick.engines.kinematics import matrices_to_quaternions
from simpick.engines.runner import Adapter
from simpick.engines.suspension import coupled_urdf
from simpick.errors import InputError

SPAWN_CLEARANCE = 0.002  # m above resting height, as for the other engines
Detector = Literal["fcl", "ode", "bullet", "dart"]
DETECTORS = get_args(Detector)


class DartSettings(EngineSettings):
    """config ``engines.dart``; the measurements behind each choice are in the module docstring."""

    # fcl (analytic primitives): one contact per wheel (it moves across the wheel's width as the
    # wheel tilts), and 1.5x (gravel) to
    # 5x (turning) faster than "ode", whose two contacts across each wheel's width slow the
    # iterative solver. "bullet" left the robot stuck at the gravel bed's 2 cm edge (with Dantzig);
    # "dart" puts each wheel's contact on an edge (inner left, outer right), which biases turning.
    collision_detector: Detector = "fcl"
    # "nsgs": DART 6.20's NsgsFrictionSolver, the true friction cone (with friction_law coulomb);
    # "dantzig": DART's stock (and Gazebo's) boxed LCP, friction boxed to the world x and y axes:
    # the Husky barely turns (0.004 rad/s averaged over 1-3 s for 0.5 commanded, ODE detector).
    # DART's PGS solver is not offered: dartpy 6.20 binds PgsBoxedLcpSolver without a constructor.
    lcp_solver: Literal["nsgs", "dantzig"] = "nsgs"
    # NsgsFrictionSolver.Law ("nsgs" only): "coulomb", the Coulomb cone; "box" and "associated",
    # DART's other two laws (not measured here)
    friction_law: Literal["coulomb", "box", "associated"] = "coulomb"
    # NSGS sweeps per step, at most: DART's default 100. 20 / 35 / 50 pass the left-turn validation,
    # but 63 % of grass steps stop at the cap, and at 35 the grass straight run's IMU statistics move
    # far beyond roundoff (module docstring): not the same physics. config.yaml: 200 (with
    # tolerance 1e-6; at 100 the robot turns right at 0.32 of w).
    solver_sweeps: Annotated[int, Field(ge=1)] = 100
    # NSGS stopping tolerance: DART's default 1e-5. 1e-4 and 1e-3 are faster (grass 1.4x / 3.9x)
    # but fail the turning validation; the skid-steer turn depends on where the solver stops
    # (module docstring). At 1e-5 right turns reach 0.30-0.33 of w, left 0.51 (Coulomb 0.478);
    # config.yaml: 1e-6, which gives 0.485 / 0.475 (module docstring).
    solver_tolerance: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 1e-5
    # s, the world's own step, a whole multiple of physics.timestep (simpick.engines.base.engine_step_multiple:
    # the run still records every physics step, the state held between DART's steps); None: physics.timestep.
    # Measured in docs/engines.md (DART: its step) and config.yaml.
    time_step: Annotated[float, Field(gt=0, allow_inf_nan=False)] | None = None


def _isometry(dart, position, rotation=None):
    t = dart.math.Isometry3()
    t.set_translation(np.asarray(position, dtype=float))
    if rotation is not None:
        t.set_rotation(np.asarray(rotation, dtype=float))
    return t


def _yaw(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


class DartEngine(Adapter):
    # dartpy 6.20 exposes one contact parameter per shape, the friction coefficient
    # (DynamicsAspect get/setFrictionCoeff; no slip compliance, no secondary direction).
    # Checked again for the turning parameter: dartpy 6.20's DynamicsAspect has get/set FrictionCoeff
    # and RestitutionCoeff only; DART's C++ primary/secondary coefficients and first friction direction are not bound,
    # so no lateral/longitudinal ratio (NsgsFrictionSolver.Options.boxForAnisotropic has nothing to act on)
    calibratable = {"friction": FRICTION}
    name = "dart"
    settings_model = DartSettings
    simulates_suspension = True

    def version(self) -> str:
        return importlib.metadata.version("dartpy")

    def _detector(self, dart, name: str):
        c = dart.collision
        if name == "ode":
            return c.OdeCollisionDetector()
        if name == "bullet":
            return c.BulletCollisionDetector()
        if name == "fcl":
            detector = c.FCLCollisionDetector()
            # analytic primitives rather than meshes (dartpy 6.20's default, made explicit)
            detector.setPrimitiveShapeType(c.FCLCollisionDetector.PrimitiveShape.PRIMITIVE)
            return detector
        return c.DARTCollisionDetector()  # "dart"

    def build(self, scenario: Scenario) -> DartWorld:
        """The DART world, its robot skeletons and per robot the driven wheel joints (in simpick's order)."""
        import dartpy as dart

        settings = DartSettings.of(scenario.settings, self.name)
        world = dart.simulation.World()
        world.setGravity(list(scenario.gravity))
        multiple = engine_step_multiple(settings.time_step, scenario.timestep)
        world.setTimeStep(scenario.timestep * multiple)
        solver = world.getConstraintSolver()
        solver.setCollisionDetector(self._detector(dart, settings.collision_detector))
        if settings.lcp_solver == "nsgs":
            C = dart.constraint
            options = C.NsgsFrictionSolver.Options()
            options.law = getattr(C.NsgsFrictionSolver.Law, settings.friction_law.capitalize())
            options.maxSweeps = settings.solver_sweeps
            options.tolerance = settings.solver_tolerance
            solver.setBoxedLcpSolver(C.NsgsFrictionSolver(options))
        # "dantzig": DART's default primary solver (with PGS as its fallback), left as it is

        terrain = scenario.terrain
        robot_mu = max(1.0, float(terrain.friction), float(scenario.ground_friction))

        def static_skeleton(name: str):
            skel = dart.dynamics.Skeleton(name)
            _, body = skel.createWeldJointAndBodyNodePair()
            skel.setMobile(False)
            return skel, body

        def add_shape(body, shape, transform, mu: float):
            node = body.createShapeNode(shape)
            node.setRelativeTransform(transform)
            node.createCollisionAspect()
            node.createDynamicsAspect().setFrictionCoeff(mu)
            return node

        # Ground and terrain on one static body (see the module docstring); this alone took
        # the gravel strip from 4 800 to 6 300 steps/s with the Dantzig solver.
        ground, body = static_skeleton("terrain")
        add_shape(
            body,
            dart.dynamics.PlaneShape(np.array([0.0, 0.0, 1.0]), 0.0),
            _isometry(dart, [0, 0, 0]),
            scenario.ground_friction,
        )
        for x, y, z, yaw, sx, sy, sz in terrain.boxes:
            add_shape(
                body,
                dart.dynamics.BoxShape(np.array([sx, sy, sz])),
                _isometry(dart, [x, y, z], _yaw(yaw)),
                terrain.friction,
            )
        for x, y, z, r in terrain.spheres:
            add_shape(body, dart.dynamics.SphereShape(r), _isometry(dart, [x, y, z]), terrain.friction)
        world.addSkeleton(ground)

        robot = scenario.robot
        loader = dart.utils.DartLoader()
        # the robot's file with its <mimic> elements exactly the spec's couplings: DART's loader makes each
        # follower a MIMIC joint (simpick.engines.suspension)
        uri = coupled_urdf(robot).resolve().as_uri()
        robots = []
        for i, (x, y, yaw) in enumerate(scenario.starts):
            skel = loader.parseSkeleton(uri)
            if skel is None:
                raise InputError(str(robot.urdf), "DART's URDF loader could not read the robot")
            skel.setName(f"robot{i}")
            root = skel.getRootJoint()
            root.setPositions(
                dart.dynamics.FreeJoint.convertToPositions(
                    _isometry(dart, [x, y, robot.base_height + SPAWN_CLEARANCE], _yaw(yaw))
                )
            )
            for body in skel.getBodyNodes():
                for node in body.getShapeNodes():
                    if node.hasDynamicsAspect():
                        node.getDynamicsAspect().setFrictionCoeff(robot_mu)
            wheels = []
            for name in robot.wheel_joints:
                joint = skel.getJoint(name)
                joint.setActuatorType(dart.dynamics.ActuatorType.SERVO)
                joint.setForceLowerLimit(0, -scenario.max_wheel_torque)
                joint.setForceUpperLimit(0, scenario.max_wheel_torque)
                joint.setCommand(0, 0.0)
                wheels.append(joint)
            _suspend(skel, robot)
            world.addSkeleton(skel)
            robots.append((skel, wheels))
        return DartWorld(world, robots, scenario, multiple)


def _suspend(skel, robot) -> None:
    """The passive suspension joints of one loaded skeleton: free (PASSIVE) but for their limits, the
    description's damping and Coulomb friction, and the couplings as bilateral coupler constraints."""
    import dartpy as dart

    followers = {c.joint for c in robot.couplings}
    for sus in robot.suspension:
        joint = skel.getJoint(sus.joint)
        # DART's loader reads the limits but leaves them unenforced (areLimitsEnforced() False, measured
        # dartpy 6.20): the Warthog, rockers uncoupled, tipped 21.6 degrees, through the +-0.15 rad stops.
        # Enforced, each limit is a joint-limit constraint solved with the contacts.
        joint.setLimitEnforcement(True)
        joint.setPositionLowerLimit(0, sus.lower)
        joint.setPositionUpperLimit(0, sus.upper)
        # The loader reads <dynamics> too (measured: 100 N m s/rad and 0.5 N m on the Warthog's rockers); set
        # from the spec all the same. DART applies damping as a joint force -c qdot, integrated implicitly
        # (the skeleton's spring/damper terms), and Coulomb friction as a velocity constraint bounded by
        # +-friction, solved with the contacts (DART's JointCoulombFrictionConstraint).
        joint.setDampingCoefficient(0, sus.damping)
        joint.setCoulombFriction(0, sus.friction)
        if sus.joint in followers:
            # The loader made the follower a MIMIC joint from <mimic> (coupled_urdf writes exactly the spec's
            # couplings), which DART enforces with its MimicMotorConstraint: a velocity constraint on the
            # follower towards multiplier x the leader's velocity plus a position error correction, bounded by
            # the follower's force limits (the URDF's effort, 1e5 N m for the Warthog: never reached).
            # DART's bilateral alternative, setUseCouplerConstraint(True) (equal and opposite impulses on
            # both joints, as a differential bar), breaks the leader-side wheels' servos in dartpy 6.20.0
            # (measured, Warthog, rims (0.5, -0.5) m/s: the left wheels ran at 0.30 m/s against a 500 N m
            # bound and 0.70 m/s with 5 000 N m while the right ones tracked, yaw gain 0.11 / 0.54; with
            # the motor both sides track, gain 0.599; tolerance 1e-7, 1000 sweeps). In DART's published source
            # the coupler's row measures the follower's velocity alone (CouplerConstraint::update,
            # getVelocityChange) while its impulse goes to both joints, so the row's response misses the
            # leader's side. The motor's reaction goes to the chassis rather than to the leader, so the
            # follower alone carries the chassis's pitching moment about the pivots (100 kg x 0.04 m: 39 N m,
            # about 43 N of front/back load shift on the follower's wheels, each carrying about 640 N) where a
            # bar shares it between the rockers.
            if joint.getActuatorType() != dart.dynamics.ActuatorType.MIMIC:
                raise RuntimeError(f"dart: {sus.joint} was not loaded as a mimic joint")
        else:
            joint.setActuatorType(dart.dynamics.ActuatorType.PASSIVE)


class DartWorld:
    """One DART world (simpick.engines.base.World). base_link's world pose and the world-frame
    velocity of its origin come straight from the body node, independent of the FreeJoint's
    coordinate convention (in dartpy 6.20 its generalized velocity is angular in the body frame
    but linear in the world frame)."""

    def __init__(self, world, robots: list, scenario: Scenario, multiple: int = 1):
        self.world, self.robots = world, robots
        # physics steps per DART step (the time_step setting); the world steps on the physics steps k = 0, m,
        # 2m ... with the command set then, and its state is read (held) until its next step
        self.multiple, self.k = multiple, 0
        skel0, wheels0 = robots[scenario.recorded_robot]
        self.skel0, self.base = skel0, skel0.getBodyNode(scenario.robot.base_link)
        self.wheel_dofs = [j.getIndexInSkeleton(0) for j in wheels0]
        self.all_wheels = [j for _, ws in robots for j in ws]

    def set_wheel_targets(self, speeds: np.ndarray) -> None:
        for joint, w in zip(self.all_wheels, speeds.ravel().tolist()):
            joint.setCommand(0, w)

    def step(self, n: int = 1) -> None:
        step, m = self.world.step, self.multiple
        # the world's steps among physics steps k .. k + n - 1: those on a multiple of m
        steps = n if m == 1 else (self.k + n - 1) // m - (self.k - 1) // m
        self.k += n
        for _ in range(steps):
            step(False)  # False: keep the servo commands (DART resets them after a step by default)

    def read(self) -> tuple:
        base = self.base
        return (
            base.getWorldTransform().matrix(),
            base.getLinearVelocity(),
            base.getAngularVelocity(),
            self.skel0.getVelocities(),
        )

    def states(self, samples: list) -> BaseStates:
        pose = np.array([s[0] for s in samples], dtype=float).reshape(len(samples), 4, 4)
        velocity, omega, joint_speed = (
            np.array([s[i] for s in samples], dtype=float).reshape(len(samples), -1) for i in (1, 2, 3)
        )
        return BaseStates(
            position=pose[:, :3, 3].copy(),
            quaternion=matrices_to_quaternions(pose[:, :3, :3]),
            linear_velocity=velocity,
            angular_velocity=omega,
            wheel_speed=joint_speed[:, self.wheel_dofs],
        )
