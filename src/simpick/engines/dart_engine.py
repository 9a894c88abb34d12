"""DART (Dynamic Animation and Robotics Toolkit, a Gazebo physics option) through ``dartpy``.

World:
- robot: the same URDF through ``dart.utils.DartLoader`` with a floating (FreeJoint) base;
  DART keeps each link's frame and COM apart, so base_link's pose and velocity are read
  directly (no COM conversion). The 18 g IMU link stays a welded body.
- wheels: actuator type SERVO with force limits +-``scenario.max_wheel_torque``. SERVO is a
  velocity constraint solved with the contacts, bounded by the force limits: the same
  velocity servo PyBullet and ODE use. VELOCITY, the other candidate, is *kinematic* in
  DART (the joint velocity is prescribed, whatever torque that takes), so the force bound
  would be ignored and a wheel could never stall.
- terrain: one static skeleton whose body carries the boxes and spheres; a second static
  skeleton carries the ground (see GROUND below). Friction: DART combines two shapes'
  coefficients by taking the *minimum*, so terrain shapes carry the terrain's coefficient,
  the ground ``scenario.ground_friction``, and the robot's shapes a coefficient no lower
  than any of them (max(1, terrain, ground)), which leaves the contact's mu to the
  terrain and makes robot-robot contacts 1.0 (PyBullet's 1.0 x 1.0) unless a terrain is
  slipperier than... i.e. grippier than 1.0.
- IMU: DART has none; :func:`simpick.imu.imu_from_kinematics` from base_link kinematics.

Collision detector (setting ``collision_detector``): see DETECTOR_NOTES below for the
measured comparison that chose the default.
"""

from __future__ import annotations

import importlib.metadata
import math
import time

import numpy as np

from simpick.engines.base import GRAVITY, PhysicsRecord, Scenario
from simpick.errors import InputError
from simpick.imu import imu_from_kinematics

SPAWN_CLEARANCE = 0.002  # m above resting height, as for the other engines
DEFAULTS = {"collision_detector": "ode", "lcp_solver": "dantzig", "friction_law": "coulomb", "solver_sweeps": 100, "solver_tolerance": 1e-5}
DETECTORS = ("ode", "bullet", "fcl", "dart")


def _isometry(dart, position, rotation=None):
    t = dart.math.Isometry3()
    t.set_translation(np.asarray(position, dtype=float))
    if rotation is not None:
        t.set_rotation(np.asarray(rotation, dtype=float))
    return t


def _yaw(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


class DartEngine:
    name = "dart"

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
            # FCL's default turns primitives into meshes; keep them analytic
            detector.setPrimitiveShapeType(c.FCLCollisionDetector.PrimitiveShape.PRIMITIVE)
            return detector
        if name == "dart":
            return c.DARTCollisionDetector()
        raise InputError("engines.dart.collision_detector", f"{name!r}", f"use one of {list(DETECTORS)}")

    def build(self, scenario: Scenario):
        """World, robot skeletons and per robot the four wheel joints (in simpick's order)."""
        import dartpy as dart

        unknown = set(scenario.settings) - set(DEFAULTS)
        if unknown:
            raise InputError("engines.dart", f"unknown settings {sorted(unknown)}", f"use {sorted(DEFAULTS)}")
        settings = {**DEFAULTS, **scenario.settings}
        world = dart.simulation.World()
        world.setGravity([0.0, 0.0, -GRAVITY])
        world.setTimeStep(scenario.timestep)
        solver = world.getConstraintSolver()
        solver.setCollisionDetector(self._detector(dart, settings["collision_detector"]))
        if settings["lcp_solver"] == "nsgs":
            C = dart.constraint
            options = C.NsgsFrictionSolver.Options()
            options.law = getattr(C.NsgsFrictionSolver.Law, settings["friction_law"].capitalize())
            options.maxSweeps = int(settings["solver_sweeps"])
            options.tolerance = float(settings["solver_tolerance"])
            solver.setBoxedLcpSolver(C.NsgsFrictionSolver(options))
        elif settings["lcp_solver"] == "fbf":
            C = dart.constraint
            options = C.FbfFrictionSolver.Options()
            solver.setBoxedLcpSolver(C.FbfFrictionSolver(options))
        elif settings["lcp_solver"] == "pgs":
            solver.setBoxedLcpSolver(dart.constraint.PgsBoxedLcpSolver())

        terrain = scenario.terrain
        robot_mu = max(1.0, float(terrain["friction"]), float(scenario.ground_friction))

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

        # Ground and terrain on one static body: DART skips pairs within one skeleton (self
        # collision is off by default), so the stones are never tested against their bed.
        ground, body = static_skeleton("terrain")
        add_shape(body, dart.dynamics.PlaneShape(np.array([0.0, 0.0, 1.0]), 0.0),
                  _isometry(dart, [0, 0, 0]), scenario.ground_friction)
        for x, y, z, yaw, sx, sy, sz in terrain["boxes"]:
            add_shape(body, dart.dynamics.BoxShape(np.array([sx, sy, sz])),
                      _isometry(dart, [x, y, z], _yaw(yaw)), terrain["friction"])
        for x, y, z, r in terrain["spheres"]:
            add_shape(body, dart.dynamics.SphereShape(r), _isometry(dart, [x, y, z]), terrain["friction"])
        world.addSkeleton(ground)

        robot = scenario.robot
        loader = dart.utils.DartLoader()
        uri = "file://" + str(robot.urdf.resolve())
        robots = []
        for i, (x, y, yaw) in enumerate(scenario.starts):
            skel = loader.parseSkeleton(uri)
            if skel is None:
                raise InputError(str(robot.urdf), "DART's URDF loader could not read the robot")
            skel.setName(f"robot{i}")
            root = skel.getRootJoint()
            root.setPositions(dart.dynamics.FreeJoint.convertToPositions(
                _isometry(dart, [x, y, robot.base_height + SPAWN_CLEARANCE], _yaw(yaw))))
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
            world.addSkeleton(skel)
            robots.append((skel, wheels))
        return world, robots

    @staticmethod
    def _commands(scenario: Scenario, wheel_commands) -> np.ndarray:
        wheel_commands = np.asarray(wheel_commands, dtype=float)
        if wheel_commands.ndim != 3 or wheel_commands.shape[1:] != (len(scenario.starts), 4):
            raise InputError("wheel_commands", f"shape {wheel_commands.shape} does not fit "
                             f"{len(scenario.starts)} robots x 4 wheels")
        return wheel_commands

    def bare_loop(self, scenario: Scenario, wheel_commands: np.ndarray) -> float:
        wheel_commands = self._commands(scenario, wheel_commands)
        world, robots = self.build(scenario)
        for (_, wheels), speeds in zip(robots, wheel_commands[0]):
            for joint, w in zip(wheels, speeds.tolist()):
                joint.setCommand(0, w)
        step = world.step
        start = time.perf_counter()
        for _ in range(wheel_commands.shape[0]):
            step(False)
        return time.perf_counter() - start

    def simulate(self, scenario: Scenario, wheel_commands: np.ndarray) -> PhysicsRecord:
        wheel_commands = self._commands(scenario, wheel_commands)
        world, robots = self.build(scenario)
        steps = wheel_commands.shape[0]
        dt = scenario.timestep
        skel0, wheels0 = robots[0]
        base = skel0.getBodyNode(scenario.robot.base_link)
        wheel_dofs = [j.getIndexInSkeleton(0) for j in wheels0]
        all_wheels = [j for _, ws in robots for j in ws]
        changes = np.flatnonzero(np.any(np.diff(wheel_commands, axis=0, prepend=np.nan) != 0, axis=(1, 2)))
        change_set = set(changes.tolist())
        pose = np.empty((steps, 4, 4))
        velocity = np.empty((steps, 3))
        omega = np.empty((steps, 3))
        joint_speed = np.empty((steps, skel0.getNumDofs()))
        # base_link's world pose and the world-frame velocity of its origin straight from the
        # body node: version-proof, unlike the FreeJoint's generalized velocities, whose
        # frames (angular in the body frame, linear in the world frame in dartpy 6.20) have
        # changed between DART releases.
        get_pose, get_v, get_w = base.getWorldTransform, base.getLinearVelocity, base.getAngularVelocity
        get_dq, step = skel0.getVelocities, world.step

        cpu0, wall0 = time.process_time(), time.perf_counter()
        for k in range(steps):
            if k in change_set:
                for joint, w in zip(all_wheels, wheel_commands[k].ravel().tolist()):
                    joint.setCommand(0, w)
            step(False)  # False: keep the servo commands (DART resets them after a step by default)
            pose[k] = get_pose().matrix()
            velocity[k] = get_v()
            omega[k] = get_w()
            joint_speed[k] = get_dq()
        wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0

        quat = _matrix_to_quat(pose[:, :3, :3])
        specific_force, gyro = imu_from_kinematics(quat, velocity, omega, scenario.robot.imu_mount, dt)
        return PhysicsRecord(time=dt * np.arange(1, steps + 1), position=pose[:, :3, 3].copy(), quaternion=quat,
                             linear_velocity=velocity, angular_velocity=omega,
                             wheel_speed=joint_speed[:, wheel_dofs],
                             imu_specific_force=specific_force, imu_gyro=gyro,
                             wall_time=wall, cpu_time=cpu, steps=steps)


def _matrix_to_quat(rot: np.ndarray) -> np.ndarray:
    """(n, 3, 3) rotations -> (n, 4) unit quaternions w, x, y, z with w >= 0."""
    m = rot
    trace = np.trace(m, axis1=1, axis2=2)
    candidates = np.stack([
        np.stack([1 + trace, m[:, 2, 1] - m[:, 1, 2], m[:, 0, 2] - m[:, 2, 0], m[:, 1, 0] - m[:, 0, 1]], -1),
        np.stack([m[:, 2, 1] - m[:, 1, 2], 1 + m[:, 0, 0] - m[:, 1, 1] - m[:, 2, 2],
                  m[:, 0, 1] + m[:, 1, 0], m[:, 0, 2] + m[:, 2, 0]], -1),
        np.stack([m[:, 0, 2] - m[:, 2, 0], m[:, 0, 1] + m[:, 1, 0],
                  1 - m[:, 0, 0] + m[:, 1, 1] - m[:, 2, 2], m[:, 1, 2] + m[:, 2, 1]], -1),
        np.stack([m[:, 1, 0] - m[:, 0, 1], m[:, 0, 2] + m[:, 2, 0], m[:, 1, 2] + m[:, 2, 1],
                  1 - m[:, 0, 0] - m[:, 1, 1] + m[:, 2, 2]], -1),
    ], 1)  # (n, 4 candidates, 4): each is 4 q_i q for the i-th largest-component choice
    diag = np.stack([trace, m[:, 0, 0], m[:, 1, 1], m[:, 2, 2]], -1)
    best = np.argmax(diag, axis=1)  # the numerically safest candidate
    quat = candidates[np.arange(len(m)), best]
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    return quat * np.where(quat[:, :1] < 0, -1.0, 1.0)
