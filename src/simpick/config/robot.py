"""The robot and how it is stepped: physics, the robot's description and overrides, its IMU, the
health checks of a run."""

from __future__ import annotations

from pydantic import Field

from simpick.inputs.robot.settings import RobotCoupling, RobotOverrides, RobotParams, RobotWheel
from simpick.simulate.settings import Health, Imu, Physics


# the fields the jobs read are defined once, in the stages (simpick.inputs.robot.settings,
# simpick.simulate.settings), so that a job's model and the config's section cannot drift apart
class Robot(RobotParams):
    """The robot studied: its description file and the settings read with it."""

    urdf: str = Field(
        description="the robot's URDF or xacro file (simpick.inputs.robot.load_robot), read once at planning time"
    )


__all__ = ["Health", "Imu", "Physics", "Robot", "RobotCoupling", "RobotOverrides", "RobotWheel"]
