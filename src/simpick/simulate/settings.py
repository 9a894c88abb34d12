"""The settings a simulation job is given, as typed models: the physics, the IMU, the health limits, a lab
motion and the CPU-load scenarios, and what every simulation on one model reads (:class:`SimulationParams`).

Defined here, in the simulate layer, so that the jobs read them typed; the config's sections
(:mod:`simpick.config.robot`, :mod:`simpick.config.lab`) are these models, so each field has one definition.
"""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import Field

from simpick.inputs.robot.settings import RobotParams
from simpick.params import Finite, JobParams, NonNegative, PhysicsStep, Positive


class Physics(PhysicsStep):
    """The physics step of every engine and the floor around the terrain strips."""

    ground_friction: NonNegative = Field(description="Coulomb coefficient of the floor around the terrain strips")


class Imu(JobParams):
    """The simulated IMU (the paper's LORD MicroStrain 3DM-GX3-25)."""

    rate_hz: Positive = Field(description="Hz, the rate of the lab traces (a real log's own rate is used for it)")
    accel_range: Positive = Field(description="m/s^2, the accelerometer's clipping range (+-)")
    gyro_range: Positive = Field(description="rad/s, the gyroscope's clipping range (+-)")
    accel_noise_std: NonNegative = Field(
        0.0, description="m/s^2, standard deviation of the accelerometer's white noise (seeded)"
    )
    gyro_noise_std: NonNegative = Field(
        0.0, description="rad/s, standard deviation of the gyroscope's white noise (seeded)"
    )


class Health(JobParams):
    """Limits beyond which a run is recorded as failed, reported and left out of the scores."""

    min_height: Finite = Field(description="m: the base below this height has fallen through the ground")
    max_tilt: Positive = Field(description="rad of roll or pitch: beyond it the robot has flipped")
    max_speed: Positive = Field(description="m/s: a base faster than this has exploded")
    max_velocity_jump: Positive = Field(description="m/s change of the base velocity in one physics step: a jump")
    wheel_tracking: Positive = Field(
        description="rad/s, mean wheel-speed error over a second beyond wheel_lag's servo lag: the wheels do "
        "not follow their command"
    )
    wheel_lag: NonNegative = Field(
        description="s, time constant of the slowest servo response still counted as following: a wheel "
        "between its command and the command through a first-order lag of this time constant is not in error "
        "(a servo's lag at a command change is not a stuck wheel). Basis, measured at a 0 -> 1 m/s step on "
        "flat ground: MuJoCo and Newton (the same servo) lag 0.024 s (0.032 s at a 0.5 -> -0.5 rad/s turn), the "
        "other engines under 0.01 s; "
        "0 judges the plain error"
    )
    max_parked_speed: Positive = Field(description="m/s while every wheel is commanded to stop: the robot slides")
    timeout: Positive = Field(description="s of wall time after which a simulation is stopped and recorded as hung")


class Motion(JobParams):
    """An open-loop command held for the whole run, as the paper's controller drove it."""

    v: Finite = Field(description="m/s, commanded forward speed")
    w: Finite = Field(description="rad/s, commanded yaw rate (positive: left)")
    duration: Positive = Field(description="s simulated")
    start: tuple[Finite, Finite, Finite] = Field(
        description="x (m), y (m), yaw (rad) of the start, relative to the strip (which spans x 0..tiles m)"
    )


class CpuLoad(JobParams):
    """The paper's CPU-load scenarios: CPU seconds per simulated second, % of one core."""

    terrain: str = Field(description="the lab terrain driven (one of terrains)")
    motion: str = Field(description="the motion driven (one of motions)")
    duration: Positive = Field(description="s simulated per repeat")
    repeats: Annotated[int, Field(ge=1)] = Field(description="repeats per scenario; the median is reported")
    robots_average: Annotated[int, Field(ge=1)] = Field(description="robots in one world, the paper's Scenario 1")
    robots_intense: Annotated[int, Field(ge=1)] = Field(description="robots in one world, the paper's Scenario 2")
    spacing: Positive = Field(description="m between robots in the convoy")


class SimulationParams(JobParams):
    """What every simulation on one model reads, whatever it drives over (the plan's
    :func:`simpick.sources.base.simulation_params`)."""

    engine: str
    engine_settings: dict[str, Any] = Field(
        description="the model's settings as the config gives them; its adapter's own settings model checks them "
        "(the config's engines block at planning time, the adapter in the job)"
    )
    physics: Physics
    robot: RobotParams
    imu: Imu
    health: Health
    seed: Annotated[int, Field(ge=0, lt=2**32)]


__all__ = ["CpuLoad", "Health", "Imu", "Motion", "Physics", "SimulationParams"]
