"""Each converted job's parameters, built from the typed study and validated against the job's own model.

A job's model lies next to its job function, in its stage's module (e.g.
:class:`simpick.studies.turnmap.TurnmapEngineParams`); the job validates its params into it. Here the plan
fills the same model from the study's sections (:class:`simpick.config.Study`, defaults filled in) and hands
the rule its plain dump (:func:`job_params`): builtins made canonical, as Snakemake fingerprints params by
their repr. A field the plan and the job disagree on stops the run here, at planning time, naming the rule,
the model and the key, instead of failing as a ``KeyError`` in a job.
"""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ValidationError

from simpick.errors import validation_problems
from simpick.plan.errors import PlanError
from simpick.sources.base import canonical, model_settings


def job_params(rule: str, model: type[BaseModel], data: dict[str, Any]) -> dict:
    """``data`` validated as ``model`` (what rule ``rule``'s job reads), as canonical plain data."""
    try:
        typed = model.model_validate(data)
    except ValidationError as exc:
        lines = "; ".join(f"{key}: {problem}" for key, problem in validation_problems(exc))
        raise PlanError(
            f"rule {rule}: the plan's params do not fit its job's {model.__module__}.{model.__name__} "
            f"({lines}); the plan (simpick.plan.jobs) and the job's model must name the same fields"
        ) from None
    return canonical(typed.model_dump(mode="json", by_alias=True))


def fields_of(section: BaseModel, model: type[BaseModel]) -> dict:
    """A config section's values of the fields a lower layer's ``model`` defines (the section subclasses
    it and adds fields no job of that model reads), as plain data."""
    return section.model_dump(mode="json", include=set(model.model_fields))


def _plain(data: dict[str, Any]) -> dict[str, Any]:
    """``data`` with its sections (models of the typed study) as plain data, to be validated as a job's model
    (revalidating a plain mapping checks every field: a model instance would pass as it is)."""
    return {k: v.model_dump(mode="json") if isinstance(v, BaseModel) else v for k, v in data.items()}


class JobPlanning:
    """The params of the rules whose jobs read a typed model (mixed into :class:`simpick.plan.Plan`, which
    gives ``settings``, the typed study, and ``config``, its plain settings with the simulator profiles)."""

    def _robot(self) -> dict:
        """The robot section less its file (a job reads the file from its input, whose content Snakemake
        tracks): the fields of :class:`simpick.inputs.robot.settings.RobotParams`."""
        from simpick.inputs.robot.settings import RobotParams

        return fields_of(self.settings.robot, RobotParams)

    def _grounds(self) -> dict:
        """Each real terrain class's ground as the engines see it (no source)."""
        from simpick.real.settings import Ground

        return {name: fields_of(terrain, Ground) for name, terrain in self.settings.real_data.classes.items()}

    def _engine(self, engine: str) -> dict:
        """A model's name, its settings (an engine's block, a profile's or a reference model's) and the step."""
        return {
            "engine": engine,
            "engine_settings": model_settings(self.config, engine),
            "physics": {"timestep": self.settings.physics.timestep},
        }

    # --- the turn map (rules/turnmap.smk) ---

    def turnmap_params(self, engine: str | None = None) -> dict:
        """Rule turnmap_grid's params; with ``engine``, rule turnmap_engine's for that engine."""
        from simpick.studies.turnmap import TurnmapEngineParams, TurnmapGridParams

        data = {"robot": self._robot(), "classes": self._grounds()}
        if engine is None:
            return job_params("turnmap_grid", TurnmapGridParams, data)
        return job_params("turnmap_engine", TurnmapEngineParams, data | self._engine(engine))

    # --- validation against analytic mechanics (rules/validate.smk) ---

    def validation_params(self, engine: str) -> dict:
        """Rule validate's params for a model (an engine or a simulator's profile)."""
        from simpick.studies.validation.job import ValidateParams

        data = self._engine(engine) | {"robot": self._robot(), "cases": self.settings.validation.cases}
        return job_params("validate", ValidateParams, data)

    # --- the simulators as rows (rules/simulators.smk) ---

    def simulators_params(self) -> dict:
        """Rule simulators' params: which profiles ran and what each reads, the engines beside them, the
        statistics and the verdict's margins (no weight), and how DRIVE's steps are judged where the study
        replays them (None without a DRIVE folder)."""
        from simpick.score.simulators import SimulatorsParams
        from simpick.sources import module as source_module

        drive = None
        if self.settings.drive_dir:
            judged = source_module("drive").compare_settings(self.settings)
            drive = {"tolerance": judged["tolerance"], "unit": judged["unit"]}
        data = {
            "profile_results": self.profile_results,
            "engines": self.engines,
            "simulators": self.simulators,
            "left_out": self.simulators_left_out,
            "settings_files": {p: f"results/simulators/settings/{p}" for p in self.profile_results},
            "model_files": self.model_files(),
            "model_notes": self.model_notes(),
            "statistics": self.settings.statistics,
            "seed": self.settings.seed,
            "verdict": self.settings.verdict,
            "drive": drive,
            "calibrated_left_out": self.calibrated_left_out,
        }
        return job_params("simulators", SimulatorsParams, _plain(data))

    def simulator_settings_params(self) -> dict:
        """Rule simulator_settings' params: each run profile's full settings and the robot's wheel links (the
        files' <gazebo reference>, pairs)."""
        from simpick.score.simulator_settings import SimulatorSettingsParams

        # the profiles' full settings are the plan's own (the catalog over the engine's block)
        data = {
            "profiles": {p: self.profile_settings[p] for p in self.profile_results},
            "robot": self.robot.name,
            "wheel_links": [w.link for w in self.robot.driven],
        }
        return job_params("simulator_settings", SimulatorSettingsParams, data)

    def simulator_models_params(self) -> dict:
        """Rule simulator_models' params: each model profile's full settings (a calibrated one's: its tuned
        profile's, the fit merged in the job), the catalog's words for where they come from, the robot, the step,
        the ground of the settings files and the validation's turning cases on it (simpick.studies.simulator_models)."""
        from simpick.engines.simulator_files import GROUND_MU
        from simpick.engines.simulators import MODEL_SETTINGS, engine_of, split
        from simpick.studies.simulator_models import SimulatorModelsParams, claimed_cases

        profiles = {}
        for p in self.model_profiles:
            simulator, variant = split(p)
            sim, engine = self.catalog.simulators[simulator], engine_of(p)
            # a calibrated profile starts from the tuned one (its fit is merged in the job); the catalog's profile
            # lies over the study's robot-model settings of its engine (its wheel actuators: MODEL_SETTINGS)
            catalogued = "tuned" if variant == "calibrated" else variant
            basis = f"the catalog's {catalogued} profile ({getattr(sim, catalogued).basis})"
            if MODEL_SETTINGS.get(engine):
                basis += f"; {', '.join(MODEL_SETTINGS[engine])} from the study's engines.{engine}"
            profiles[p] = {"settings": self.profile_settings[p], "label": sim.label, "basis": basis}
        data = {
            "profiles": profiles,
            "robot": self._robot(),
            "physics": {"timestep": self.settings.physics.timestep},
            "ground_mu": GROUND_MU,
            "cases": claimed_cases(self.settings.validation.cases, GROUND_MU),
        }
        return job_params("simulator_models", SimulatorModelsParams, _plain(data))

    def simulator_scores_params(self) -> dict:
        """The simulators' weighing (the report job's, simpick.report.weighing): the run simulators and the weights."""
        from simpick.score.simulators import SimulatorScoresParams

        data = {"simulators": self.simulators, "weights": self.settings.weights}
        return job_params("report", SimulatorScoresParams, data)

    def simulator_tree_params(self) -> dict:
        """Rule simulator_tree's params: the run simulators, and whether the study has a verdict."""
        from simpick.score.simulators import SimulatorTreeParams

        return job_params(
            "simulator_tree", SimulatorTreeParams, {"simulators": self.simulators, "verdict": self.verdict}
        )

    # --- a dataset folder's import and segments (the jobs of rules/real.smk, which builds their params inline
    # today; these give the same content, validated, for that file to pass instead) ---

    def real_segments_params(self) -> dict:
        """Rule real_segments' params: the segment rules, the controller's track and the data's source."""
        from simpick.real.jobs import SegmentsParams

        data = {
            "segment_rules": self.settings.real_data.segment_rules,
            "track": self.settings.robot.track,
            "source": self.replay_dataset()["source"],
        }
        return job_params("real_segments", SegmentsParams, _plain(data))

    def import_real_params(self) -> dict:
        """Rule import_real's settings: the controller's track, the dataset's name, label and declared rates."""
        from simpick.real.jobs import ImportParams

        dataset = self.replay_dataset()
        data = {
            "track": self.settings.robot.track,
            "dataset": self.replay_set.name,
            "label": dataset["label"],
            "declared": dataset["declared"],
        }
        return job_params("import_real", ImportParams, data)

    def real_turning_params(self) -> dict:
        """Rule real_turning's settings: the controller's track, the steady-command windows' length and
        settling, and the segment rules' tolerance and turn threshold."""
        from simpick.real.turning import TurningParams

        rules = self.settings.real_data.segment_rules
        data = {
            "track": self.settings.robot.track,
            "window": 1.0,  # s: short enough for many windows a run, long for a mean of 100 samples
            "settle": 0.5,  # s of held command before a window (wheel speeds settle in ~0.3 s)
            "tolerance": rules.tolerance,
            "min_turn": rules.min_turn,
        }
        return job_params("real_turning", TurningParams, data)

    # --- the calibration on step units (rules/drive.smk's drive_calibrate and drive_calibration) ---

    def drive_calibrate_params(self, model: str, terrain_class: str) -> dict:
        """Rule drive_calibrate's settings for a model and a terrain class: the model's simulation settings,
        every class's ground, how the steps are replayed and the calibration's search settings."""
        from simpick.sources.base import simulation_params
        from simpick.studies.calibration.steps import StepCalibrateParams

        cal = self.settings.calibration
        data = {
            "engine": model,
            "terrain_class": terrain_class,
            "case": simulation_params(self.settings, model, model_settings(self.config, model)),
            "classes": {name: c.model_dump(mode="json") for name, c in self.settings.real_data.classes.items()},
            "replay": self.settings.drive_replay.model_dump(mode="json"),
            "calibration": {
                "source": "drive",
                "scales": cal.scales.model_dump(mode="json"),
                "test_fraction": cal.test_fraction,
                "n_trials": cal.n_trials,
                "startup_trials": cal.startup_trials,
                "seed": cal.seed,
                "bounds": {model: cal.bounds.get(model) or {}},
            },
        }
        return job_params("drive_calibrate", StepCalibrateParams, data)

    def drive_calibration_params(self) -> dict:
        """Rule drive_calibration's settings: the statistics of its summary."""
        from simpick.studies.calibration.steps import StepSummaryParams

        data = {"statistics": self.settings.statistics.model_dump(mode="json")}
        return job_params("drive_calibration", StepSummaryParams, data)
