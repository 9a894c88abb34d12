"""How results are judged, as the jobs are given it: the statistics over independent real runs and the
verdict's margins and mechanics gate. Defined here, in the score layer, so that the jobs read them typed; the
config's sections (:mod:`simpick.config.verdict`) are these models, so each field has one definition."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from simpick.compare.realmetrics import LEVEL, MIN_RUNS
from simpick.params import JobParams, Positive


class Statistics(JobParams):
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


def _runs_for(level: float) -> int:
    from simpick.compare.realmetrics import smallest_p

    n = 2
    while smallest_p(n) >= 1 - level:
        n += 1
    return n
