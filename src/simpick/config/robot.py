"""The robot and how it is stepped: physics, the robot's description and overrides, its IMU, the
health checks of a run."""

from __future__ import annotations

from pydantic import Field

from simpick.config.base import Finite, NonNegative, Positive, Strict
from simpick.inputs.robot.settings import RobotCoupling, RobotOverrides, RobotParams, RobotWheel
from simpick.params import PhysicsStep


# the fields the jobs read are defined once, in the lower layers (simpick.params, simpick.inputs.robot.settings),
# so that a job's model and the config's section cannot drift apart
class Physics(PhysicsStep):
    """The physics step of every engine and the floor around the terrain strips."""

    ground_friction: NonNegative = Field(description="Coulomb coefficient of the floor around the terrain strips")


class Robot(RobotParams):
    """The robot studied: its description file and the settings read with it."""

    urdf: str = Field(
        description="the robot's URDF or xacro file (simpick.inputs.robot.load_robot), read once at planning time"
    )


class Imu(Strict):
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


class Health(Strict):
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


__all__ = ["Health", "Imu", "Physics", "Robot", "RobotCoupling", "RobotOverrides", "RobotWheel"]
