"""Real data: segment rules, terrain classes, DRIVE's sessions and replay, declared datasets, own logs."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import Field, model_validator

from simpick.config.base import Positive, Strict
from simpick.real.settings import DeclaredRates, SegmentRules, StepReplay, TerrainClass


class DriveSession(Strict):
    """What the config says of one DRIVE session (by its folder name) over what its files say."""

    terrain_class: str | None = Field(None, description="replaces the terrain of the session's metadata.yaml")
    gyro_sign: Literal[-1, 1] | None = Field(
        None, description="the gyro's sign, only where the data cannot fix it (refused where they contradict it)"
    )


# how the steps are replayed is defined once, below the config, for the replay and calibration jobs that read it
# (simpick.real.settings)
class DriveReplay(StepReplay):
    """How the DRIVE steps are replayed in the engines (rules/drive.smk, simpick.simulate.steps)."""


# the declared rates are defined once, with what the import job reads (simpick.real.settings.DeclaredRates)
class DeclaredDataset(DeclaredRates):
    """What is known of a dataset folder before reading it (all optional; rates are measured)."""

    # the folder's layout: "borealtc" (terrain-class folders of imu_/pro_ CSV pairs, simpick.real.datasets) or
    # "drive" (DRIVE's calib_data folder of session pickles, simpick.real.logs.drive)
    kind: Literal["borealtc", "drive"] = Field(
        "borealtc",
        description="the folder's layout: 'borealtc' (terrain-class "
        "folders of imu_/pro_ CSV pairs) or 'drive' (DRIVE's calib_data folder "
        "of session pickles)",
    )
    label: str | None = Field(None, description="the dataset's name in the report")
    source: str | None = Field(None, description="where the data come from, with their licence")
    sessions: dict[str, DriveSession] = Field(
        {}, description="DRIVE only: per-session overrides, by session folder name"
    )
    robot: str | None = Field(
        None,
        description="DRIVE only: the name the sessions' metadata.yaml give the study's robot; a session of "
        "another robot is refused at planning time (default: the robot's URDF <robot name>)",
    )

    @model_validator(mode="after")
    def sessions_of_drive(self):
        if self.sessions and self.kind != "drive":
            raise ValueError(f"sessions are overrides of DRIVE sessions; this dataset's kind is {self.kind!r}")
        if self.robot is not None and self.kind != "drive":
            raise ValueError(f"robot names the robot of DRIVE sessions; this dataset's kind is {self.kind!r}")
        return self


class RealData(Strict):
    dataset: str = Field(description="the dataset the committed segment table was derived from")
    robot: str | None = Field(
        None,
        description="the robot (its URDF <robot name>) the committed segments and the "
        "dataset folders were recorded on: they are compared with the "
        "study only when robot.urdf is that robot",
    )
    segments: str = Field(
        description="the committed table of constant-command segments (read by every run, "
        "written only by the maintain_segments rule)"
    )
    segment_rules: SegmentRules = Field(description="how segments are cut from a log")
    window: Positive = Field(description="s: a full replay is compared in windows of this length")
    classes: dict[str, TerrainClass] = Field(
        description="terrain class (a dataset's sub-folder, lower case) -> its ground model"
    )
    datasets: dict[str, DeclaredDataset] = Field(
        {}, description="what is declared about a dataset folder, by dataset name (rates are measured either way)"
    )


class OwnLog(Strict):
    """One of the user's own logs, replayed through every engine like a BorealTC run."""

    name: Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")] = Field(
        description="the log's name in results/real/own/ and the tables"
    )
    terrain_class: str = Field(description="the ground it was recorded on: one of real_data.classes")
    csv: str | None = Field(None, description="a CSV holding the IMU (and the commands, unless commands_csv)")
    commands_csv: str | None = Field(None, description="a second CSV holding the commands")
    mapping: dict[str, Any] | None = Field(
        None, description="canonical quantity -> column, or {column, unit}; units such as ms, deg/s and g are converted"
    )
    rosbag: str | None = Field(None, description="a ROS 1 .bag or ROS 2 bag folder (read without ROS)")
    imu_topic: str | None = Field(None, description="the bag's sensor_msgs/Imu topic")
    command_topic: str | None = Field(None, description="the bag's command topic (Twist, Odometry or JointState)")
    command_type: str | None = Field(None, description="the command topic's message type, where the bag does not say")
    wheel_radius: Positive | None = Field(None, description="m, to turn JointState wheel speeds into commands")
    left_joints: str | None = Field(None, description="JointState: a pattern matching the left wheel joints")
    right_joints: str | None = Field(None, description="JointState: a pattern matching the right wheel joints")
    frame_z: Literal["up", "down"] | None = Field(
        None, description="the IMU's z axis; down is turned to simpick's z up"
    )
    imu_rate_hz: Positive | None = Field(None, description="Hz the IMU is known to log at (checked against the data)")
    command_rate_hz: Positive | None = Field(
        None, description="Hz the commands are known to log at (checked against the data)"
    )

    @model_validator(mode="after")
    def one_source(self):
        if bool(self.csv) == bool(self.rosbag):
            raise ValueError(f"own log {self.name!r}: give exactly one of csv (with mapping) or rosbag")
        if self.csv and not self.mapping:
            raise ValueError(f"own log {self.name!r}: a csv needs a column and unit mapping (docs/real-data.md)")
        if self.rosbag and not (self.imu_topic and self.command_topic):
            raise ValueError(f"own log {self.name!r}: a rosbag needs imu_topic and command_topic")
        for key in ("csv", "commands_csv"):
            path = getattr(self, key)
            if path and not Path(path).is_file():
                raise ValueError(f"own log {self.name!r}: {key} file {path!r} does not exist")
        if self.rosbag and not Path(self.rosbag).exists():
            raise ValueError(f"own log {self.name!r}: rosbag {self.rosbag!r} does not exist")
        return self
