"""The statistics the calibration's summaries share: the validated settings (least runs, level) and
the interval over runs, by the real-data statistics' rule."""

from __future__ import annotations

import math

import numpy as np

from simpick.compare.realmetrics import mean_ci, statistics_settings


def stats_of(statistics: dict | None) -> tuple[int, float]:
    """(min_runs, level) of the validated ``statistics`` settings (simpick.plan: Plan.statistics_params)."""
    return statistics_settings(statistics)


def interval_over_runs(values, runs, min_runs: int, level: float) -> tuple[float, float, float]:
    """(mean, low, high) over runs (a run's units averaged first): the real-data statistics'
    rule (simpick.compare.realmetrics.mean_ci), so no interval below ``min_runs`` runs."""
    values = np.asarray(values, float)
    if len(values) == 0:
        return (math.nan, math.nan, math.nan)
    mean, low, high, _ = mean_ci(values, runs, min_runs, level)
    return mean, low, high
