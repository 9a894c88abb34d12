"""A calibration job's settings as typed models: the objective's windows and scales, the search's budget and
bounds, and what the workflow's calibrate and evaluate jobs read (:class:`EvaluateSettings`,
:class:`SearchSettings`). The config's ``calibration`` section (:class:`simpick.config.studies.Calibration`)
extends :class:`CalibrationWindows` and :class:`CalibrationBudget`, so each field has one definition."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from simpick.params import Finite, JobParams, Positive
from simpick.real.settings import SteadyRules


class CalibrationScales(JobParams):
    """Each error of the objective is divided by its scale before they are summed, so the terms count alike."""

    yaw_rate: Positive = Field(description="rad/s, the low-passed yaw-rate error's scale")
    accel_x: Positive = Field(description="m/s^2, the low-passed longitudinal-acceleration error's scale")
    yaw_rate_gain: Positive | None = Field(
        None,
        description="the steady yaw-rate gain error's scale, on units that "
        "turn under a steady command; null: no gain term",
    )


class CalibrationWindows(JobParams):
    """What a unit's errors are measured over: the first seconds of each unit, and the objective's scales."""

    segment_seconds: Positive | None = Field(
        None, description="committed segments: the first seconds of each compared window"
    )
    replay_seconds: Positive | None = Field(None, description="full replay: the first seconds of each run")
    scales: CalibrationScales = Field(description="the objective's scales")


class CalibrationBudget(JobParams):
    """The search's budget, seed and bounds."""

    seed: Annotated[int, Field(ge=0, lt=2**32)] = Field(description="the split and the sampler derive from it")
    n_trials: Annotated[int, Field(ge=1)] = Field(
        description="evaluations per model x class, each over all its "
        "training units; the first is the as-configured model"
    )
    startup_trials: Annotated[int, Field(ge=1)] = Field(
        description="random trials before the TPE sampler models the history"
    )
    bounds: dict[str, dict[str, Annotated[list[Finite], Field(min_length=2, max_length=2)]]] = Field(
        {}, description="model -> parameter -> [low, high], overriding the bounds its adapter declares"
    )


class CalibrationSplit(JobParams):
    """How the units are split: the held-out share (the config's ``calibration.test_fraction``)."""

    test_fraction: Annotated[float, Field(gt=0, lt=1, allow_inf_nan=False)] = Field(
        description="share of each terrain class's runs held out (split by run, never within one)"
    )


class EvaluateSettings(CalibrationWindows):
    """What rule calibration_evaluate's job reads besides its case: the source of the units, the windows, the
    scales and, for a replayed run, the steady-command rules of its turning windows."""

    source: Literal["segments", "replay"] = Field(description="the units: committed segments or replayed runs")
    steady: SteadyRules | None = Field(None, description="a replayed run's turning windows; None for segments")


class SearchSettings(EvaluateSettings, CalibrationBudget):
    """What rule calibrate's job reads besides its case: the evaluation's settings, the budget, the seed and this
    model's bounds."""


__all__ = [
    "CalibrationBudget",
    "CalibrationSplit",
    "CalibrationScales",
    "CalibrationWindows",
    "EvaluateSettings",
    "SearchSettings",
]
