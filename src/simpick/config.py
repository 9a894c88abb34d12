"""The study config, validated before any job runs.

Typed models give every error the key, the bad value and what is allowed; the Snakefile
calls :func:`validate_or_exit`, so a bad config stops the run with those lines and no
traceback.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, create_model, field_validator, model_validator

from simpick.compare.realmetrics import LEVEL, MIN_RUNS
from simpick.engines import ADAPTERS, REFERENCE_MODELS, get_engine
from simpick.errors import validation_problems
from simpick.inputs.terrain import RULES, TILES
from simpick.score.scoring import METRICS
from simpick.studies.validation.measures import DEFAULT_HEADING, MIN_MEASURED_S, SETTLE_S

Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False)]
Finite = Annotated[float, Field(allow_inf_nan=False)]


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


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


class Terrain(BaseModel):
    """A lab terrain strip; the keys beyond these are its rule's own parameters (simpick.inputs.terrain)."""

    model_config = ConfigDict(extra="allow")  # the rule's own parameters
    rule: Literal[tuple(RULES)] = Field(
        description="how the strip is built: flat tiles, plywood layers or a "  # type: ignore[valid-type]
        "gravel bed"
    )
    friction: Annotated[float, Field(ge=0, le=10, allow_inf_nan=False)] = Field(
        description="Coulomb coefficient of the strip's surface (the paper's values)"
    )
    tiles: Annotated[int, Field(ge=1, le=100)] = Field(TILES, description="the strip's length in 1 m x 1 m tiles")


class Motion(Strict):
    """An open-loop command held for the whole run, as the paper's controller drove it."""

    v: Finite = Field(description="m/s, commanded forward speed")
    w: Finite = Field(description="rad/s, commanded yaw rate (positive: left)")
    duration: Positive = Field(description="s simulated")
    start: tuple[Finite, Finite, Finite] = Field(
        description="x (m), y (m), yaw (rad) of the start, relative to the strip (which spans x 0..tiles m)"
    )


class CpuLoad(Strict):
    """The paper's CPU-load scenarios: CPU seconds per simulated second, % of one core."""

    terrain: str = Field(description="the lab terrain driven (one of terrains)")
    motion: str = Field(description="the motion driven (one of motions)")
    duration: Positive = Field(description="s simulated per repeat")
    repeats: Annotated[int, Field(ge=1)] = Field(description="repeats per scenario; the median is reported")
    robots_average: Annotated[int, Field(ge=1)] = Field(description="robots in one world, the paper's Scenario 1")
    robots_intense: Annotated[int, Field(ge=1)] = Field(description="robots in one world, the paper's Scenario 2")
    spacing: Positive = Field(description="m between robots in the convoy")


class Reference(Strict):
    published: str = Field(description="the paper's published figures (its Tables 3, 4, 6-11) as YAML")


class SegmentRules(Strict):
    """How constant-command segments are cut from a real log."""

    tolerance: Positive = Field(description="m/s: both wheel commands within this of constant")
    min_duration: Positive = Field(description="s of constant command after settling, at least")
    max_duration: Positive = Field(description="s compared at most (bounds the study's simulation time)")
    settle: NonNegative = Field(description="s driven before the compared window, to reach the new speed")
    min_turn: Positive = Field(description="rad/s of kinematic yaw rate above which a segment is turning")
    per_kind: Annotated[int, Field(ge=1)] = Field(
        description="the longest straight and turning segments kept per terrain class"
    )


class TerrainClass(Strict):
    """A real terrain class as the engines see it: rigid flat ground with one friction coefficient."""

    friction: Annotated[float, Field(ge=0, le=10, allow_inf_nan=False)] = Field(
        description="Coulomb coefficient the engines give this class's ground"
    )
    source: str = Field(description="where the coefficient comes from (a handbook table, or 'assumption: ...')")


class DriveSession(Strict):
    """What the config says of one DRIVE session (by its folder name) over what its files say."""

    terrain_class: str | None = Field(None, description="replaces the terrain of the session's metadata.yaml")
    gyro_sign: Literal[-1, 1] | None = Field(
        None, description="the gyro's sign, only where the data cannot fix it (refused where they contradict it)"
    )


class DriveReplay(Strict):
    """How the DRIVE steps are replayed in the engines (rules/drive.smk, simpick.simulate.drive)."""

    models: list[str] | None = Field(
        None, description="the engines and reference models that replay the steps; default: every configured one"
    )
    every: Annotated[int, Field(ge=1)] = Field(
        1, description="replay every N-th step of each session, counted from step 1 (1: every step)"
    )
    max_steps_per_session: Annotated[int, Field(ge=1)] | None = Field(
        None, description="at most this many of those steps per session, the earliest (None: no limit)"
    )
    warmup: Annotated[float, Field(gt=0, le=20)] = Field(
        3.0,
        description="s driven at the real robot's wheel speeds before each step (the first 1 s a ramp from rest), "
        "to reach the engine's own steady state for them",
    )
    unit: Literal["step", "session"] = Field(
        "step", description="the verdict's unit of pairing: each step, or each session (its steps averaged)"
    )


class DeclaredDataset(Strict):
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
    imu_hz: Positive | None = Field(
        None, description="Hz the IMU is known to log at; a file more than 20 % off is refused"
    )
    commands_hz: Positive | None = Field(
        None, description="Hz the wheel commands are known to log at; a file more than 20 % off is refused"
    )
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


class ValidationCase(Strict):
    """A case with a known mechanical answer (simpick.studies.validation documents the kinds)."""

    kind: Literal["yaw_gain", "straight", "slide", "incline", "rest", "rest_pose", "articulation"] = Field(
        description="yaw_gain: steady yaw rate / w against the Coulomb gain; straight: speed = wheel speed x "
        "radius; slide: locked-wheel deceleration mu g; incline: parked below atan(mu), sliding "
        "above; rest: accelerometer g, gyro 0, no creep; a robot on a suspension (skipped on others): "
        "rest_pose: the chassis level at its resting height; articulation: coupled rockers twisted on "
        "two diagonal blocks h high, the chassis' pitch, roll and height as the coupling sets them"
    )
    h: Annotated[float, Field(gt=0, le=0.5, allow_inf_nan=False)] | None = Field(
        None, description="m, articulation: the blocks' height (below half the wheel radius)"
    )
    v: Finite | None = Field(None, description="m/s, commanded forward speed (yaw_gain, straight, slide)")
    w: Finite | None = Field(None, description="rad/s, commanded yaw rate (yaw_gain; positive: left)")
    mu: Annotated[float, Field(gt=0, le=10, allow_inf_nan=False)] = Field(
        description="Coulomb coefficient of the flat rigid ground"
    )
    angle_factor: Positive | None = Field(
        None, description="incline: the slope as a multiple of atan(mu) (below 1 it must hold, above it must slide)"
    )
    heading: Annotated[float, Field(ge=-180, le=180, allow_inf_nan=False)] = Field(
        DEFAULT_HEADING,
        description="deg; yaw_gain, straight, slide: the robot's start heading; incline: the "
        "downhill direction from the robot's back (the robot starts at heading 0); "
        "rest: refused (it would change nothing)",
    )
    duration: Positive | None = Field(None, description="s simulated; default: the kind's own")
    cruise: Positive | None = Field(None, description="slide: s driven before the wheels lock; default: the kind's")
    friction_ratio: Annotated[float, Field(gt=0, le=2, allow_inf_nan=False)] | None = Field(
        None,
        description="yaw_gain only: the wheels' lateral/longitudinal friction ratio given to the engine's "
        "friction_ratio setting; the analytic gain is then the anisotropic Coulomb one (an "
        "engine without that setting skips the case)",
    )

    @model_validator(mode="after")
    def needed(self):
        need = {
            "yaw_gain": ("v", "w"),
            "straight": ("v",),
            "slide": ("v",),
            "incline": ("angle_factor",),
            "rest": (),
            "rest_pose": (),
            "articulation": ("h",),
        }[self.kind]
        missing = [k for k in need if getattr(self, k) is None]
        if missing:
            raise ValueError(f"a {self.kind} case needs {missing}")
        if self.kind == "yaw_gain" and self.w == 0:
            raise ValueError("a yaw_gain case needs w != 0 (the gain is yaw rate / w)")
        if self.friction_ratio is not None and self.kind != "yaw_gain":
            raise ValueError("friction_ratio is a yaw_gain case's parameter only")
        if self.kind == "rest" and self.heading != 0:
            raise ValueError("a rest case takes no heading (parked on level ground, it would change nothing)")
        if self.kind in ("incline", "rest") and self.duration is not None and self.duration < SETTLE_S + MIN_MEASURED_S:
            raise ValueError(
                f"a {self.kind} case measures after {SETTLE_S:g} s of settling: its duration must be "
                f"at least {SETTLE_S + MIN_MEASURED_S:g} s, got {self.duration:g}"
            )
        return self


class Validation(Strict):
    """Every engine against analytic mechanics before any real-data comparison."""

    cases: dict[Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")], ValidationCase] = Field(
        description="case name -> its kind and parameters; editing a case reruns every engine's validation job"
    )
    tolerances: dict[str, NonNegative] = Field(
        description="quantity -> tolerance, one per quantity the cases measure; editing one reruns only the "
        "validation summary and the report"
    )

    @model_validator(mode="after")
    def every_quantity(self):
        from simpick.studies.validation.measures import QUANTITIES

        unknown = sorted(set(self.tolerances) - set(QUANTITIES))
        missing = sorted(set(QUANTITIES) - set(self.tolerances))
        if unknown or missing:
            raise ValueError(
                f"unknown tolerance(s) {unknown}, missing tolerance(s) {missing}; "
                f"one per quantity: {sorted(QUANTITIES)}"
            )
        return self


def timestep_label(timestep: float) -> str:
    """0.0005 -> '0.5ms': a sweep timestep's wildcard and file name (rules/sweep.smk)."""
    return f"{timestep * 1000:g}ms"


class Sweep(Strict):
    """The speed-accuracy sweep: the committed segments at several physics steps."""

    name: Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")] = Field(
        description="the sweep's folder under results/sweeps/"
    )
    timesteps: Annotated[list[Annotated[float, Field(gt=0, le=0.02, allow_inf_nan=False)]], Field(min_length=1)] = (
        Field(
            description="s, the physics steps swept; 20 ms at most (a step that long skips whole contact events of "
            "a 0.33 m wheel at 1 m/s)"
        )
    )

    @field_validator("timesteps")
    @classmethod
    def distinct(cls, timesteps):
        labels = [timestep_label(t) for t in timesteps]
        if len(set(labels)) != len(labels):
            raise ValueError(f"timesteps must be distinct (to 6 significant digits in ms), got {timesteps}")
        return timesteps


class CalibrationScales(Strict):
    """Each error of the objective is divided by its scale before they are summed, so the terms count alike."""

    yaw_rate: Positive = Field(description="rad/s, the low-passed yaw-rate error's scale")
    accel_x: Positive = Field(description="m/s^2, the low-passed longitudinal-acceleration error's scale")
    yaw_rate_gain: Positive | None = Field(
        None,
        description="the steady yaw-rate gain error's scale, on units that "
        "turn under a steady command; null: no gain term",
    )


class CalibrationTarget(Strict):
    """What a calibrated engine must reach on held-out runs to turn like the real robot
    (simpick.studies.calibration.turning.target_table)."""

    classes: list[str] | None = Field(None, description="terrain classes judged together; null: every class calibrated")
    gain_tolerance: Annotated[float, Field(gt=0, lt=1, allow_inf_nan=False)] = Field(
        0.10, description="the calibrated mean yaw-rate gain within this fraction of the real robot's, per class"
    )
    reference: str = Field(
        "coulomb",
        description="the model whose as-configured yaw-rate error the calibrated "
        "engine must beat (paired test over runs)",
    )


class Calibration(Strict):
    """Calibrate every real-data model on training runs and judge it on held-out runs: what a user who
    tunes an engine to their robot and ground can expect."""

    enabled: bool = Field(
        False,
        description="true: the default target and the report include the calibration; "
        "`snakemake calibration` runs it either way",
    )
    test_fraction: Annotated[float, Field(gt=0, lt=1, allow_inf_nan=False)] = Field(
        description="share of each terrain class's runs held out (split by run, never within one)"
    )
    seed: Annotated[int, Field(ge=0, lt=2**32)] = Field(description="the split and the sampler derive from it")
    n_trials: Annotated[int, Field(ge=1)] = Field(
        description="evaluations per model x class, each over all its "
        "training units; the first is the as-configured model"
    )
    startup_trials: Annotated[int, Field(ge=1)] = Field(
        description="random trials before the TPE sampler models the history"
    )
    segment_seconds: Positive | None = Field(
        None, description="committed segments: the first seconds of each compared window"
    )
    replay_seconds: Positive | None = Field(None, description="full replay: the first seconds of each run")
    scales: CalibrationScales = Field(description="the objective's scales")
    models: list[str] | None = Field(
        None,
        description="engines and reference models to calibrate; null: every one "
        "of the study's that declares parameters",
    )
    bounds: dict[str, dict[str, Annotated[list[Finite], Field(min_length=2, max_length=2)]]] = Field(
        {}, description="model -> parameter -> [low, high], overriding the bounds its adapter declares"
    )
    target: CalibrationTarget = Field(
        CalibrationTarget(), description="what a calibrated engine must reach on held-out runs"
    )

    @model_validator(mode="after")
    def known_parameters(self):
        for engine, params in self.bounds.items():
            if engine not in ADAPTERS and engine not in REFERENCE_MODELS:
                raise ValueError(f"bounds.{engine}: unknown engine; available: {sorted(ADAPTERS | REFERENCE_MODELS)}")
            declared = get_engine(engine).calibratable
            for name, (low, high) in params.items():
                if name not in declared:
                    raise ValueError(
                        f"bounds.{engine}.{name}: {engine} declares no calibratable parameter "
                        f"{name!r}; it declares {sorted(declared)}"
                    )
                if not low < high:
                    raise ValueError(f"bounds.{engine}.{name}: low {low} must be below high {high}")
                if declared[name].log and low <= 0:
                    raise ValueError(f"bounds.{engine}.{name}: searched on a log scale, low must be > 0")
        return self


class Accuracy(Strict):
    reference: Literal["real", "paper", "own"] = Field(
        description="what the IMU accuracy scores rest on: real (BorealTC: the committed segments, or the full "
        "replay when borealtc_dir is set), paper (its one lab test, gravel/straight) or own (own_logs)"
    )


class Simulators(Strict):
    """The simulators as rows (simpick.simulators): each run through its engine as it ships and as tuned."""

    catalog: str = Field(
        "resources/simulators/simulators.yaml",
        description="the simulator catalog: facts, sources and the two profiles of each simulator",
    )
    run: list[str] | None = Field(
        None,
        description="simulators whose profiles the study runs; null: every one whose engine the study "
        "runs (an engine the study leaves out leaves its simulators out, named in the report)",
    )
    variants: list[Literal["shipped", "tuned"]] = Field(
        ["shipped", "tuned"], description="which profiles of each simulator run"
    )
    drive: bool = Field(
        False,
        description="replay the DRIVE steps (drive_dir) with the profiles too; off by default: each profile "
        "adds its engine's replay time (docs/drive.md)",
    )


class Statistics(Strict):
    """How sure the real-data comparison may claim to be; the defaults are simpick.compare.realmetrics'
    (MIN_RUNS, LEVEL: stated once, there, with their reasons)."""

    min_runs: Annotated[int, Field(ge=2)] = Field(
        MIN_RUNS,
        description="independent real runs below which a group gets no interval and no verdict, only "
        "'too few runs' (a sign-flip test over n runs cannot give p below 2/2^n)",
    )
    level: Annotated[float, Field(gt=0, lt=1)] = Field(
        LEVEL, description="confidence of the BCa intervals; a verdict needs a sign-flip p below 1 - level"
    )

    @model_validator(mode="after")
    def reachable(self):
        from simpick.compare.realmetrics import smallest_p

        if smallest_p(self.min_runs) >= 1 - self.level:
            raise ValueError(
                f"statistics.min_runs {self.min_runs}: a sign-flip test over {self.min_runs} runs "
                f"cannot give p below {smallest_p(self.min_runs):.3g}, so no verdict could ever reach "
                f"level {self.level:g}; use at least {_runs_for(self.level)}"
            )
        return self


VERDICT_METRICS = ("gain_error", "heading_error", "speed_error")
# the kinds of validation case (simpick.studies.validation) a metric's mechanics can rest on; "invariance":
# the checks made across yaw-gain cases (left against right turns, start headings)
CASE_KINDS = Literal["yaw_gain", "straight", "slide", "incline", "rest", "rest_pose", "articulation", "invariance"]
# the real robot's own figure behind a metric, which a margin measured from the data is taken from
REAL_FIGURE = {"gain_error": "yaw_rate_gain_real"}


class Margin(Strict):
    """A practical margin of one verdict metric: differences to the best engine smaller than this
    are of no practical consequence (simpick.score.equivalence.margin)."""

    basis: Literal["absolute", "real_spread", "real_fraction"] = Field(
        description="absolute: `value` in the metric's unit; real_spread: `value` x the real robot's own "
        "run-to-run spread of the figure behind the metric (pooled within-class standard deviation "
        "over runs); real_fraction: `value` x the real robot's mean of that figure"
    )
    value: Positive = Field(description="the margin (absolute) or the factor (real_spread, real_fraction)")


class VerdictMargins(Strict):
    gain_error: Margin = Field(
        Margin(basis="real_spread", value=1.0),
        description="yaw-rate gain error: by default the real robot's own run-to-run spread",
    )
    heading_error: Margin = Field(Margin(basis="absolute", value=0.05), description="heading error, rad")
    speed_error: Margin = Field(Margin(basis="absolute", value=0.05), description="speed error, m/s")

    @model_validator(mode="after")
    def measurable(self):
        for metric in VERDICT_METRICS:
            basis = getattr(self, metric).basis
            if basis != "absolute" and metric not in REAL_FIGURE:
                raise ValueError(
                    f"{metric}: basis {basis!r} needs the real robot's own figure behind the metric, "
                    f"which only {sorted(REAL_FIGURE)} has; use basis: absolute with a value in "
                    "the metric's unit"
                )
        return self


class VerdictMechanics(Strict):
    gain_error: list[CASE_KINDS] = Field(["yaw_gain", "invariance"], description="case kinds gain error rests on")
    heading_error: list[CASE_KINDS] = Field(
        ["yaw_gain", "invariance", "straight"], description="case kinds heading error rests on"
    )
    speed_error: list[CASE_KINDS] = Field(["straight"], description="case kinds speed error rests on")


class Verdict(Strict):
    """simpick's verdict on the real data: each engine against the best (simpick.score.equivalence)."""

    margins: VerdictMargins = Field(VerdictMargins(), description="the practical margin of each metric")
    mechanics: VerdictMechanics = Field(
        VerdictMechanics(),
        description="the validation case kinds each metric depends on: an engine failing "
        "one is shown with a flag and never named best on that metric",
    )


def _runs_for(level: float) -> int:
    from simpick.compare.realmetrics import smallest_p

    n = 2
    while smallest_p(n) >= 1 - level:
        n += 1
    return n


def _settings_block(section: str, registry: dict) -> type[BaseModel]:
    """The ``engines:`` or ``baselines:`` block: one optional entry per registered name, typed by
    that adapter's own settings model (an omitted or empty entry takes the model's defaults)."""
    fields = {
        name: (
            get_engine(name).settings_model | None,
            Field(None, description=f"the {name} adapter's settings; omitted or empty: its defaults"),
        )
        for name in registry
    }
    return create_model(f"{section.capitalize()}Block", __base__=Strict, **fields)


EnginesBlock = _settings_block("engines", ADAPTERS)
BaselinesBlock = _settings_block("baselines", REFERENCE_MODELS)


class Study(Strict):
    seed: Annotated[int, Field(ge=0, lt=2**32)] = Field(
        description="terrain layouts, IMU noise and the real cases' start headings derive from it"
    )
    engines: EnginesBlock = Field(
        description="engine name -> its settings; editing one engine's settings reruns "  # type: ignore[valid-type]
        "only that engine's jobs"
    )
    baselines: BaselinesBlock = Field(
        BaselinesBlock(),
        description="reference models (formulas, not simulators) "  # type: ignore[valid-type]
        "beside the engines in the real-data comparison",
    )
    physics: Physics = Field(description="the physics step and the floor")
    robot: Robot = Field(description="the robot studied")
    imu: Imu = Field(description="the simulated IMU")
    health: Health = Field(description="limits beyond which a run is recorded as failed")
    terrains: dict[str, Terrain] = Field(description="lab terrain name -> its strip")
    motions: dict[str, Motion] = Field(description="lab motion name -> its open-loop command")
    cpu_load: CpuLoad = Field(description="the paper's CPU-load scenarios")
    validation: Validation = Field(description="the cases with known mechanical answers and their tolerances")
    reference: Reference = Field(description="the paper's published figures")
    accuracy: Accuracy = Field(description="what the IMU accuracy scores rest on")
    statistics: Statistics = Field(Statistics(), description="intervals and verdicts over independent real runs")
    verdict: Verdict = Field(
        Verdict(),
        description="the practical margins of the verdict's equivalence tests and "
        "the mechanics each real-data metric depends on",
    )
    borealtc_dir: str | None = Field(
        None,
        description="a dataset folder in the BorealTC layout (one sub-folder per "
        "terrain class of imu_<run>.csv / pro_<run>.csv pairs): every "
        "run is replayed through every model",
    )
    real_dataset: Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")] | None = Field(
        None, description="the replayed dataset's name (results/real/<name>/); default: its folder's name"
    )
    own_logs: list[OwnLog] = Field([], description="your robot's logs, replayed through every engine like BorealTC's")
    # DRIVE sessions are pickles: read only from a folder the user names, never a default path
    drive_dir: str | None = Field(
        None,
        description="a DRIVE calib_data folder, one session folder or a DRIVE "
        "checkout (pickles: name only a folder you trust)",
    )
    drive_dataset: Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")] = Field(
        "drive", description="the entry of real_data.datasets (kind drive) that declares the DRIVE sessions"
    )
    drive_replay: DriveReplay = Field(DriveReplay(), description="how the DRIVE steps are replayed (drive_dir)")
    sweep: Sweep | None = Field(None, description="a speed-accuracy sweep over physics steps (config/sweeps/)")
    calibration: Calibration | None = Field(None, description="calibration on training runs, judged on held-out runs")
    real_data: RealData = Field(description="the real data: the committed segments, terrain classes and datasets")
    simulators: Simulators = Field(
        Simulators(), description="the simulators a roboticist picks, each as shipped and as tuned (simpick.simulators)"
    )
    qualitative: str = Field(
        description="sourced qualitative facts per engine (licence, ROS, languages, ...) the "
        "paper's qualitative scores rest on"
    )
    weights: dict[str, NonNegative] = Field(
        description="metric -> weight of the paper's weighted table (its section 4 defaults)"
    )

    # Each entry's settings are checked by its adapter's model (the block's field types); these
    # name an unknown engine with what is available, where pydantic would only say "extra".
    @field_validator("engines", mode="before")
    @classmethod
    def known_engines(cls, engines):
        if isinstance(engines, dict):
            unknown = [e for e in engines if e not in ADAPTERS]
            if unknown:
                raise ValueError(f"unknown engine(s) {unknown}; available: {sorted(ADAPTERS)}")
            if not engines:
                raise ValueError("at least one engine is needed")
        return engines

    @field_validator("baselines", mode="before")
    @classmethod
    def known_baselines(cls, baselines):
        if isinstance(baselines, dict):
            for name in baselines:
                if name not in REFERENCE_MODELS:
                    raise ValueError(f"unknown reference model {name!r}; available: {sorted(REFERENCE_MODELS)}")
        return baselines

    @field_validator("weights")
    @classmethod
    def all_weights(cls, weights):
        unknown = sorted(set(weights) - set(METRICS))
        missing = [m for m in METRICS if m not in weights]
        if unknown or missing:
            raise ValueError(
                f"unknown weight(s) {unknown}, missing weight(s) {missing}; one weight per metric: {list(METRICS)}"
            )
        return weights

    @model_validator(mode="after")
    def consistent(self):
        block = 1.0 / (self.imu.rate_hz * self.physics.timestep)
        if abs(block - round(block)) > 1e-6 or round(block) < 1:
            raise ValueError(
                f"physics.timestep {self.physics.timestep} s does not divide the IMU period "
                f"1/{self.imu.rate_hz} s into whole steps; use e.g. 0.001, 0.002 or 0.005"
            )
        if self.cpu_load.terrain not in self.terrains:
            raise ValueError(f"cpu_load.terrain {self.cpu_load.terrain!r} is not one of terrains {list(self.terrains)}")
        if self.cpu_load.motion not in self.motions:
            raise ValueError(f"cpu_load.motion {self.cpu_load.motion!r} is not one of motions {list(self.motions)}")
        if self.borealtc_dir is not None and not Path(self.borealtc_dir).is_dir():
            raise ValueError(
                f"borealtc_dir: {self.borealtc_dir!r} is not a folder. Download the data "
                "(github.com/norlab-ulaval/BorealTC, folder data/borealtc) or run "
                "`snakemake --cores 2 fetch_borealtc` while online (it writes data/borealtc), then pass "
                "--config borealtc_dir=PATH"
            )
        if self.real_dataset is not None and self.borealtc_dir is None:
            raise ValueError(
                f"real_dataset {self.real_dataset!r} names the dataset folder given as borealtc_dir, "
                "but borealtc_dir is not set; pass --config borealtc_dir=PATH real_dataset=NAME"
            )
        if not Path(self.real_data.segments).is_file():
            raise ValueError(
                f"real_data.segments: {self.real_data.segments!r} does not exist; restore it from git "
                "(git checkout -- PATH) or regenerate it: "
                "snakemake --cores 2 maintain_segments --config borealtc_dir=PATH"
            )
        names = [log.name for log in self.own_logs]
        if len(set(names)) != len(names):
            raise ValueError(f"own_logs: names must be unique, got {names}")
        unknown = sorted({log.terrain_class for log in self.own_logs} - set(self.real_data.classes))
        if unknown:
            raise ValueError(
                f"own_logs: terrain classes {unknown} are not under real_data.classes "
                f"{sorted(self.real_data.classes)}; add them there with a friction and its source"
            )
        if self.calibration is not None:
            known = [
                name
                for block in (self.engines, self.baselines)
                for name in type(block).model_fields
                if name in block.model_fields_set
            ]
            unknown = [m for m in self.calibration.models or [] if m not in known]
            if unknown:
                raise ValueError(f"calibration.models: {unknown} are not in this study's engines or baselines {known}")
            target = self.calibration.target
            unknown = sorted(set(target.classes or []) - set(self.real_data.classes))
            if unknown:
                raise ValueError(
                    f"calibration.target.classes: {unknown} are not under real_data.classes "
                    f"{sorted(self.real_data.classes)}; name classes from there, or null for all"
                )
            # a reference the config names must be in the study; the default (coulomb) where the study has it,
            # else target.csv says the reference test could not be made
            if target.reference not in known and "reference" in target.model_fields_set:
                raise ValueError(
                    f"calibration.target.reference: {target.reference!r} is not in this study's "
                    f"engines or baselines {known}"
                )
        if self.drive_dir is not None:
            if not Path(self.drive_dir).is_dir():
                raise ValueError(
                    f"drive_dir: {self.drive_dir!r} is not a folder; pass DRIVE's calib_data folder "
                    "(github.com/norlab-ulaval/DRIVE) or one session folder: --config drive_dir=PATH"
                )
            declared = self.real_data.datasets.get(self.drive_dataset)
            if declared is None or declared.kind != "drive":
                raise ValueError(
                    f"drive_dataset {self.drive_dataset!r}: real_data.datasets has no entry of that name "
                    f"with kind: drive; declare it: real_data: {{datasets: {{{self.drive_dataset}: "
                    "{kind: drive, label: ..., source: ...}}}"
                )
        named = self.real_data.datasets.get(self.real_dataset) if self.real_dataset else None
        if named is not None and named.kind == "drive":
            raise ValueError(
                f"real_dataset {self.real_dataset!r} is declared kind: drive in real_data.datasets, but "
                "borealtc_dir reads the BorealTC layout; pass a DRIVE folder as drive_dir instead"
            )
        for name, declared in self.real_data.datasets.items():
            unknown = sorted(
                {o.terrain_class for o in declared.sessions.values() if o.terrain_class is not None}
                - set(self.real_data.classes)
            )
            if unknown:
                raise ValueError(
                    f"real_data.datasets.{name}.sessions: terrain classes {unknown} are not under "
                    f"real_data.classes {sorted(self.real_data.classes)}; add them there with a "
                    "friction and its source"
                )
        if self.accuracy.reference == "own" and not self.own_logs:
            raise ValueError("accuracy.reference is 'own' but own_logs is empty")
        for key, path in (
            ("robot.urdf", self.robot.urdf),
            ("reference.published", self.reference.published),
            ("qualitative", self.qualitative),
        ):
            if not Path(path).is_file():
                raise ValueError(f"{key}: file {path!r} does not exist")
        # the simulator catalog is read here: a misspelt setting or an unsourced fact stops the run now
        from simpick.simulators import SIMULATORS
        from simpick.simulators.catalog import CatalogError, load_catalog

        try:
            catalog = load_catalog(self.simulators.catalog)
        except CatalogError as exc:
            raise ValueError(f"simulators.catalog: {exc}") from None
        unknown = sorted(set(self.simulators.run or []) - set(catalog.simulators))
        if unknown:
            raise ValueError(
                f"simulators.run: {unknown} not in the catalog {self.simulators.catalog}; known: {sorted(SIMULATORS)}"
            )
        # the robot is read here, at planning time: a description no job could read stops the run
        # before any job starts (and before Snakemake deletes any output to rerun it)
        from simpick.errors import InputError
        from simpick.inputs.robot import load_from_config

        try:
            robot = load_from_config(self.robot.model_dump(exclude_none=True))
            if robot.suspension:  # rockers with no resting pose (uncoupled) leave no job anything to run
                from simpick.coulomb import contact_layout

                contact_layout(robot, points_per_wheel=1)
        except InputError as exc:
            raise ValueError(f"robot.urdf: {exc}") from None
        if self.real_data.robot is not None and robot.name != self.real_data.robot:
            # the real data are another robot's: nothing may rest on them
            theirs = (
                f"the real data (real_data.dataset {self.real_data.dataset!r}) were recorded on robot "
                f"{self.real_data.robot!r}, not on this study's {robot.name!r} ({self.robot.urdf})"
            )
            if self.accuracy.reference == "real":
                raise ValueError(
                    f"accuracy.reference is 'real', but {theirs}; set accuracy.reference: paper, "
                    "or own with own_logs recorded on your robot"
                )
            if self.borealtc_dir is not None:
                raise ValueError(f"borealtc_dir is set, but {theirs}; leave borealtc_dir out")
            if self.calibration is not None and self.calibration.enabled:
                raise ValueError(f"calibration.enabled is true, but calibration runs on the real data and {theirs}")
            if self.sweep is not None:
                raise ValueError(f"sweep is set, but the sweep runs the real segments and {theirs}")
        return self


def problems(config: dict) -> list[str]:
    """Human-readable lines, one per problem; empty when the config is valid."""
    try:
        Study.model_validate(config)
    except ValidationError as exc:
        return [f"{key}: {problem}" for key, problem in validation_problems(exc)]
    return []


def duplicate_keys(path: str | Path) -> list[str]:
    """YAML quietly keeps the last of two equal keys; a config must not say a thing twice."""
    import yaml

    found: list[str] = []

    class Loader(yaml.SafeLoader):
        pass

    def mapping(loader, node, deep=False):
        seen = set()
        for key_node, _ in node.value:
            key = loader.construct_object(key_node, deep=deep)
            if key in seen:
                found.append(
                    f"{path}, line {key_node.start_mark.line + 1}: key {key!r} appears twice "
                    "in the same block (YAML would silently keep the last one)"
                )
            seen.add(key)
        return yaml.SafeLoader.construct_mapping(loader, node, deep)

    Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, mapping)
    try:
        yaml.load(Path(path).read_text(), Loader=Loader)
    except (OSError, yaml.YAMLError) as exc:
        found.append(f"{path}: cannot be read as YAML: {exc}")
    return found


def plain(study: Study, config: dict) -> dict:
    """The validated settings as plain data, every default filled in: what the plan reads and the
    jobs receive (rules/common.smk), so a default lives in its model alone. The ``engines`` and
    ``baselines`` blocks keep the configured entries, in the config's order, each with its adapter's
    settings in full (an empty entry: the adapter's defaults)."""
    data = study.model_dump(mode="json")
    for section in ("engines", "baselines"):
        block = getattr(study, section)
        data[section] = {
            name: (getattr(block, name) or get_engine(name).settings_model()).model_dump(mode="json")
            for name in (config.get(section) or {})
            if name in block.model_fields_set
        }
    return data


def validate_or_exit(config: dict, source: str = "config", files: list | tuple = ()) -> Study:
    """The validated, typed study settings (defaults filled in); a bad config stops the run with
    one line per problem. The rules pass slices of this object, not of the raw dict, to the jobs
    (``statistics`` so far: every summary that gives an interval or a verdict reads it)."""
    found = [line for f in files for line in duplicate_keys(f)] + problems(config)
    if found:
        print(f"simpick: the {source} has {len(found)} problem(s):", file=sys.stderr)
        for line in found:
            print(f"  - {line}", file=sys.stderr)
        sys.exit(1)
    return Study.model_validate(config)
