"""What a job is given, as a typed model: the base classes and number types every job's parameter
model and the config's section models share.

A rule's ``params:`` reach its job as plain builtin data (Snakemake fingerprints params by their repr, so
they stay builtins, made canonical by :func:`simpick.sources.base.canonical`). Next to each job function,
in its stage's module, a frozen :class:`JobParams` model says exactly what the job reads; the job
validates its params into it (``p = Model.model_validate(params)``) and reads typed fields, so a renamed
field fails where it is defined, not as a ``KeyError`` in a job. The plan builds the same params by
validating the study's slice against the same model (:mod:`simpick.plan.jobs`), so a mismatch stops the
run at planning time. The config's section models (:mod:`simpick.config`) reuse the stages' models for
the fields the jobs read (a section model subclasses or composes them), so each field is defined once.

This module lies in the lowest layer (tests/test_layers.py), so every stage can define its models on it.
"""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field

Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False)]
Finite = Annotated[float, Field(allow_inf_nan=False)]


class Strict(BaseModel):
    """A config section: no unknown keys (a misspelt key is an error, not silently ignored)."""

    model_config = ConfigDict(extra="forbid", ser_json_inf_nan="constants")


class JobParams(BaseModel):
    """What one job reads: no unknown keys (the plan and the job agree on every field) and frozen (a job
    reads its parameters, never edits them)."""

    model_config = ConfigDict(frozen=True, extra="forbid", ser_json_inf_nan="constants")


class PhysicsStep(JobParams):
    """The physics step of a job that steps an engine (the config's ``physics`` section adds the floor)."""

    timestep: Positive = Field(
        description="s, the physics step of every engine (1 ms: the IMU's internal 1 kHz "
        "sampling); must divide the IMU period into whole steps"
    )


__all__ = ["Finite", "JobParams", "NonNegative", "PhysicsStep", "Positive", "Strict"]
