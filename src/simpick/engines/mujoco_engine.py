"""MuJoCo (DeepMind) through its official Python bindings.

The world is assembled with ``MjSpec``: the same URDF the other engines load (MuJoCo
gives a URDF no free joint, so one is added), the engine-neutral terrain as primitive
geoms, velocity servos with a torque bound on the wheels, and MuJoCo's own accelerometer
and gyro at the IMU mount (they already follow REP-145). The whole run is stepped in C by
``mujoco.rollout`` with the sensors recorded there, so no Python runs per step.

Friction: MuJoCo combines two geoms' friction by taking the maximum unless one has higher
``priority``; terrain and floor get priority 1 so their coefficient is the contact's.
"""

from __future__ import annotations

import importlib.metadata
import math
import time

import numpy as np

from simpick.engines.base import PhysicsRecord, Scenario, validated_commands

SPAWN_CLEARANCE = 0.002  # m above resting height, as for the other engines
DEFAULTS = {"integrator": "implicitfast", "cone": "elliptic", "solver_iterations": 50, "wheel_servo_gain": 300.0}
# Sensor layout of robot 0, in the order the sensors are added: name -> width.
SENSORS = (("accel", 3), ("gyro", 3), ("pos", 3), ("quat", 4), ("linvel", 3), ("angvel", 3), ("wheels", 4))


def _yaw_quat(yaw: float) -> list[float]:
    return [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]


class MujocoEngine:
    name = "mujoco"

    def version(self) -> str:
        return importlib.metadata.version("mujoco")

    def build(self, scenario: Scenario):
        """Compile the world; returns (model, per-robot actuator count)."""
        import mujoco

        settings = {**DEFAULTS, **scenario.settings}
        spec = mujoco.MjSpec()
        spec.option.timestep = scenario.timestep
        spec.option.gravity = list(scenario.gravity)
        spec.option.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{settings['integrator'].upper()}")
        spec.option.cone = getattr(mujoco.mjtCone, f"mjCONE_{settings['cone'].upper()}")
        spec.option.iterations = int(settings["solver_iterations"])
        world = spec.worldbody

        def surface(geom, friction: float) -> None:
            geom.friction = [friction, 0.0, 0.0]
            geom.priority = 1
            geom.condim = 3

        floor = world.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1])
        surface(floor, scenario.ground_friction)
        terrain = scenario.terrain
        for x, y, z, yaw, sx, sy, sz in terrain["boxes"]:
            surface(world.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[sx / 2, sy / 2, sz / 2],
                                   pos=[x, y, z], quat=_yaw_quat(yaw)), terrain["friction"])
        for x, y, z, r in terrain["spheres"]:
            surface(world.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[r, 0, 0], pos=[x, y, z]),
                    terrain["friction"])

        robot = scenario.robot
        kv = float(settings["wheel_servo_gain"])  # N m s/rad
        for i, (x, y, yaw) in enumerate(scenario.starts):
            child = mujoco.MjSpec.from_file(str(robot.urdf))
            frame = world.add_frame(pos=[x, y, robot.base_height + SPAWN_CLEARANCE], quat=_yaw_quat(yaw))
            prefix = f"r{i}/"
            spec.attach(child, prefix=prefix, frame=frame)
            base = spec.body(prefix + robot.base_link)
            base.add_freejoint()
            for joint in robot.wheel_joints:
                act = spec.add_actuator(name=prefix + joint + "/servo", target=prefix + joint,
                                        trntype=mujoco.mjtTrn.mjTRN_JOINT)
                act.set_to_velocity(kv=kv)
                act.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
                act.forcerange = [-scenario.max_wheel_torque, scenario.max_wheel_torque]
            if i == 0:
                base.add_site(name="imu", pos=list(robot.imu_mount))
                S, O = mujoco.mjtSensor, mujoco.mjtObj
                spec.add_sensor(type=S.mjSENS_ACCELEROMETER, objtype=O.mjOBJ_SITE, objname="imu")
                spec.add_sensor(type=S.mjSENS_GYRO, objtype=O.mjOBJ_SITE, objname="imu")
                for kind in (S.mjSENS_FRAMEPOS, S.mjSENS_FRAMEQUAT, S.mjSENS_FRAMELINVEL, S.mjSENS_FRAMEANGVEL):
                    spec.add_sensor(type=kind, objtype=O.mjOBJ_XBODY, objname=prefix + robot.base_link)
                for joint in robot.wheel_joints:
                    spec.add_sensor(type=S.mjSENS_JOINTVEL, objtype=O.mjOBJ_JOINT, objname=prefix + joint)
        return spec.compile()

    def bare_loop(self, scenario: Scenario, wheel_commands: np.ndarray) -> float:
        import mujoco

        model = self.build(scenario)
        data = mujoco.MjData(model)
        data.ctrl[:] = wheel_commands[0].reshape(-1)
        start = time.perf_counter()
        mujoco.mj_step(model, data, nstep=wheel_commands.shape[0])
        return time.perf_counter() - start

    def simulate(self, scenario: Scenario, wheel_commands: np.ndarray) -> PhysicsRecord:
        wheel_commands = validated_commands(scenario, wheel_commands)
        import mujoco
        from mujoco import rollout

        model = self.build(scenario)
        data = mujoco.MjData(model)
        state_spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        initial = np.empty(mujoco.mj_stateSize(model, state_spec))
        mujoco.mj_getState(model, data, initial, state_spec)
        steps = wheel_commands.shape[0]
        # One extra step so that the sensors of the last real step's end state get evaluated.
        padded = np.concatenate([wheel_commands, wheel_commands[-1:]], axis=0)
        control = np.ascontiguousarray(padded.reshape(1, steps + 1, -1), dtype=np.float64)

        cpu0, wall0 = time.process_time(), time.perf_counter()
        _, sensordata = rollout.rollout(model, data, initial[None], control)
        wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0

        columns, start = {}, 0
        for name, width in SENSORS:
            columns[name] = sensordata[0, :, start:start + width]
            start += width
        # MuJoCo evaluates sensors at the start of each step: row k + 1 holds the state at
        # the end of step k, as every engine's record does, while the accelerometer's row k
        # is the acceleration *during* step k.
        def after_step(a: np.ndarray) -> np.ndarray:
            return a[1:]

        return PhysicsRecord(
            time=scenario.timestep * np.arange(1, steps + 1),
            position=after_step(columns["pos"]), quaternion=after_step(columns["quat"]),
            linear_velocity=after_step(columns["linvel"]), angular_velocity=after_step(columns["angvel"]),
            wheel_speed=after_step(columns["wheels"]),
            imu_specific_force=columns["accel"][:-1].copy(), imu_gyro=after_step(columns["gyro"]),
            wall_time=wall, cpu_time=cpu, steps=steps)
