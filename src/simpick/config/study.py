"""The Study model: every section together, the engines' and baselines' settings blocks, and the checks
that span sections."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

from pydantic import BaseModel, Field, create_model, field_validator, model_validator

from simpick.config.base import NonNegative, Strict
from simpick.config.lab import CpuLoad, Motion, Reference, Terrain
from simpick.config.real import DriveReplay, OwnLog, RealData
from simpick.config.robot import Health, Imu, Physics, Robot
from simpick.config.studies import Calibration, Sweep, Validation
from simpick.config.verdict import Accuracy, Simulators, Statistics, Verdict
from simpick.engines import ADAPTERS, REFERENCE_MODELS, get_engine
from simpick.score.scoring import METRICS


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
        Simulators(),
        description="the simulators a roboticist picks, each as shipped and as tuned (simpick.engines.simulators)",
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
        from simpick.engines.catalog import CatalogError, load_catalog
        from simpick.engines.simulators import SIMULATORS

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
