"""One simulation case: engine x terrain x motion -> a Parquet IMU trace.

Kept free of Snakemake so tests and benchmarks call exactly what the workflow calls.
"""

from __future__ import annotations

import dataclasses
import platform
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
from pydantic import BaseModel, Field

import simpick
from simpick.engines import get_engine
from simpick.engines.base import PhysicsRecord, Scenario
from simpick.engines.kinematics import euler_rpy, rotation_matrices
from simpick.inputs.motions import constant_commands
from simpick.inputs.robot import RobotSpec
from simpick.inputs.terrain import Terrain
from simpick.params import JobParams
from simpick.seeds import config_hash, stable_seed  # noqa: F401 (re-exported: the jobs import them from here)
from simpick.simulate.health import HealthLimits, check
from simpick.simulate.imu import ImuModel, block_average, interval_average, sensor_output
from simpick.simulate.settings import SimulationParams


@dataclass(frozen=True)
class Case:
    engine: str
    terrain: str
    motion: str
    v: float  # m/s
    w: float  # rad/s
    duration: float  # s
    start: tuple[float, float, float]  # x, y, yaw


def to_trace(
    record: PhysicsRecord,
    commands: np.ndarray,
    timestep: float,
    imu: ImuModel,
    rng: np.random.Generator,
    robot: RobotSpec | None = None,
) -> dict[str, np.ndarray]:
    """Physics-rate record of robot 0 -> IMU-rate trace columns (see simpick.simulate.traces.UNITS)."""
    ratio = 1.0 / (imu.rate_hz * timestep)
    block = int(round(ratio))
    if abs(ratio - block) < 1e-6 and block >= 1:  # the IMU period is a whole number of steps
        accel, gyro = sensor_output(
            block_average(record.imu_specific_force, block), block_average(record.imu_gyro, block), imu, rng
        )
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
        "ax": accel[:, 0],
        "ay": accel[:, 1],
        "az": accel[:, 2],
        "wx": gyro[:, 0],
        "wy": gyro[:, 1],
        "wz": gyro[:, 2],
        "x": record.position[at, 0],
        "y": record.position[at, 1],
        "z": record.position[at, 2],
        "roll": rpy[:, 0],
        "pitch": rpy[:, 1],
        "yaw": np.unwrap(rpy[:, 2]),
        "vx": vel[:, 0],
        "vy": vel[:, 1],
        "vz": vel[:, 2],
        "v_forward": body_vel[:, 0],
        "yaw_rate": body_rate[:, 2],
        "cmd_left": signed[:, first[0]],
        "cmd_right": signed[:, first[1]],
        "wheel_fl": wheel[:, first[0]],
        "wheel_fr": wheel[:, first[1]],
        "wheel_rl": wheel[:, last[0]],
        "wheel_rr": wheel[:, last[1]],
    }
    return frame


@dataclass(frozen=True)
class Recording:
    """How a run becomes a trace: the simulated IMU, the health limits it is checked against and the
    study seed its noise derives from."""

    imu: ImuModel
    limits: HealthLimits = HealthLimits()
    seed: int = 0

    @classmethod
    def from_params(cls, params: SimulationParams | Mapping[str, Any], imu: ImuModel | None = None) -> Recording:
        """From a job's params (:class:`~simpick.simulate.settings.SimulationParams`: ``imu``, ``health``,
        ``seed``); ``imu``: another sensor model (a replay's at the real log's rate)."""
        p = simulation(params)
        limits = HealthLimits(**p.health.model_dump())
        return cls(imu=ImuModel(**p.imu.model_dump()) if imu is None else imu, limits=limits, seed=p.seed)


class Unit(JobParams):
    """Which unit of cases a simulate job runs (:func:`simpick.simulate.jobs.simulate_job`): how its cases are
    driven, the source they belong to and their names; each kind's params model extends it."""

    kind: str = Field(description="how the cases are driven: simpick.simulate.jobs.PREPARE")
    source: str = Field(description="the source of cases the traces belong to (the plan's sources)")
    cases: list[str] = Field(description="the unit's case names, one trace each")


class UnitParams(SimulationParams, Unit):
    """What :func:`simpick.simulate.jobs.simulate_job` reads of any unit's params, whatever its kind: the
    model's simulation settings and which cases (the kind's prepare function reads the rest, typed)."""


Typed = TypeVar("Typed", bound=BaseModel)


def fields_of(model: type[Typed], params: BaseModel | Mapping[str, Any]) -> Typed:
    """``model``'s fields of a job's params, typed: an instance of ``model`` (a job's own model extending it)
    as it is, else those fields of the params (a mapping a job hands on, or another model's dump), validated;
    the params' other keys are their job's own, which its model checks."""
    if isinstance(params, model):
        return params
    data = params.model_dump(mode="json", by_alias=True) if isinstance(params, BaseModel) else params
    return model.model_validate({k: v for k, v in data.items() if k in model.model_fields})


def simulation(params: SimulationParams | Mapping[str, Any]) -> SimulationParams:
    """What every simulation on one model reads of a job's params (:func:`fields_of`
    :class:`~simpick.simulate.settings.SimulationParams`)."""
    return fields_of(SimulationParams, params)


def scenario_from(
    params: SimulationParams | Mapping[str, Any],
    urdf: str | Path,
    terrain: Terrain | Mapping,
    starts=((0.0, 0.0, 0.0),),
    *,
    ground_friction: float | None = None,
) -> Scenario:
    """A job's params (:func:`simulation`) read once into the typed :class:`~simpick.engines.base.Scenario`
    its engine builds: the robot (its settings, ``max_wheel_torque``; the description ``urdf``), ``terrain``
    (a Terrain or a terrain file's dict), the physics (``timestep``, ``ground_friction`` unless the case sets
    its own) and the model's ``engine_settings``."""
    p = simulation(params)
    return Scenario(
        robot=p.robot.spec(urdf),
        terrain=Terrain.of(terrain),
        ground_friction=p.physics.ground_friction if ground_friction is None else ground_friction,
        timestep=p.physics.timestep,
        max_wheel_torque=p.robot.max_wheel_torque,
        starts=tuple(tuple(start) for start in starts),
        settings=p.engine_settings,
    )


def run_commands(
    engine_name: str, commands: np.ndarray, scenario: Scenario, recording: Recording, noise_seed: int
) -> tuple[dict[str, np.ndarray], dict]:
    """Drive the scenario's robot 0 with ``commands`` (steps, driven wheels) joint speeds; returns the
    trace and its metadata."""
    engine = get_engine(engine_name)
    commands = commands.reshape(len(commands), 1, -1)
    record = engine.simulate(scenario, commands)
    health = check(record, recording.limits, commands[:, 0])
    timestep, imu = scenario.timestep, recording.imu
    frame = to_trace(record, commands, timestep, imu, np.random.default_rng(noise_seed), scenario.robot)
    sim_time = record.steps * timestep
    metadata = {
        "engine": engine_name,
        "engine_version": engine.version(),
        "timestep": timestep,
        "imu_rate_hz": imu.rate_hz,
        "noise_seed": noise_seed,
        "terrain_seed": scenario.terrain.seed,
        "ground_friction": scenario.ground_friction,
        "terrain_friction": scenario.terrain.friction,
        "steps": record.steps,
        "sim_time": sim_time,
        "wall_time": record.wall_time,
        "cpu_time": record.cpu_time,
        "real_time_factor": sim_time / record.wall_time if record.wall_time > 0 else None,
        "health": health.as_dict(),
        "simpick_version": simpick.__version__,
        "python": platform.python_version(),
    }
    return frame, metadata


def run_case(case: Case, scenario: Scenario, track: float, recording: Recording) -> tuple[dict[str, np.ndarray], dict]:
    """One constant-command case on ``scenario`` (its robot started at ``case.start``); ``track``: the
    controller's effective track, m (the config's ``robot.track``)."""
    scenario = dataclasses.replace(scenario, starts=(tuple(case.start),))
    commands = constant_commands(case.v, case.w, case.duration, scenario.timestep, track, scenario.robot)[:, 0]
    noise_seed = stable_seed(recording.seed, case.engine, case.terrain, case.motion)
    frame, metadata = run_commands(case.engine, commands, scenario, recording, noise_seed)
    metadata.update(
        {
            "terrain": case.terrain,
            "motion": case.motion,
            "seed": recording.seed,
            "command": {"v": case.v, "w": case.w, "track": track},
        }
    )
    return frame, metadata
