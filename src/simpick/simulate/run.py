"""One simulation case: engine x terrain x motion -> a Parquet IMU trace.

Kept free of Snakemake so tests and benchmarks call exactly what the workflow calls.
"""

from __future__ import annotations

import platform
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import simpick
from simpick.inputs import terrain as terrain_io
from simpick.engines import get_engine
from simpick.engines.base import PhysicsRecord, Scenario
from simpick.simulate.health import HealthLimits, check
from simpick.engines.kinematics import euler_rpy, rotation_matrices
from simpick.simulate.imu import ImuModel, block_average, interval_average, sensor_output
from simpick.inputs.motions import constant_commands
from simpick.inputs.robot import RobotSpec, load_from_config
from simpick.seeds import config_hash, stable_seed  # noqa: F401 (re-exported: the jobs import them from here)
from simpick.simulate.traces import write_trace


@dataclass(frozen=True)
class Case:
    engine: str
    terrain: str
    motion: str
    v: float  # m/s
    w: float  # rad/s
    duration: float  # s
    start: tuple[float, float, float]  # x, y, yaw


def to_trace(record: PhysicsRecord, commands: np.ndarray, timestep: float, imu: ImuModel,
             rng: np.random.Generator, robot: RobotSpec | None = None) -> dict[str, np.ndarray]:
    """Physics-rate record of robot 0 -> IMU-rate trace columns (see simpick.simulate.traces.UNITS)."""
    ratio = 1.0 / (imu.rate_hz * timestep)
    block = int(round(ratio))
    if abs(ratio - block) < 1e-6 and block >= 1:  # the IMU period is a whole number of steps
        accel, gyro = sensor_output(block_average(record.imu_specific_force, block),
                                    block_average(record.imu_gyro, block), imu, rng)
        at = np.arange(block - 1, (len(record.time) // block) * block, block)  # last step of each block
        time = record.time[at]
    else:  # e.g. a 4 ms step for a 100 Hz IMU (the timestep sweep): average by time, not by step
        period = 1.0 / imu.rate_hz
        force = interval_average(record.imu_specific_force, timestep, period)
        accel, gyro = sensor_output(force, interval_average(record.imu_gyro, timestep, period), imu, rng)
        time = period * np.arange(1, len(force) + 1)
        # the state at the last step that ends at or before each IMU sample
        at = np.floor(time / timestep + 1e-9).astype(int) - 1
    quat = record.quaternion[at]
    rpy = euler_rpy(quat)
    vel = record.linear_velocity[at]
    body_vel = np.einsum("nji,nj->ni", rotation_matrices(quat), vel)
    body_rate = np.einsum("nji,nj->ni", rotation_matrices(quat), record.angular_velocity[at])
    cmd = commands[at, 0]
    # The trace's wheel columns, for any robot: forward-signed joint speeds (a mirrored joint's
    # sign undone) of the front-most (fl, fr) and rear-most (rl, rr) driven wheel of each side; with
    # two driven wheels, front and rear are the same wheel. The Husky: its FL, FR, RL, RR as they are.
    n = record.wheel_speed.shape[1]
    signs = np.ones(n) if robot is None else np.array([w.axis_sign for w in robot.driven], dtype=float)
    first, last = (0, 1), (n - 2, n - 1)
    signed = commands[at, 0] * signs if robot is not None and np.any(signs != 1) else cmd
    wheel = record.wheel_speed[at] * signs if robot is not None and np.any(signs != 1) else record.wheel_speed[at]
    frame = {
        "time": time,
        "ax": accel[:, 0], "ay": accel[:, 1], "az": accel[:, 2],
        "wx": gyro[:, 0], "wy": gyro[:, 1], "wz": gyro[:, 2],
        "x": record.position[at, 0], "y": record.position[at, 1], "z": record.position[at, 2],
        "roll": rpy[:, 0], "pitch": rpy[:, 1], "yaw": np.unwrap(rpy[:, 2]),
        "vx": vel[:, 0], "vy": vel[:, 1], "vz": vel[:, 2],
        "v_forward": body_vel[:, 0], "yaw_rate": body_rate[:, 2],
        "cmd_left": signed[:, first[0]], "cmd_right": signed[:, first[1]],
        "wheel_fl": wheel[:, first[0]], "wheel_fr": wheel[:, first[1]],
        "wheel_rl": wheel[:, last[0]], "wheel_rr": wheel[:, last[1]],
    }
    return frame


def run_commands(engine_name: str, commands: np.ndarray, *, robot: RobotSpec, terrain: dict,
                 start: tuple[float, float, float], timestep: float, ground_friction: float,
                 max_wheel_torque: float, engine_settings: dict, imu: ImuModel, noise_seed: int,
                 limits: HealthLimits) -> tuple[dict[str, np.ndarray], dict]:
    """Drive robot 0 with ``commands`` (steps, driven wheels) joint speeds; returns the trace and its metadata."""
    engine = get_engine(engine_name)
    scenario = Scenario(robot=robot, terrain=terrain, ground_friction=ground_friction, timestep=timestep,
                        max_wheel_torque=max_wheel_torque, starts=(tuple(start),), settings=engine_settings)
    commands = commands.reshape(len(commands), 1, -1)
    record = engine.simulate(scenario, commands)
    health = check(record, limits, commands[:, 0])
    frame = to_trace(record, commands, timestep, imu, np.random.default_rng(noise_seed), robot)
    sim_time = record.steps * timestep
    metadata = {
        "engine": engine_name, "engine_version": engine.version(), "timestep": timestep,
        "imu_rate_hz": imu.rate_hz, "noise_seed": noise_seed, "terrain_seed": terrain.get("seed"),
        "ground_friction": ground_friction, "terrain_friction": terrain.get("friction"),
        "steps": record.steps, "sim_time": sim_time, "wall_time": record.wall_time, "cpu_time": record.cpu_time,
        "real_time_factor": sim_time / record.wall_time if record.wall_time > 0 else None,
        "health": health.as_dict(), "simpick_version": simpick.__version__, "python": platform.python_version(),
    }
    return frame, metadata


def run_case(case: Case, *, urdf: str | Path, terrain_file: str | Path | None = None, terrain: dict | None = None,
             track: float, max_wheel_torque: float, timestep: float, ground_friction: float,
             engine_settings: dict, imu: ImuModel, seed: int,
             limits: HealthLimits = HealthLimits(), robot_options: dict | None = None
             ) -> tuple[dict[str, np.ndarray], dict]:
    """One constant-command case; the terrain comes from a file or, already loaded, as a dict.
    ``robot_options``: the config's ``robot`` block (imu_link, wheels, overrides)."""
    robot = load_from_config({**(robot_options or {}), "urdf": urdf})
    terrain = terrain if terrain is not None else terrain_io.load(terrain_file)
    commands = constant_commands(case.v, case.w, case.duration, timestep, track, robot)[:, 0]
    noise_seed = stable_seed(seed, case.engine, case.terrain, case.motion)
    frame, metadata = run_commands(case.engine, commands, robot=robot, terrain=terrain, start=case.start,
                                   timestep=timestep, ground_friction=ground_friction,
                                   max_wheel_torque=max_wheel_torque, engine_settings=engine_settings, imu=imu,
                                   noise_seed=noise_seed, limits=limits)
    metadata.update({"terrain": case.terrain, "motion": case.motion, "seed": seed,
                     "command": {"v": case.v, "w": case.w, "track": track}})
    return frame, metadata


def simulate_to_file(case: Case, output: str | Path, *, params: dict, **kwargs) -> dict:
    frame, metadata = run_case(case, **kwargs)
    metadata["config_hash"] = config_hash(params)
    write_trace(frame, metadata, output)
    return metadata
