"""What makes up each engine's weighted total (paper section 4, Table 11), and what separates the
leader from the others: written by the scores job beside the weighted table, so that a reader (the
report, the decision tree) takes the points and the drivers as they are and computes none."""

from __future__ import annotations

import math
from collections.abc import Mapping

import pandas as pd

from simpick.score.scoring import METRIC_LABELS, METRICS, QUALITATIVE_METRICS

CONTRIBUTION_COLUMNS = [
    "engine",
    "rank",
    "total",
    "share",
    "metric",
    "label",
    "group",
    "weight",
    "score",
    "points",
    "excluded",
]
DRIVER_COLUMNS = ["engine", "leader", "gap", "metric", "label", "difference", "order"]


def contributions(weighted: pd.DataFrame, weights: Mapping[str, float]) -> pd.DataFrame:
    """One row per engine and metric of the weighted table (:func:`weighted_table`): the weight,
    the score, its points (weight x score, a NaN score counting as 0 with ``excluded`` true), the
    engine's total, rank and share of the largest possible total (the sum of the weights)."""
    top = sum(float(weights[m]) for m in METRICS)
    rows = []
    for engine, row in weighted.iterrows():
        for m in METRICS:
            score = float(row[m])
            rows.append(
                {
                    "engine": engine,
                    "rank": int(row["rank"]),
                    "total": float(row["total"]),
                    "share": float(row["total"]) / top if top else math.nan,
                    "metric": m,
                    "label": METRIC_LABELS[m],
                    "group": "qualitative" if m in QUALITATIVE_METRICS else "quantitative",
                    "weight": float(weights[m]),
                    "score": score,
                    "points": 0.0 if math.isnan(score) else float(weights[m]) * score,
                    "excluded": math.isnan(score),
                }
            )
    return pd.DataFrame(rows, columns=CONTRIBUTION_COLUMNS)


def drivers(contribution: pd.DataFrame) -> pd.DataFrame:
    """Per engine other than the leader (rank 1, first in the table) and metric: the leader's points
    less the engine's (``difference``: positive where the metric puts the leader ahead), ``gap`` the
    difference of the totals, ``order`` 1 for the metric that favours the leader most."""
    if contribution.empty:
        return pd.DataFrame(columns=DRIVER_COLUMNS)
    leader = contribution.engine.iloc[0]
    points = contribution.pivot_table(index="metric", columns="engine", values="points", sort=False)
    totals = contribution.drop_duplicates("engine").set_index("engine").total
    rows = []
    for engine in dict.fromkeys(contribution.engine):
        if engine == leader:
            continue
        diff = (points[leader] - points[engine]).sort_values(ascending=False, kind="mergesort")
        for order, (m, d) in enumerate(diff.items(), start=1):
            rows.append(
                {
                    "engine": engine,
                    "leader": leader,
                    "gap": float(totals[leader] - totals[engine]),
                    "metric": m,
                    "label": METRIC_LABELS[m],
                    "difference": float(d),
                    "order": order,
                }
            )
    return pd.DataFrame(rows, columns=DRIVER_COLUMNS)
