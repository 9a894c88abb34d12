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
