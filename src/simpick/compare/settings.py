"""What the compare stage's jobs are given, as typed models: the statistics over independent real runs (which
:mod:`simpick.compare.realmetrics` applies; the score layer and the config's ``statistics`` section reuse the
model), and each kind's comparison settings (:data:`simpick.compare.kinds.SETTINGS`)."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field, model_validator

from simpick.compare.realmetrics import LEVEL, MIN_RUNS, smallest_p
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
        if smallest_p(self.min_runs) >= 1 - self.level:
            raise ValueError(
                f"statistics.min_runs {self.min_runs}: a sign-flip test over {self.min_runs} runs "
                f"cannot give p below {smallest_p(self.min_runs):.3g}, so no verdict could ever reach "
                f"level {self.level:g}; use at least {_runs_for(self.level)}"
            )
        return self


def _runs_for(level: float) -> int:
    n = 2
    while smallest_p(n) >= 1 - level:
        n += 1
    return n


class NoSettings(JobParams):
    """A comparison that reads no settings (the lab's against the paper's figures, a step unit's against the
    real robot's steady figures): its files say it all."""


class SegmentSettings(JobParams):
    """What the segments' comparison reads (simpick.compare.real.segment_compare)."""

    track: Positive = Field(description="m, the controller's track (the config's robot.track): the kinematic yaw rate")


class ReplaySettings(SegmentSettings):
    """What a replayed run's comparison reads (simpick.compare.real.replay_compare)."""

    window: Positive = Field(description="s: a full replay is compared in windows of this length (real_data.window)")


class SummariseSettings(JobParams):
    """What rule summarise's job reads (simpick.compare.jobs.summarise_job): the column that groups the source's
    cases and the statistics over runs."""

    group: str = Field(description="the source's group column: 'terrain' (the lab) or 'terrain_class'")
    statistics: Statistics | None = Field(None, description="the study's statistics; None: their defaults")


__all__ = ["NoSettings", "ReplaySettings", "SegmentSettings", "Statistics", "SummariseSettings"]
