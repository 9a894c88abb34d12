"""The paper's weighted table cell by cell: per engine and metric the weight, the score and their
product, the weighted score (paper section 4, Table 11), beside the engine's total and rank.

Written by the scores job next to ``weighted.csv`` so that the report shows these cells as a rule
wrote them and multiplies nothing itself. The products are those :func:`simpick.score.scoring.weighted_table`
sums (a metric without a score counts as 0), so each engine's ``weighted`` column adds up to its ``total``.
"""

from __future__ import annotations

from collections.abc import Mapping

import pandas as pd

from simpick.score.scoring import METRIC_LABELS, METRICS, QUALITATIVE_METRICS

COLUMNS = ["engine", "rank", "total", "metric", "label", "group", "weight", "score", "measured", "weighted"]


def contributions_table(weighted: pd.DataFrame, weights: Mapping[str, float]) -> pd.DataFrame:
    """One row per engine (in ``weighted``'s order: the ranking) and metric (:data:`METRICS` order)."""
    rows = []
    for engine, r in weighted.iterrows():
        for m in METRICS:
            score = float(r[m])
            measured = score == score  # NaN: not measured, counts as 0 in the total
            rows.append({"engine": engine, "rank": int(r["rank"]), "total": float(r["total"]), "metric": m,
                         "label": METRIC_LABELS.get(m, m),
                         "group": "qualitative" if m in QUALITATIVE_METRICS else "quantitative",
                         "weight": float(weights[m]), "score": score, "measured": measured,
                         "weighted": float(weights[m]) * score if measured else 0.0})
    return pd.DataFrame(rows, columns=COLUMNS)
