"""Bullet through PyBullet (the engine family of CoppeliaSim's Bullet 2.78 and of MORSE).

Bullet has no IMU sensor, so the adapter records the base kinematics at every step and
the runner's :func:`simpick.engines.kinematics.imu_from_kinematics` turns them into an IMU reading.

Passive suspension (RobotSpec.suspension): Bullet's limits, joint damping, a friction-bounded
velocity motor and one gear constraint per coupling (:meth:`PyBulletEngine._suspension`).

Two Bullet habits the adapter undoes:
- the base pose and velocity PyBullet reports are those of the base's *principal inertial
  frame*: with the Husky's off-diagonal chassis inertia that frame is tilted and offset from
  base_link, so it is converted back to base_link after the run;
- contact friction is the *product* of the two bodies' coefficients, so wheels get 1.0 and
  the terrain carries the whole coefficient.

Skid-steer turning (measured through this adapter, mu 0.8). Bullet's rigid contacts leave the
four wheel loads statically indeterminate and its solver picks a warped split (at rest
FL/FR/RL/RR 41/236/138/140 N for the rigid-body 105/172/105/173 N); in a long spin the Husky then
locks at about 70 deg of yaw and stops turning. Compliant contacts (PyBulletSettings contact_stiffness /
contact_damping) restore the loads and cost nothing (steps/s up 4-39 %). What remains is Bullet's
multibody friction: each contact gets two friction rows along *world-fixed* directions
(btPlaneSpace1 of the normal: -y and +x on a level plane, reported by getContactPoints), each
solved with its own diagonal effective mass and then scaled into the cone, so the friction
force converges to (v1/a1, v2/a2) instead of opposing the slip v. A driven wheel is an order of
magnitude easier to move along its rolling direction (the free wheel spin) than sideways, so with the
wheels along the world axes the friction leans sideways (measured 25-57 deg off the slip) and the
yaw-rate gain falls to ~0.11; with the wheels at 45 deg to the axes both rows see the same mass
and the gain is 0.51 (the Coulomb value for Bullet's own one-edge contact layout, 0.537). The gain
thus varies with heading with a period of 90 deg (long-run mean ~0.26 for 0.478). Upstream:
bullet3 PR #4539 (open) and bullet3 issue #2590. No PyBullet setting changes it: enableConeFriction=0
(world-aligned pyramid) over-turns (0.69, |f| up to 1.1 mu N), the Dantzig MLCP solver, friction
anchors, 200 solver iterations and mesh cylinders leave it. Also: a rolling implicit cylinder touches
the plane at one point, always the same (-y) edge of every wheel, which shifts the contact layout 56 mm
to the right of the wheel centres.

Maximal coordinates, as CoppeliaSim and MORSE build a robot (rigid bodies joined by constraints), would
remove the artefact: Bullet's rigid-body solver gives a sliding contact its friction row along the slip
(btSequentialImpulseConstraintSolver, velocity-dependent friction direction). PyBullet builds such a robot
with loadURDF(useMaximalCoordinates=True) (a btRigidBody per link, a btGeneric6DofSpring2Constraint per
joint; bullet3 6c888f4a examples/SharedMemory/PhysicsServerCommandProcessor.cpp:3416-3436) and drives a
joint through the constraint's angular motor (:7796-7804), but the in-process DIRECT client this adapter
uses parses only multibodies into joint info (PhysicsDirect.cpp:706): the robot reports no joints and
every motor call is refused (pybullet.c:2619-2651; tests/test_bullet_simulators.py). The shared-memory
client sees the joints, yet the server reports a rigid-body robot's base only (no wheel speeds,
PhysicsServerCommandProcessor.cpp:8122-8172) and each command is a round trip of 1.7-4 ms here. Measured
that way (bench/bullet_rows.py maximal; 5 ms, 100 iterations, mu 0.8, Coulomb 0.478; five commands and
headings) the maximal Husky turns at 0.46-0.59 of the command, the multibody at 0.01-0.28, and each 6 s run
costs 18-47 s of wall time against about 1 s (its wheels also turn the other way for the same target: the
rigid-body motor's sense is the opposite of the multibody's). So the Bullet
simulators' rows (CoppeliaSim, MORSE) run this multibody at their own step and solver constants
(PyBulletSettings time_step, sub_steps, contact_erp).
"""

from __future__ import annotations

import importlib.metadata
from typing import Annotated

import numpy as np
from pydantic import Field

from simpick.engines.base import (
    FRICTION,
    FRICTION_RATIO,
    BaseStates,
    Calibratable,
    EngineSettings,
    Scenario,
    engine_step_multiple,
)
from simpick.engines.kinematics import rotation_matrices
from simpick.engines.runner import Adapter

SPAWN_CLEARANCE = 0.002  # m above resting height, so no wheel starts inside the ground


class PyBulletSettings(EngineSettings):
    """config ``engines.pybullet``."""

    # setPhysicsEngineParameter numSolverIterations: constraint solver iterations per step;
    # 50 is PyBullet's own default (getPhysicsEngineParameters)
    solver_iterations: Annotated[int, Field(ge=1)] = 50
    # Compliant wheel contacts (changeDynamics contactStiffness / contactDamping, N/m and N s/m).
    # Four rigid wheel contacts are statically indeterminate and Bullet's rigid solver picks a
    # warped load split: at rest FL/FR/RL/RR = 41/236/138/140 N against 105/172/105/173 N for a
    # rigid body on equally stiff contacts (simpick.coulomb), which cut the skid-steer yaw-rate
    # gain (0.415/0.342/0.113 at (v,w) = (0,.5)/(.5,.5)/(.5,.2), mu 0.8). With equal
    # spring-dampers the loads are 106/171/107/171 N and the gain 0.443/0.443/0.173 (8 s from
    # heading 0; it now swings 0.11-0.51 with the heading: Bullet's friction directions, see
    # the module docstring), and a long spin no longer locks up. 0: rigid contacts. 1e6 N/m: ~0.14 mm
    # static deflection, vertical mode ~42 Hz with a quarter of the mass (24 steps at 1 kHz);
    # 5e3 N s/m: damping ratio ~0.7. 1e7 N/m (2e4 N s/m) gives the same gains within 0.001;
    # 1e5 N/m lets the loads oscillate (sd 20 N) in a spin.
    contact_stiffness: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 1.0e6
    # N s/m, with the stiffness above (damping ratio ~0.7 on a quarter of the robot's mass)
    contact_damping: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 5.0e3
    # Torsional ("spinning") friction of the robot's links, m: Bullet combines it with the
    # ground's friction (robot spinning x ground mu), a torque of that x the normal force
    # resisting a contact's spin about its normal. 0: none (the set-up before calibration).
    spinning_friction: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 0.0
    # Lateral / longitudinal friction ratio of the driven wheels: changeDynamics
    # anisotropicFriction on each wheel link, in the link's local frame, with the component along
    # the wheel's joint axis set to this ratio (Bullet's btCollisionObject::m_anisotropicFriction
    # scales each friction direction's local components before the solve; it does not renormalise
    # them). 1: not set (isotropic, the default). Measured (mu 0.8, 6 s, (0, 0.5) / (0.5, 0.5) /
    # (0.5, -0.5), anisotropic Coulomb in brackets): r 1 0.375 / 0.372 / 0.278 (0.478), 0.8 0.518 /
    # 0.517 / 0.456 (0.601), 0.63 0.618 / 0.620 / 0.600 (0.705), 0.5 0.651 / 0.657 / 0.657 (0.781):
    # it raises the gain, but Bullet's world-aligned friction rows keep it low and heading-dependent
    # (r 0.63, 4 s: 0.45 / 0.41 / 0.21 from headings 0 / 112.5 / -135 turning left).
    friction_ratio: Annotated[float, Field(gt=0, le=2, allow_inf_nan=False)] = 1.0
    # s, Bullet's own step (setPhysicsEngineParameter fixedTimeStep), a whole multiple of physics.timestep
    # (simpick.engines.base.engine_step_multiple, as Drake's time_step): the run still records every
    # physics step, the state held between Bullet's steps, and each Bullet step reads the command of the
    # physics step it starts on. None: physics.timestep (the default run, 1 ms). A simulator's own step:
    # CoppeliaSim 5 ms, MORSE 1/60 s (resources/simulators/simulators.yaml).
    time_step: Annotated[float, Field(gt=0, allow_inf_nan=False)] | None = None
    # setPhysicsEngineParameter numSubSteps: Bullet splits each step into this many substeps of equal
    # length (Blender's game engine: physics_step_sub, MORSE 2). 0: one step, PyBullet's own default.
    sub_steps: Annotated[int, Field(ge=0, le=100)] = 0
    # setPhysicsEngineParameter contactERP: the share of a contact's penetration corrected per step, None:
    # PyBullet's 0.08 (bullet3 6c888f4a examples/SharedMemory/PhysicsServerCommandProcessor.cpp:2800). The
    # multibody's contacts read btContactSolverInfo::m_erp2 (btMultiBodyConstraintSolver.cpp:541); Bullet
    # 2.78's rigid contacts read m_erp, 0.2, split impulse being off (bullet3 8bc27b39f, the 2.78 release:
    # btContactSolverInfo.h:73, 77; btSequentialImpulseConstraintSolver.cpp:568-582), Bullet 2.84's m_erp2, 0.2
    # (tag 2.84: btContactSolverInfo.h:80; btSequentialImpulseConstraintSolver.cpp:785). Measured on the Husky
    # (0.5 s at (0.5, 0.5), rigid contacts, CoppeliaSim's row at 5 ms): PyBullet's 0.08 instead of 0.2 moves the
    # base by up to 9.9 mm and its yaw rate by 0.038 rad/s (MORSE's row at 60 Hz: 0.05 mm, 0.0013 rad/s).
    # What the Bullet 2.x simulators also fix and the multibody does not read (measured: bit-identical traces
    # when changed): the joint ERP m_erp (the Husky has no joint limit), split impulse (commented out in
    # btMultiBodyConstraintSolver.cpp:812-824) and the rigid bodies' warm starting factor (a multibody's contacts
    # warm-start only through articulatedWarmStartingFactor, a keyword PyPI's PyBullet 3.2.7 does not accept).
    contact_erp: Annotated[float, Field(ge=0, le=1, allow_inf_nan=False)] | None = None


# getJointStates costs about half a Bullet step; wheel speeds are read every 10th step (the
# IMU's 100 Hz at 1 kHz physics, so trace rows hold exact values) and held in between.
WHEEL_SAMPLE_EVERY = 10
# A coupling's gear constraint (PyBulletEngine._suspension): its torque bound, N m, that of the
# suspension joints' own <limit effort> in the Warthog's description (100 000 N m: never reached;
# the differential carries 40 N m at rest), and its position correction: Bullet's gear has none by
# default (erp 0: the rocker sum drifted 9e-6 rad in 0.3 s of a 10 N m push, and on the Warthog at
# 1 kHz stood at 1.9e-4 rad after 2 s at rest and 3.1e-4 after a 2 s spin at +-0.5 m/s rims); 0.2, as
# Bullet's contact and joint default (btContactSolverInfo m_erp), holds it to 2.6e-6 / 3.8e-7 rad
GEAR_MAX_TORQUE = 1.0e5
GEAR_ERP = 0.2


def _hold(samples: np.ndarray) -> np.ndarray:
    """Forward-fill NaN rows with the last sample (the first sample fills the start)."""
    valid = ~np.isnan(samples[:, 0])
    if not valid.any():
        return np.zeros_like(samples)
    index = np.where(valid, np.arange(len(samples)), 0)
    np.maximum.accumulate(index, out=index)
    index[: np.argmax(valid)] = np.argmax(valid)
    return samples[index]


def _xyzw_to_wxyz(q: np.ndarray) -> np.ndarray:
    return q[..., [3, 0, 1, 2]]


def _quat_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    aw, ax, ay, az = np.moveaxis(a, -1, 0)
    bw, bx, by, bz = np.moveaxis(b, -1, 0)
    return np.stack(
        [
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ],
        -1,
    )


class PyBulletEngine(Adapter):
    calibratable = {
        "friction": FRICTION,
        # Contact softness: 2e5 N/m is ~0.7 mm static sag per wheel; at 1e5 the loads oscillate in a
        # spin (sd 20 N, PyBulletSettings above); 1e7 gives the gains of 1e6 within 0.001, so the range
        # covers every distinct behaviour. Damping stays at its setting.
        "contact_stiffness": Calibratable(
            2.0e5, 1.0e7, log=True, why="1e5 N/m oscillates in a spin; 1e7 = 1e6 within 0.001"
        ),
        # Torsional friction, m (x mu x normal force): 0 to 0.05 m, under half the wheel's
        # 0.114 m width, the largest lever a contact patch across the wheel could give.
        "spinning_friction": Calibratable(0.0, 0.05, why="0 to under half the 0.114 m wheel width"),
        # the turning parameter: base.FRICTION_RATIO, the adapter's friction_ratio
        "friction_ratio": FRICTION_RATIO,
    }
    name = "pybullet"
    settings_model = PyBulletSettings
    simulates_suspension = True  # limits, damping, friction and couplings: PyBulletEngine._suspension

    def version(self) -> str:
        return importlib.metadata.version("pybullet")

    def build(self, scenario: Scenario) -> PyBulletWorld:
        import pybullet as pb

        cid = pb.connect(pb.DIRECT)
        try:
            bodies, wheel_index = self._build_world(pb, cid, scenario)
        except BaseException:
            pb.disconnect(cid)
            raise
        return PyBulletWorld(pb, cid, bodies, wheel_index, scenario)

    def _build_terrain(self, pb, cid: int, scenario: Scenario) -> None:
        ground = pb.createMultiBody(0, pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=cid), physicsClientId=cid)
        pb.changeDynamics(ground, -1, lateralFriction=scenario.ground_friction, physicsClientId=cid)
        terrain = scenario.terrain
        # Boxes and stones are static *rigid* bodies (useMaximalCoordinates), asleep. PyBullet makes
        # every createMultiBody a btMultiBody unless told otherwise, and Bullet puts each static
        # multibody through its articulated-body algorithm, integration, forward kinematics and AABB
        # refresh on every step (perf, gravel: computeAccelerationsArticulatedBodyAlgorithmMultiDof
        # alone 12 % of the run); asleep, a static rigid body also skips the AABB refresh and
        # PyBullet's transform notifications (another quarter of a gravel run). Same shapes, poses
        # (read back bit-identical) and friction; measured on the bare loop, medians, shared
        # 2-core machine, alternated runs:
        # - stones as rigid bodies: gravel 3.2 k -> 8.3 k steps/s (n 5), traces bit-identical on
        #   all six lab runs; asleep as well: 7.6 k -> 12.0 k (n 5);
        # - boxes as sleeping rigid bodies: bumps 9.5 k -> 12.4 k (straight), 12.3 k -> 17.7 k
        #   (circle, n 3); grass unchanged (4 boxes).
        # Stones as rigid bodies alone change nothing (bit-identical lab traces); asleep, and boxes
        # as rigid bodies, the traces are not bit-identical: they first part mid-run at roundoff
        # level (bumps straight: 7e-18 m at step 1614; gravel straight: 1e-9 m at step 2456) and
        # then grow as any roundoff does over bumps and stones. Against the adapter with multibody obstacles,
        # the IMU statistics at 100 Hz (max |diff| over axes; in brackets the same for three 1e-9 m
        # start shifts of the old adapter) differ as little as a nanometre start shift makes them:
        #   run            accel mean        accel range     gyro mean          gyro range
        #   grass straight 2.4e-6 [3.7e-6-9.7e-6] 0.082 [0.074-0.15] 7.2e-7 [5e-7-1.4e-6] 3.4e-3 [9.5e-4-3.2e-3]
        #   grass circle   0 (bit-identical)
        #   bumps straight 2.3e-3 [1.9e-3-4.3e-2] 3.4 [0.68-3.5]    2.4e-5 [5.7e-5-7.1e-4] 9.6e-3 [0.016-0.026]
        #   bumps circle   4.1e-3 [5.8e-4-7.9e-2] 0.68 [1.2-2.4]    1.4e-4 [2.1e-4-4.2e-3] 9.3e-3 [9.2e-3-0.19]
        #   gravel straight 7.4e-4 [4e-3-1e-2]    0.12 [0.53-0.88]  4.7e-5 [1.2e-4-1.7e-3] 1.5e-3 [5.6e-3-0.032]
        #   gravel circle  0.033 [0.019-0.080]    2.4 [1.9-2.9]     5.5e-3 [8.8e-4-4.8e-3] 0.097 [0.059-0.089]
        # (m/s^2 and rad/s; accelerometer ranges are 20-40 m/s^2). The validation cases have no
        # terrain bodies, only the plane, which stays as it was: their values are unchanged.
        static = {"useMaximalCoordinates": True, "physicsClientId": cid}
        asleep = {
            "lateralFriction": terrain.friction,
            "activationState": pb.ACTIVATION_STATE_SLEEP,
            "physicsClientId": cid,
        }
        for x, y, z, yaw, sx, sy, sz in terrain.boxes:
            shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[sx / 2, sy / 2, sz / 2], physicsClientId=cid)
            body = pb.createMultiBody(
                0, shape, basePosition=[x, y, z], baseOrientation=pb.getQuaternionFromEuler([0, 0, yaw]), **static
            )
            pb.changeDynamics(body, -1, **asleep)
        for x, y, z, r in terrain.spheres:
            shape = pb.createCollisionShape(pb.GEOM_SPHERE, radius=r, physicsClientId=cid)
            body = pb.createMultiBody(0, shape, basePosition=[x, y, z], **static)
            pb.changeDynamics(body, -1, **asleep)

    def _build_world(self, pb, cid: int, scenario: Scenario) -> tuple[list[int], list[int]]:
        """Ground, terrain and robots; returns the robot bodies and the wheel joint indices."""
        settings = PyBulletSettings.of(scenario.settings, self.name)
        pb.setGravity(*scenario.gravity, physicsClientId=cid)
        # Not deterministicOverlappingPairs: with it, a Husky commanded to spin in place on a
        # plane translates forward without turning (measured: 1.38 m, 0.02 rad in 10 s; without
        # it 1.23 rad). Runs are deterministic without it: the world is built in a fixed order
        # (tests/test_determinism.py).
        solver = {} if settings.contact_erp is None else {"contactERP": settings.contact_erp}
        pb.setPhysicsEngineParameter(
            fixedTimeStep=scenario.timestep * engine_step_multiple(settings.time_step, scenario.timestep),
            numSubSteps=settings.sub_steps,
            numSolverIterations=settings.solver_iterations,
            **solver,
            physicsClientId=cid,
        )
        self._build_terrain(pb, cid, scenario)

        robot = scenario.robot
        flags = pb.URDF_USE_INERTIA_FROM_FILE | pb.URDF_USE_IMPLICIT_CYLINDER
        bodies, wheel_index = [], None
        for x, y, yaw in scenario.starts:
            body = pb.loadURDF(
                str(robot.urdf),
                [x, y, robot.base_height + SPAWN_CLEARANCE],
                pb.getQuaternionFromEuler([0, 0, yaw]),
                flags=flags,
                physicsClientId=cid,
            )
            names = {
                pb.getJointInfo(body, j, physicsClientId=cid)[1].decode(): j
                for j in range(pb.getNumJoints(body, physicsClientId=cid))
            }
            wheel_index = [names[n] for n in robot.wheel_joints]
            # casters and their swivels roll free: Bullet motorises every revolute joint by default
            # (a velocity motor holding 0), which a maximum force of 0 switches off
            passive = [names[n] for n in robot.passive_joints]
            if passive:
                pb.setJointMotorControlArray(
                    body, passive, pb.VELOCITY_CONTROL, forces=[0.0] * len(passive), physicsClientId=cid
                )
            # contact_stiffness 0: Bullet's rigid contacts (the adapter before compliant contacts)
            compliance = (
                {"contactStiffness": settings.contact_stiffness, "contactDamping": settings.contact_damping}
                if settings.contact_stiffness > 0
                else {}
            )
            for link in range(-1, pb.getNumJoints(body, physicsClientId=cid)):
                pb.changeDynamics(
                    body,
                    link,
                    lateralFriction=1.0,
                    rollingFriction=0.0,
                    spinningFriction=settings.spinning_friction,
                    restitution=0.0,
                    linearDamping=0.0,
                    angularDamping=0.0,
                    **compliance,
                    physicsClientId=cid,
                )
            if settings.friction_ratio != 1.0:
                for joint in wheel_index:
                    axis = np.abs(np.asarray(pb.getJointInfo(body, joint, physicsClientId=cid)[13], dtype=float))
                    pb.changeDynamics(
                        body,
                        joint,
                        physicsClientId=cid,
                        anisotropicFriction=(1.0 - (1.0 - settings.friction_ratio) * axis).tolist(),
                    )
            self._suspension(pb, cid, body, names, robot)
            bodies.append(body)
        return bodies, wheel_index

    @staticmethod
    def _suspension(pb, cid: int, body: int, names: dict, robot) -> None:
        """The robot's passive suspension joints (RobotSpec.suspension) and their couplings.

        - limits: Bullet's URDF loader reads <limit> and its multibody enforces it (measured: the
          uncoupled Warthog rests on its rockers' +0.15 rad stops);
        - damping: changeDynamics jointDamping, the field Bullet's loader fills from <dynamics
          damping> (set here from RobotSpec so nothing rests on the loader); PyBullet applies it as a
          torque -damping x joint speed each step (measured: a 10 N m torque on a Warthog rocker
          in zero gravity tends to 0.1 rad/s with damping 100, grows without bound with 0);
        - friction: the velocity motor Bullet puts on every revolute joint, held at speed 0 with
          the description's <dynamics friction> as its force bound, Bullet's own recipe for joint
          friction (examples/pybullet/examples/jointFrictionAndMotor.py); by default that motor
          would hold the rocker still (measured: the uncoupled Warthog level at rest);
        - couplings: one JOINT_GEAR constraint per coupling (Bullet's URDF loader ignores <mimic>:
          measured, the Warthog's file without RobotSpec couplings tips onto the stops). Sign,
          measured (zero gravity, fixed base, a torque on the parent joint): gearRatio r holds
          q'(parent) + r q'(child) = 0 (r 1: opposite speeds, 2: the child at minus half), so with
          the follower as parent and the leader as child r = -multiplier, and erp pulls
          q(follower) - multiplier q(leader) to relativePositionTarget = offset.
        """
        for sus in robot.suspension:
            joint = names[sus.joint]
            pb.changeDynamics(body, joint, jointDamping=sus.damping, physicsClientId=cid)
            pb.setJointMotorControl2(
                body, joint, pb.VELOCITY_CONTROL, targetVelocity=0.0, force=sus.friction, physicsClientId=cid
            )
        axes = {sus.joint: list(sus.axis) for sus in robot.suspension}
        for c in robot.couplings:
            gear = pb.createConstraint(
                body,
                names[c.joint],
                body,
                names[c.leader],
                pb.JOINT_GEAR,
                axes[c.joint],
                [0.0, 0.0, 0.0],
                [0.0, 0.0, 0.0],
                physicsClientId=cid,
            )
            pb.changeConstraint(
                gear,
                gearRatio=-c.multiplier,
                relativePositionTarget=c.offset,
                maxForce=GEAR_MAX_TORQUE,
                erp=GEAR_ERP,
                physicsClientId=cid,
            )


class PyBulletWorld:
    """One PyBullet client (simpick.engines.base.World). Per step, PyBullet's tuples are kept as they
    come and made arrays once after the run: four numpy row assignments a step cost ~3 us, a tenth
    of a grass step (job/bare 0.87)."""

    def __init__(self, pb, cid: int, bodies: list[int], wheel_index: list[int], scenario: Scenario):
        self.pb, self.cid, self.bodies, self.wheel_index = pb, cid, bodies, wheel_index
        self.body0 = bodies[scenario.recorded_robot]
        self.torque = [scenario.max_wheel_torque] * len(wheel_index)
        self.k = 0  # physics steps taken (scenario.timestep each)
        # physics steps per Bullet step (PyBulletSettings.time_step); above 1 the state is held between
        # Bullet's steps and read once after each of them (self.held)
        self.every = engine_step_multiple(
            PyBulletSettings.of(scenario.settings, PyBulletEngine.name).time_step, scenario.timestep
        )
        self.held: tuple | None = None

    def set_wheel_targets(self, speeds: np.ndarray) -> None:
        pb, cid = self.pb, self.cid
        for i, body in enumerate(self.bodies):
            pb.setJointMotorControlArray(
                body,
                self.wheel_index,
                pb.VELOCITY_CONTROL,
                targetVelocities=speeds[i].tolist(),
                forces=self.torque,
                physicsClientId=cid,
            )

    def step(self, n: int = 1) -> None:
        step, cid = self.pb.stepSimulation, self.cid
        if self.every == 1:
            for _ in range(n):
                step(physicsClientId=cid)
            self.k += n
            return
        # Bullet steps on the physics steps k = 0, every, 2 every ... (each advancing every x timestep)
        bullet_steps = -(-(self.k + n) // self.every) - (-(-self.k // self.every))
        for _ in range(bullet_steps):
            step(physicsClientId=cid)
        if bullet_steps:
            self.held = None
        self.k += n

    def read(self) -> tuple:
        """(pose, velocity, wheel joint states or None): the wheels every WHEEL_SAMPLE_EVERY steps; with
        a coarser Bullet step (self.every > 1), everything once after each Bullet step, then held."""
        pb, cid, body = self.pb, self.cid, self.body0
        if self.every > 1:
            if self.held is None:
                self.held = (
                    pb.getBasePositionAndOrientation(body, physicsClientId=cid),
                    pb.getBaseVelocity(body, physicsClientId=cid),
                    pb.getJointStates(body, self.wheel_index, physicsClientId=cid),
                )
            return self.held
        wheels = (
            pb.getJointStates(body, self.wheel_index, physicsClientId=cid) if self.k % WHEEL_SAMPLE_EVERY == 0 else None
        )
        return (
            pb.getBasePositionAndOrientation(body, physicsClientId=cid),
            pb.getBaseVelocity(body, physicsClientId=cid),
            wheels,
        )

    def states(self, samples: list) -> BaseStates:
        steps = len(samples)
        com, com_q = (np.array([s[0][j] for s in samples], dtype=float).reshape(steps, -1) for j in (0, 1))
        com_v, omega = (np.array([s[1][j] for s in samples], dtype=float).reshape(steps, 3) for j in (0, 1))
        wheels = np.full((steps, len(self.wheel_index)), np.nan)
        for k, s in enumerate(samples):
            if s[2] is not None:
                wheels[k] = [j[1] for j in s[2]]
        wheels = _hold(wheels)

        # From the principal inertial frame back to base_link.
        info = self.pb.getDynamicsInfo(self.body0, -1, physicsClientId=self.cid)
        local_pos = np.asarray(info[3])
        local_q = _xyzw_to_wxyz(np.asarray(info[4]))
        local_q_inv = local_q * np.array([1, -1, -1, -1])
        quat = _quat_multiply(_xyzw_to_wxyz(com_q), local_q_inv)
        quat /= np.linalg.norm(quat, axis=1, keepdims=True)
        offset = rotation_matrices(quat) @ local_pos
        return BaseStates(
            position=com - offset,
            quaternion=quat,
            linear_velocity=com_v - np.cross(omega, offset),
            angular_velocity=omega,
            wheel_speed=wheels,
        )

    def close(self) -> None:
        self.pb.disconnect(self.cid)
