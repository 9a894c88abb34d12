"""The robot as a job is given it: the config's ``robot`` section less its file (a job reads the file
from its input, whose content Snakemake tracks). Defined here, beside the loader, so that every stage's
job model can compose it; the config's ``robot`` section (:class:`simpick.config.robot.Robot`) adds the
file's path to these fields."""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import Field

from simpick.inputs.robot.load import load_from_config
from simpick.inputs.robot.spec import RobotSpec
from simpick.params import Finite, JobParams, NonNegative, Positive


class RobotWheel(JobParams):
    joint: str = Field(description="a driven wheel's continuous joint, as the URDF names it")
    side: Literal["left", "right"] = Field(description="the side of the robot the wheel is on")


class RobotOverrides(JobParams):
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


class RobotCoupling(JobParams):
    """A linkage between two passive suspension joints the description leaves out (simpick.inputs.robot.Coupling)."""

    joint: str = Field(description="the follower: a limited revolute rocker joint, as the URDF names it")
    leader: str = Field(description="the rocker joint it follows")
    multiplier: Finite = Field(-1.0, description="q(joint) = multiplier x q(leader) + offset; -1: a differential bar")
    offset: Finite = Field(0.0, description="rad")


class RobotParams(JobParams):
    """The robot's settings a job reads; :meth:`spec` loads the robot from its file with them."""

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

    def spec(self, urdf: str | Path) -> RobotSpec:
        """The robot described by ``urdf`` (the job's input) with these settings."""
        fields = self.model_dump(include=set(RobotParams.model_fields))
        return load_from_config({**fields, "urdf": str(urdf)})


__all__ = ["RobotCoupling", "RobotOverrides", "RobotParams", "RobotWheel"]
