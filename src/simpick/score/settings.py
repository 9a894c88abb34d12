"""How results are judged, as the jobs are given it: the statistics over independent real runs (defined with the
comparison that applies them, :mod:`simpick.compare.settings`) and the verdict's margins and mechanics gate.
Defined here, in the score layer, so that the jobs read them typed; the config's sections
(:mod:`simpick.config.verdict`) are these models, so each field has one definition."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from simpick.compare.settings import Statistics  # noqa: F401 - defined with the comparison that applies it
from simpick.params import JobParams, Positive

VERDICT_METRICS = ("gain_error", "heading_error", "speed_error")


# the kinds of validation case (simpick.studies.validation) a metric's mechanics can rest on; "invariance":
# the checks made across yaw-gain cases (left against right turns, start headings)
CASE_KINDS = Literal["yaw_gain", "straight", "slide", "incline", "rest", "rest_pose", "articulation", "invariance"]


# the real robot's own figure behind a metric, which a margin measured from the data is taken from
REAL_FIGURE = {"gain_error": "yaw_rate_gain_real"}


class Margin(JobParams):
    """A practical margin of one verdict metric: differences to the best engine smaller than this
    are of no practical consequence (simpick.score.equivalence.margin)."""

    basis: Literal["absolute", "real_spread", "real_fraction"] = Field(
        description="absolute: `value` in the metric's unit; real_spread: `value` x the real robot's own "
        "run-to-run spread of the figure behind the metric (pooled within-class standard deviation "
        "over runs); real_fraction: `value` x the real robot's mean of that figure"
    )
    value: Positive = Field(description="the margin (absolute) or the factor (real_spread, real_fraction)")


class VerdictMargins(JobParams):
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


class VerdictMechanics(JobParams):
    gain_error: list[CASE_KINDS] = Field(["yaw_gain", "invariance"], description="case kinds gain error rests on")
    heading_error: list[CASE_KINDS] = Field(
        ["yaw_gain", "invariance", "straight"], description="case kinds heading error rests on"
    )
    speed_error: list[CASE_KINDS] = Field(["straight"], description="case kinds speed error rests on")


class Verdict(JobParams):
    """simpick's verdict on the real data: each engine against the best (simpick.score.equivalence)."""

    margins: VerdictMargins = Field(VerdictMargins(), description="the practical margin of each metric")
    mechanics: VerdictMechanics = Field(
        VerdictMechanics(),
        description="the validation case kinds each metric depends on: an engine failing "
        "one is shown with a flag and never named best on that metric",
    )
