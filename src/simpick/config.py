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
from simpick.studies.validation import DEFAULT_HEADING, MIN_MEASURED_S, SETTLE_S

Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False)]
Finite = Annotated[float, Field(allow_inf_nan=False)]


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class Physics(Strict):
    timestep: Positive
    ground_friction: NonNegative


class RobotWheel(Strict):
    joint: str
    side: Literal["left", "right"]


class RobotOverrides(Strict):
    """Figures that replace the description's (simpick.inputs.robot.OVERRIDABLE); the engines still
    simulate the description, these feed the controller and the mechanics."""
    wheel_radius: Positive | None = None
    track: Positive | None = None
    wheelbase: NonNegative | None = None
    mass: Positive | None = None
    com: tuple[Finite, Finite, Finite] | None = None
    base_height: Positive | None = None
    imu_mount: tuple[Finite, Finite, Finite] | None = None


class Robot(Strict):
    urdf: str  # a URDF or xacro file (simpick.inputs.robot.load_robot)
    label: str | None = None  # the robot's name in the report (default: the URDF's <robot name>)
    track: Positive
    max_wheel_torque: Positive
    imu_link: str | None = None  # default: the first link with "imu" in its name, else the base
    wheels: list[RobotWheel] | None = None  # the driven joints and sides, instead of finding them
    overrides: RobotOverrides | None = None


class Imu(Strict):
    rate_hz: Positive
    accel_range: Positive
    gyro_range: Positive
    accel_noise_std: NonNegative = 0.0
    gyro_noise_std: NonNegative = 0.0


class Health(Strict):
    min_height: Finite
    max_tilt: Positive
    max_speed: Positive
    max_velocity_jump: Positive
    wheel_tracking: Positive
    max_parked_speed: Positive
    timeout: Positive


class Terrain(BaseModel):
    model_config = ConfigDict(extra="allow")  # the rule's own parameters
    rule: Literal[tuple(RULES)]  # type: ignore[valid-type]
    friction: Annotated[float, Field(ge=0, le=10, allow_inf_nan=False)]
    tiles: Annotated[int, Field(ge=1, le=100)] = TILES  # the strip's length in 1 m tiles


class Motion(Strict):
    v: Finite
    w: Finite
    duration: Positive
    start: tuple[Finite, Finite, Finite]


class CpuLoad(Strict):
    terrain: str
    motion: str
    duration: Positive
    repeats: Annotated[int, Field(ge=1)]
    robots_average: Annotated[int, Field(ge=1)]
    robots_intense: Annotated[int, Field(ge=1)]
    spacing: Positive


class Reference(Strict):
    published: str


class SegmentRules(Strict):
    tolerance: Positive
    min_duration: Positive
    max_duration: Positive
    settle: NonNegative
    min_turn: Positive
    per_kind: Annotated[int, Field(ge=1)]


class TerrainClass(Strict):
    friction: Annotated[float, Field(ge=0, le=10, allow_inf_nan=False)]
    source: str


class DeclaredDataset(Strict):
    """What is known of a dataset folder before reading it (all optional; rates are measured)."""
    label: str | None = None
    source: str | None = None
    imu_hz: Positive | None = None
    commands_hz: Positive | None = None


class RealData(Strict):
    dataset: str
    # the robot the committed segments and the dataset folders were recorded on, as its URDF names
    # it (<robot name>): they are compared with the study only when robot.urdf is that robot
    robot: str | None = None
    segments: str
    segment_rules: SegmentRules
    window: Positive
    classes: dict[str, TerrainClass]
    datasets: dict[str, DeclaredDataset] = {}


class OwnLog(Strict):
    """One of the user's own logs, replayed through every engine like a BorealTC run."""
    name: Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")]
    terrain_class: str
    csv: str | None = None
    commands_csv: str | None = None
    mapping: dict[str, Any] | None = None
    rosbag: str | None = None
    imu_topic: str | None = None
    command_topic: str | None = None
    command_type: str | None = None
    wheel_radius: Positive | None = None
    left_joints: str | None = None
    right_joints: str | None = None
    frame_z: Literal["up", "down"] | None = None
    imu_rate_hz: Positive | None = None
    command_rate_hz: Positive | None = None

    @model_validator(mode="after")
    def one_source(self):
        if bool(self.csv) == bool(self.rosbag):
            raise ValueError(f"own log {self.name!r}: give exactly one of csv (with mapping) or rosbag")
        if self.csv and not self.mapping:
            raise ValueError(f"own log {self.name!r}: a csv needs a column and unit mapping (see README)")
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
    kind: Literal["yaw_gain", "straight", "slide", "incline", "rest"]
    v: Finite | None = None
    w: Finite | None = None
    mu: Annotated[float, Field(gt=0, le=10, allow_inf_nan=False)]
    angle_factor: Positive | None = None
    # deg: yaw_gain, straight, slide: the robot's start heading; incline: the downhill direction
    # from the robot's back (the robot starts at heading 0); rest: refused (it would change nothing)
    heading: Annotated[float, Field(ge=-180, le=180, allow_inf_nan=False)] = DEFAULT_HEADING
    duration: Positive | None = None
    cruise: Positive | None = None
    # yaw_gain only: the wheels' lateral/longitudinal friction ratio (issue 20) given to the engine's
    # friction_ratio setting; the analytic gain is the anisotropic Coulomb one at that ratio
    friction_ratio: Annotated[float, Field(gt=0, le=2, allow_inf_nan=False)] | None = None

    @model_validator(mode="after")
    def needed(self):
        need = {"yaw_gain": ("v", "w"), "straight": ("v",), "slide": ("v",), "incline": ("angle_factor",),
                "rest": ()}[self.kind]
        missing = [k for k in need if getattr(self, k) is None]
        if missing:
            raise ValueError(f"a {self.kind} case needs {missing}")
        if self.kind == "yaw_gain" and self.w == 0:
            raise ValueError("a yaw_gain case needs w != 0 (the gain is yaw rate / w)")
        if self.friction_ratio is not None and self.kind != "yaw_gain":
            raise ValueError("friction_ratio is a yaw_gain case's parameter only")
        if self.kind == "rest" and self.heading != 0:
            raise ValueError("a rest case takes no heading (parked on level ground, it would change nothing)")
        if self.kind in ("incline", "rest") and self.duration is not None \
                and self.duration < SETTLE_S + MIN_MEASURED_S:
            raise ValueError(f"a {self.kind} case measures after {SETTLE_S:g} s of settling: its duration must be "
                             f"at least {SETTLE_S + MIN_MEASURED_S:g} s, got {self.duration:g}")
        return self


class Validation(Strict):
    cases: dict[Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")], ValidationCase]
    tolerances: dict[str, NonNegative]

    @model_validator(mode="after")
    def every_quantity(self):
        from simpick.studies.validation import QUANTITIES

        unknown = sorted(set(self.tolerances) - set(QUANTITIES))
        missing = sorted(set(QUANTITIES) - set(self.tolerances))
        if unknown or missing:
            raise ValueError(f"unknown tolerance(s) {unknown}, missing tolerance(s) {missing}; "
                             f"one per quantity: {sorted(QUANTITIES)}")
        return self


def timestep_label(timestep: float) -> str:
    """0.0005 -> '0.5ms': a sweep timestep's wildcard and file name (rules/sweep.smk)."""
    return f"{timestep * 1000:g}ms"


class Sweep(Strict):
    name: Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")]
    # s; 20 ms at most (a step that long skips whole contact events of a 0.33 m wheel at 1 m/s)
    timesteps: Annotated[list[Annotated[float, Field(gt=0, le=0.02, allow_inf_nan=False)]], Field(min_length=1)]

    @field_validator("timesteps")
    @classmethod
    def distinct(cls, timesteps):
        labels = [timestep_label(t) for t in timesteps]
        if len(set(labels)) != len(labels):
            raise ValueError(f"timesteps must be distinct (to 6 significant digits in ms), got {timesteps}")
        return timesteps


class CalibrationScales(Strict):
    yaw_rate: Positive  # rad/s
    accel_x: Positive  # m/s^2
    yaw_rate_gain: Positive | None = None  # steady yaw-rate gain error (issue 20); None: no gain term


class CalibrationTarget(Strict):
    """Issue 20's target on held-out runs (simpick.studies.calibration.target_table)."""
    classes: list[str] | None = None  # terrain classes judged together; None: every class calibrated
    gain_tolerance: Annotated[float, Field(gt=0, lt=1, allow_inf_nan=False)] = 0.10  # relative to the real gain
    reference: str = "coulomb"  # the model whose as-configured error the calibrated engine must beat


class Calibration(Strict):
    """Issue 11: calibrate every real-data model on training runs, judge it on test runs."""
    enabled: bool = False
    test_fraction: Annotated[float, Field(gt=0, lt=1, allow_inf_nan=False)]
    seed: Annotated[int, Field(ge=0, lt=2**32)]
    n_trials: Annotated[int, Field(ge=1)]
    startup_trials: Annotated[int, Field(ge=1)]
    segment_seconds: Positive | None = None
    replay_seconds: Positive | None = None
    scales: CalibrationScales
    models: list[str] | None = None  # engines and baselines to calibrate; None: every one in the study
    bounds: dict[str, dict[str, Annotated[list[Finite], Field(min_length=2, max_length=2)]]] = {}
    target: CalibrationTarget = CalibrationTarget()

    @model_validator(mode="after")
    def known_parameters(self):
        for engine, params in self.bounds.items():
            if engine not in ADAPTERS and engine not in REFERENCE_MODELS:
                raise ValueError(f"bounds.{engine}: unknown engine; available: {sorted(ADAPTERS | REFERENCE_MODELS)}")
            declared = get_engine(engine).calibratable
            for name, (low, high) in params.items():
                if name not in declared:
                    raise ValueError(f"bounds.{engine}.{name}: {engine} declares no calibratable parameter "
                                     f"{name!r}; it declares {sorted(declared)}")
                if not low < high:
                    raise ValueError(f"bounds.{engine}.{name}: low {low} must be below high {high}")
                if declared[name].log and low <= 0:
                    raise ValueError(f"bounds.{engine}.{name}: searched on a log scale, low must be > 0")
        return self


class Accuracy(Strict):
    reference: Literal["real", "paper", "own"]


class Statistics(Strict):
    # the defaults are simpick.compare.realmetrics' (MIN_RUNS, LEVEL: stated once, there, with their reasons)
    min_runs: Annotated[int, Field(ge=2)] = MIN_RUNS
    level: Annotated[float, Field(gt=0, lt=1)] = LEVEL

    @model_validator(mode="after")
    def reachable(self):
        from simpick.compare.realmetrics import smallest_p

        if smallest_p(self.min_runs) >= 1 - self.level:
            raise ValueError(f"statistics.min_runs {self.min_runs}: a sign-flip test over {self.min_runs} runs "
                             f"cannot give p below {smallest_p(self.min_runs):.3g}, so no verdict could ever reach "
                             f"level {self.level:g}; use at least {_runs_for(self.level)}")
        return self


VERDICT_METRICS = ("gain_error", "heading_error", "speed_error")
# the kinds of validation case (simpick.studies.validation) a metric's mechanics can rest on; "invariance":
# the checks made across yaw-gain cases (left against right turns, start headings)
CASE_KINDS = Literal["yaw_gain", "straight", "slide", "incline", "rest", "invariance"]
# the real robot's own figure behind a metric, which a margin measured from the data is taken from
REAL_FIGURE = {"gain_error": "yaw_rate_gain_real"}


class Margin(Strict):
    """A practical margin of one verdict metric: differences to the best engine smaller than this
    are of no practical consequence (simpick.score.equivalence.margin)."""
    basis: Literal["absolute", "real_spread", "real_fraction"] = Field(
        description="absolute: `value` in the metric's unit; real_spread: `value` x the real robot's own "
                    "run-to-run spread of the figure behind the metric (pooled within-class standard deviation "
                    "over runs); real_fraction: `value` x the real robot's mean of that figure")
    value: Positive = Field(description="the margin (absolute) or the factor (real_spread, real_fraction)")


class VerdictMargins(Strict):
    gain_error: Margin = Margin(basis="real_spread", value=1.0)
    heading_error: Margin = Margin(basis="absolute", value=0.05)
    speed_error: Margin = Margin(basis="absolute", value=0.05)

    @model_validator(mode="after")
    def measurable(self):
        for metric in VERDICT_METRICS:
            basis = getattr(self, metric).basis
            if basis != "absolute" and metric not in REAL_FIGURE:
                raise ValueError(f"{metric}: basis {basis!r} needs the real robot's own figure behind the metric, "
                                 f"which only {sorted(REAL_FIGURE)} has; use basis: absolute with a value in "
                                 "the metric's unit")
        return self


class VerdictMechanics(Strict):
    gain_error: list[CASE_KINDS] = ["yaw_gain", "invariance"]
    heading_error: list[CASE_KINDS] = ["yaw_gain", "invariance", "straight"]
    speed_error: list[CASE_KINDS] = ["straight"]


class Verdict(Strict):
    """simpick's verdict on the real data: each engine against the best (simpick.score.equivalence)."""
    margins: VerdictMargins = Field(VerdictMargins(), description="the practical margin of each metric")
    mechanics: VerdictMechanics = Field(
        VerdictMechanics(), description="the validation case kinds each metric depends on: an engine failing "
                                        "one is shown with a flag and never named best on that metric")


def _runs_for(level: float) -> int:
    from simpick.compare.realmetrics import smallest_p

    n = 2
    while smallest_p(n) >= 1 - level:
        n += 1
    return n


def _settings_block(section: str, registry: dict) -> type[BaseModel]:
    """The ``engines:`` or ``baselines:`` block: one optional entry per registered name, typed by
    that adapter's own settings model (an omitted or empty entry takes the model's defaults)."""
    fields = {name: (get_engine(name).settings_model | None, None) for name in registry}
    return create_model(f"{section.capitalize()}Block", __base__=Strict, **fields)


EnginesBlock = _settings_block("engines", ADAPTERS)
BaselinesBlock = _settings_block("baselines", REFERENCE_MODELS)


class Study(Strict):
    seed: Annotated[int, Field(ge=0, lt=2**32)]
    engines: EnginesBlock  # type: ignore[valid-type]
    baselines: BaselinesBlock = BaselinesBlock()  # type: ignore[valid-type]
    physics: Physics
    robot: Robot
    imu: Imu
    health: Health
    terrains: dict[str, Terrain]
    motions: dict[str, Motion]
    cpu_load: CpuLoad
    validation: Validation
    reference: Reference
    accuracy: Accuracy
    statistics: Statistics = Statistics()
    verdict: Verdict = Verdict()
    borealtc_dir: str | None = None
    real_dataset: Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")] | None = None
    own_logs: list[OwnLog] = []
    sweep: Sweep | None = None
    calibration: Calibration | None = None
    real_data: RealData
    qualitative: str
    weights: dict[str, NonNegative]

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
            raise ValueError(f"unknown weight(s) {unknown}, missing weight(s) {missing}; "
                             f"one weight per metric: {list(METRICS)}")
        return weights

    @model_validator(mode="after")
    def consistent(self):
        block = 1.0 / (self.imu.rate_hz * self.physics.timestep)
        if abs(block - round(block)) > 1e-6 or round(block) < 1:
            raise ValueError(f"physics.timestep {self.physics.timestep} s does not divide the IMU period "
                             f"1/{self.imu.rate_hz} s into whole steps; use e.g. 0.001, 0.002 or 0.005")
        if self.cpu_load.terrain not in self.terrains:
            raise ValueError(f"cpu_load.terrain {self.cpu_load.terrain!r} is not one of terrains {list(self.terrains)}")
        if self.cpu_load.motion not in self.motions:
            raise ValueError(f"cpu_load.motion {self.cpu_load.motion!r} is not one of motions {list(self.motions)}")
        if self.borealtc_dir is not None and not Path(self.borealtc_dir).is_dir():
            raise ValueError(f"borealtc_dir: {self.borealtc_dir!r} is not a folder. Download the data "
                             "(github.com/norlab-ulaval/BorealTC, folder data/borealtc) or run "
                             "`snakemake --cores 2 fetch_borealtc` while online (it writes data/borealtc), then pass "
                             "--config borealtc_dir=PATH")
        if self.real_dataset is not None and self.borealtc_dir is None:
            raise ValueError(f"real_dataset {self.real_dataset!r} names the dataset folder given as borealtc_dir, "
                             "but borealtc_dir is not set; pass --config borealtc_dir=PATH real_dataset=NAME")
        if not Path(self.real_data.segments).is_file():
            raise ValueError(f"real_data.segments: {self.real_data.segments!r} does not exist; restore it from git "
                             "(git checkout -- PATH) or regenerate it: "
                             "snakemake --cores 2 maintain_segments --config borealtc_dir=PATH")
        names = [log.name for log in self.own_logs]
        if len(set(names)) != len(names):
            raise ValueError(f"own_logs: names must be unique, got {names}")
        unknown = sorted({log.terrain_class for log in self.own_logs} - set(self.real_data.classes))
        if unknown:
            raise ValueError(f"own_logs: terrain classes {unknown} are not under real_data.classes "
                             f"{sorted(self.real_data.classes)}; add them there with a friction and its source")
        if self.calibration is not None:
            known = [name for block in (self.engines, self.baselines) for name in type(block).model_fields
                     if name in block.model_fields_set]
            unknown = [m for m in self.calibration.models or [] if m not in known]
            if unknown:
                raise ValueError(f"calibration.models: {unknown} are not in this study's engines or baselines {known}")
            target = self.calibration.target
            unknown = sorted(set(target.classes or []) - set(self.real_data.classes))
            if unknown:
                raise ValueError(f"calibration.target.classes: {unknown} are not under real_data.classes "
                                 f"{sorted(self.real_data.classes)}; name classes from there, or null for all")
            # a reference the config names must be in the study; the default (coulomb) where the study has it,
            # else target.csv says the reference test could not be made
            if target.reference not in known and "reference" in target.model_fields_set:
                raise ValueError(f"calibration.target.reference: {target.reference!r} is not in this study's "
                                 f"engines or baselines {known}")
        if self.accuracy.reference == "own" and not self.own_logs:
            raise ValueError("accuracy.reference is 'own' but own_logs is empty")
        for key, path in (("robot.urdf", self.robot.urdf), ("reference.published", self.reference.published),
                          ("qualitative", self.qualitative)):
            if not Path(path).is_file():
                raise ValueError(f"{key}: file {path!r} does not exist")
        # the robot is read here, at planning time: a description no job could read stops the run
        # before any job starts (and before Snakemake deletes any output to rerun it)
        from simpick.errors import InputError
        from simpick.inputs.robot import load_from_config

        try:
            robot = load_from_config(self.robot.model_dump(exclude_none=True))
        except InputError as exc:
            raise ValueError(f"robot.urdf: {exc}") from None
        if self.real_data.robot is not None and robot.name != self.real_data.robot:
            # the real data are another robot's: nothing may rest on them
            theirs = (f"the real data (real_data.dataset {self.real_data.dataset!r}) were recorded on robot "
                      f"{self.real_data.robot!r}, not on this study's {robot.name!r} ({self.robot.urdf})")
            if self.accuracy.reference == "real":
                raise ValueError(f"accuracy.reference is 'real', but {theirs}; set accuracy.reference: paper, "
                                 "or own with own_logs recorded on your robot")
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
                found.append(f"{path}, line {key_node.start_mark.line + 1}: key {key!r} appears twice "
                             "in the same block (YAML would silently keep the last one)")
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
