"""How far the paper's published figures (:mod:`simpick.inputs.published`) can be recomputed: the
paper's arithmetic redone with :mod:`simpick.score.scoring`:

* Table 11 from Table 3's facts and Table 10's raw figures;
* a per-metric comparison of recomputed and printed scores;
* the worked example (Tables 6 to 9) of the Eq. 7 error.

Nothing here bends a formula to fit a printed figure: where the paper's
numbers disagree with each other, both are returned side by side.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import pandas as pd

from simpick.compare.metrics import axis_errors
from simpick.score.scoring import (
    METRICS,
    accuracy_scores,
    efficiency_scores,
    qualitative_scores,
    real_time_factor_scores,
    weighted_table,
)

# A printed score has 3 decimals; a recomputed one "matches" when it rounds to it.
MATCH_TOLERANCE = 5e-4 + 1e-9

# Eq. 7 figures come from 2-3 decimal inputs; rounding the float noise away
# keeps the JSON readable without changing any printed digit.
_DIGITS = 9


def _recomputed_scores(published: Mapping[str, Any]) -> pd.DataFrame:
    sims: list[str] = list(published["simulators"])
    t10 = published["table10"]

    def pick(block: Mapping[str, float]) -> dict[str, float]:
        return {s: block[s] for s in sims}  # paper order

    quantitative = {
        "real_time_factor": real_time_factor_scores(pick(t10["real_time_factor"])),
        "cpu_average": efficiency_scores(pick(t10["cpu_average_percent"])),
        "cpu_intense": efficiency_scores(pick(t10["cpu_intense_percent"])),
        "imu_angular": accuracy_scores(pick(t10["imu_angular_error_rad_s"])),
        "imu_linear": accuracy_scores(pick(t10["imu_linear_error_m_s2"])),
    }
    rows = {}
    for s in sims:
        row = qualitative_scores(published["table3"]["facts"][s])
        row.update({m: quantitative[m][s] for m in quantitative})
        rows[s] = row
    df = pd.DataFrame.from_dict(rows, orient="index")[list(METRICS)]
    df.index.name = "simulator"
    return df


def _published_scores(published: Mapping[str, Any]) -> pd.DataFrame:
    sims = list(published["simulators"])
    scores = published["table11"]["scores"]
    df = pd.DataFrame.from_dict({s: scores[s] for s in sims}, orient="index")[list(METRICS)].astype(float)
    df.index.name = "simulator"
    return df


def recompute_table11(published: Mapping[str, Any]) -> pd.DataFrame:
    """Table 11 recomputed, one row per simulator in the paper's order.

    Columns: every metric key (qualitative from Table 3's facts, quantitative
    from Table 10's figures), ``total`` (those scores times Table 11's
    weights), ``total_from_published_scores`` (Table 11's printed scores times
    its weights) and ``published_total`` (Table 11's printed totals).
    """
    weights = {k: float(v) for k, v in published["table11"]["weights"].items()}
    recomputed = _recomputed_scores(published)
    totals = weighted_table(recomputed, weights)["total"]
    printed = _published_scores(published)
    w = pd.Series({k: weights[k] for k in METRICS})

    out = recomputed.copy()
    out["total"] = totals.reindex(out.index)
    out["total_from_published_scores"] = printed.mul(w, axis=1).sum(axis=1)
    out["published_total"] = pd.Series(published["table11"]["totals"], dtype=float).reindex(out.index)
    return out


def table11_comparison(published: Mapping[str, Any]) -> pd.DataFrame:
    """Long form: simulator, metric, published, recomputed, difference, matches.

    ``difference`` is recomputed minus published; ``matches`` is true when
    the recomputed score rounds to the printed 3-decimal figure.
    """
    recomputed = _recomputed_scores(published)
    printed = _published_scores(published)
    records = []
    for s in recomputed.index:
        for m in METRICS:
            p, r = float(printed.at[s, m]), float(recomputed.at[s, m])
            d = r - p
            records.append(
                {
                    "simulator": s,
                    "metric": m,
                    "published": p,
                    "recomputed": r,
                    "difference": d,
                    "matches": bool(abs(d) <= MATCH_TOLERANCE),
                }
            )
    return pd.DataFrame.from_records(records)


def _r(x: float) -> float:
    return round(x, _DIGITS)


def _example_block(inputs: Mapping[str, Any], printed: Mapping[str, Any], text_total: float) -> dict[str, Any]:
    axes = axis_errors(inputs["sim"], inputs["real"])
    printed_axes = {a: {k: float(v) for k, v in printed[a].items()} for a in axes}
    return {
        "unit": inputs["unit"],
        "axes": {a: {k: _r(v) for k, v in e.items()} for a, e in axes.items()},
        # Sum of the per-axis errors recomputed from the range/mean table.
        "total_from_inputs": _r(sum(e["total_error"] for e in axes.values())),
        "printed_axes": printed_axes,
        "printed_rows_sum": _r(sum(p["total_error"] for p in printed_axes.values())),
        "text_total": float(text_total),
        "axis_differences": {a: {k: _r(axes[a][k] - printed_axes[a][k]) for k in axes[a]} for a in axes},
    }


def worked_example(published: Mapping[str, Any]) -> dict[str, Any]:
    """Tables 8 and 9 recomputed from Tables 6 and 7 (one test, Eq. 7).

    Returns ``angular`` and ``linear`` blocks, each with the recomputed
    per-axis errors, ``total_from_inputs`` (from Table 6 / 7),
    ``printed_rows_sum`` (Table 8 / 9 rows added up) and ``text_total`` (the
    figure the text states), so disagreements stay visible: for the linear
    acceleration these are 23.43, 23.39 and 23.19 m/s^2.
    """
    ex = published["worked_example"]
    text = ex["text_totals"]
    return {
        "source": ex["source"],
        "test": dict(ex["test"]),
        "sensor_frame": dict(ex["sensor_frame"]),
        "angular": _example_block(ex["table6"], ex["table8"], text["angular_rad_s"]),
        "linear": _example_block(ex["table7"], ex["table9"], text["linear_m_s2"]),
    }


def _json_safe(obj: Any) -> Any:
    if isinstance(obj, float) and math.isnan(obj):
        return None
    if isinstance(obj, dict):
        return {k: _json_safe(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_json_safe(v) for v in obj]
    return obj


def write_outputs(published: Mapping[str, Any], outdir: str | Path) -> dict[str, Path]:
    """Write ``table11.csv``, ``table11_comparison.csv`` and ``worked_example.json``.

    Returns the written paths by short name.
    """
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    paths = {
        "table11": out / "table11.csv",
        "table11_comparison": out / "table11_comparison.csv",
        "worked_example": out / "worked_example.json",
    }
    recompute_table11(published).to_csv(paths["table11"], index_label="simulator")
    table11_comparison(published).to_csv(paths["table11_comparison"], index=False)
    with open(paths["worked_example"], "w", encoding="utf-8") as fh:
        json.dump(_json_safe(worked_example(published)), fh, indent=2)
        fh.write("\n")
    return paths
