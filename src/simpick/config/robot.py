"""The robot and how it is stepped: physics, the robot's description and overrides, its IMU, the
health checks of a run."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from simpick.config.base import Finite, NonNegative, Positive, Strict


class Physics(Strict):
    timestep: Positive = Field(
        description="s, the physics step of every engine (1 ms: the IMU's internal 1 kHz "
        "sampling); must divide the IMU period into whole steps"
    )
    ground_friction: NonNegative = Field(description="Coulomb coefficient of the floor around the terrain strips")


class RobotWheel(Strict):
    joint: str = Field(description="a driven wheel's continuous joint, as the URDF names it")
    side: Literal["left", "right"] = Field(description="the side of the robot the wheel is on")


class RobotOverrides(Strict):
    """Figures that replace the description's (simpick.inputs.robot.OVERRIDABLE); the engines still
    simulate the description, these feed the controller and the mechanics."""

    wheel_radius: Positive | None = Field(None, description="m; default: the wheel collision's radius")
    track: Positive | None = Field(
        None, description="m between the left and right wheel centres; default: the description's"
    )
    wheelbase: NonNegative | None = Field(
        None, description="m between the front and rear axles; default: the description's"
    )
    mass: Positive | None = Field(None, description="kg, the whole robot; default: the sum of the links' masses")
    com: tuple[Finite, Finite, Finite] | None = Field(
        None, description="m, the centre of mass in the base frame (x forward, y left, z up)"
    )
    base_height: Positive | None = Field(None, description="m, the base frame's height above flat ground at rest")
    imu_mount: tuple[Finite, Finite, Finite] | None = Field(None, description="m, the IMU's position in the base frame")


class RobotCoupling(Strict):
    """A linkage between two passive suspension joints the description leaves out (simpick.inputs.robot.Coupling)."""

    joint: str = Field(description="the follower: a limited revolute rocker joint, as the URDF names it")
    leader: str = Field(description="the rocker joint it follows")
    multiplier: Finite = Field(-1.0, description="q(joint) = multiplier x q(leader) + offset; -1: a differential bar")
    offset: Finite = Field(0.0, description="rad")


class Robot(Strict):
    urdf: str = Field(
        description="the robot's URDF or xacro file (simpick.inputs.robot.load_robot), read once at planning time"
    )
    label: str | None = Field(None, description="the robot's name in the report; default: the URDF's <robot name>")
    track: Positive = Field(
        description="m, the effective track of the paper's controller (its Eq. 1): wheel speeds from (v, w)"
    )
    max_wheel_torque: Positive = Field(description="N m per wheel, the bound of every engine's wheel servo")
    imu_link: str | None = Field(
        None,
        description="the link the IMU is mounted on; default: the first link with 'imu' in its name, else the base",
    )
    wheels: list[RobotWheel] | None = Field(
        None, description="the driven joints and their sides, instead of finding them from the geometry"
    )
    overrides: RobotOverrides | None = Field(
        None, description="figures that replace the description's for the controller and the mechanics"
    )
    couplings: list[RobotCoupling] | None = Field(
        None,
        description="suspension linkages the description leaves out (a differential bar between two rockers); "
        "a <mimic> in the URDF declares the same",
    )
    packages: dict[str, str] | None = Field(
        None,
        description="package name -> its folder, for a xacro description's $(find PKG) includes (a maker's "
        "ROS package, read without ROS); package:// meshes are dropped for the primitive collisions",
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
