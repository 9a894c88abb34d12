"""The paper's method judged on the same runs: how much of each engine's Eq. 7 total is the engine
rather than the floor no rigid model escapes, whether its Eq. 8 score separates the engines, and the
weighted total with an interval over runs resampled with replacement.

It is the paper's scoring put to simpick's statistical test, apart from simpick's own metrics, so
that the two methods' rows can be compared side by side in the answer."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from simpick.compare.metrics import eq7_sum
from simpick.score.verdict.runs import _fmt, _stats, run_key

RANKING_COLUMNS = [
    "engine",
    "total",
    "total_low",
    "total_high",
    "rank",
    "share_first",
    "imu_points",
    "imu_points_low",
    "imu_points_high",
    "other_points",
    "n_runs",
    "resamples",
]
DISCRIMINATION_COLUMNS = [
    "quantity",
    "engine",
    "error",
    "floor",
    "engine_part",
    "floor_share",
    "score",
    "score_low",
    "score_high",
    "spread",
    "half_width",
    "separates",
    "n_runs",
    "floor_models",
]
IMU_SCORES = {"angular": "imu_angular", "linear": "imu_linear"}


def score_discrimination(
    per_test: pd.DataFrame,
    engines: list[str],
    floor_models: list[str],
    tests: list[str] | None = None,
    statistics: dict | None = None,
    resamples: int = 2000,
    seed: int = 0,
) -> pd.DataFrame:
    """How much of each engine's Eq. 7 total is the engine, and whether its Eq. 8 score separates it.

    - ``floor``: the smallest Eq. 7 total of the rigid reference models (``floor_models``, e.g.
      kinematic and coulomb) over the same tests: the real vibration and sensor offsets no rigid
      model produces. ``engine_part`` = E - floor, ``floor_share`` = floor / E.
    - the score's uncertainty: the Eq. 8 scores recomputed over runs resampled with replacement
      (each run's tests together, all engines alike, seeded): a percentile interval per engine,
      from ``statistics["min_runs"]`` runs on. The score ``separates`` the engines when its spread
      (largest minus smallest) is larger than the half-width of the widest interval; empty when
      there are too few runs to say.
    """
    from simpick.score.scoring import accuracy_scores

    min_runs, level = _stats(statistics)
    ok = per_test[per_test.status == "ok"]
    if tests is not None:
        ok = ok[ok.test.astype(str).isin(set(map(str, tests)))]
    ok = ok.assign(_unit=run_key(ok))
    models = [m for m in engines + floor_models if m in set(ok.engine)]
    rows = []
    for q in IMU_SCORES:
        col = f"error_{q}"
        if col not in ok or not models or not any(e in models for e in engines):
            continue
        wide = ok.pivot_table(index="_unit", columns="engine", values=col, aggfunc=eq7_sum)[models].dropna()
        eng = [e for e in engines if e in wide.columns]
        floors = [m for m in floor_models if m in wide.columns]
        totals = wide.agg(eq7_sum)
        scores = accuracy_scores({e: float(totals[e]) for e in eng})
        floor = float(totals[floors].min()) if floors else float("nan")
        n_runs = len(wide)
        low = {e: float("nan") for e in eng}
        high = dict(low)
        if n_runs >= max(min_runs, 2):
            rng = np.random.default_rng(seed)
            draws = wide[eng].to_numpy(float)[rng.integers(0, n_runs, size=(resamples, n_runs))].sum(axis=1)
            with np.errstate(divide="ignore", invalid="ignore"):
                boot = draws.min(axis=1, keepdims=True) / draws
            alpha = (1 - level) / 2
            for i, e in enumerate(eng):
                low[e], high[e] = (float(v) for v in np.nanquantile(boot[:, i], [alpha, 1 - alpha]))
        spread = max(scores.values()) - min(scores.values()) if scores else float("nan")
        widths = [(high[e] - low[e]) / 2 for e in eng if np.isfinite(low[e])]
        half = max(widths) if widths else float("nan")
        separates = None if not widths else bool(spread > half)
        for e in eng:
            rows.append(
                {
                    "quantity": q,
                    "engine": e,
                    "error": float(totals[e]),
                    "floor": floor,
                    "engine_part": float(totals[e]) - floor,
                    "floor_share": floor / float(totals[e]) if totals[e] > 0 else float("nan"),
                    "score": scores[e],
                    "score_low": low[e],
                    "score_high": high[e],
                    "spread": spread,
                    "half_width": half,
                    "separates": separates,
                    "n_runs": n_runs,
                    "floor_models": ";".join(floors),
                }
            )
    return pd.DataFrame(rows, columns=DISCRIMINATION_COLUMNS)


def ranking(
    weighted: pd.DataFrame,
    per_test: pd.DataFrame | None,
    tests: list[str] | None,
    weights: dict,
    statistics: dict | None = None,
    resamples: int = 2000,
    seed: int = 0,
) -> pd.DataFrame:
    """The paper's weighted total per engine with an interval over real runs: the runs resampled
    with replacement, the Eq. 7 totals and Eq. 8 accuracy scores recomputed per draw, everything
    else (qualitative facts, RTF, CPU) as measured. ``share_first``: the share of draws in which
    the engine ranks first. No interval below ``statistics.min_runs`` runs, or when the accuracy
    scores rest on the lab (no runs to resample)."""
    min_runs, level = _stats(statistics)
    engines = list(weighted.index)
    w = {q: float(weights[key]) for q, key in IMU_SCORES.items()}
    imu = sum(w[q] * weighted[key].astype(float).fillna(0.0) for q, key in IMU_SCORES.items())
    other = weighted["total"].astype(float) - imu
    out = pd.DataFrame(
        {
            "engine": engines,
            "total": weighted["total"].astype(float).to_numpy(),
            "rank": weighted["rank"].to_numpy(),
            "imu_points": imu.to_numpy(),
            "other_points": other.to_numpy(),
        }
    )
    for col in ("total_low", "total_high", "share_first", "imu_points_low", "imu_points_high"):
        out[col] = float("nan")
    out["n_runs"], out["resamples"] = 0, 0
    if per_test is None or per_test.empty or "run" not in per_test:
        return out[RANKING_COLUMNS]
    ok = per_test[(per_test.status == "ok") & per_test.engine.isin(engines)]
    if tests is not None:
        ok = ok[ok.test.astype(str).isin(set(map(str, tests)))]
    ok = ok.assign(_unit=run_key(ok))
    walls = {
        q: ok.pivot_table(index="_unit", columns="engine", values=f"error_{q}", aggfunc=eq7_sum).reindex(
            columns=engines
        )
        for q in IMU_SCORES
    }
    units = sorted(set.intersection(*(set(v.dropna().index) for v in walls.values())))
    n = len(units)
    out["n_runs"] = n
    if n < max(min_runs, 2):
        return out[RANKING_COLUMNS]
    rng = np.random.default_rng(seed)
    pick = rng.integers(0, n, size=(resamples, n))
    points = np.zeros((resamples, len(engines)))
    for q, wide in walls.items():
        draws = wide.loc[units].to_numpy(float)[pick].sum(axis=1)  # (resamples, engines)
        with np.errstate(divide="ignore", invalid="ignore"):
            points += w[q] * draws.min(axis=1, keepdims=True) / draws
    totals = other.to_numpy()[None, :] + points
    alpha = (1 - level) / 2
    out["total_low"], out["total_high"] = np.quantile(totals, alpha, axis=0), np.quantile(totals, 1 - alpha, axis=0)
    out["imu_points_low"], out["imu_points_high"] = (
        np.quantile(points, alpha, axis=0),
        np.quantile(points, 1 - alpha, axis=0),
    )
    first = totals.argmax(axis=1)
    out["share_first"] = [float(np.mean(first == i)) for i in range(len(engines))]
    out["resamples"] = resamples
    return out[RANKING_COLUMNS]


def paper_rows(rank: pd.DataFrame, discrimination: pd.DataFrame, weights: dict) -> list[dict]:
    """The separation rows of the paper's method: each IMU accuracy score and the weighted total."""
    out = []
    for q, key in IMU_SCORES.items():
        d = discrimination[discrimination.quantity == q]
        if d.empty:
            continue
        best = d.sort_values("score", ascending=False).iloc[:2]
        sep = d.separates.iloc[0]
        sep = None if sep is None or (isinstance(sep, float) and math.isnan(sep)) else bool(sep)
        lo, hi = d.score.min(), d.score.max()
        statement = (
            f"the paper's IMU {q} accuracy score (Eq. 8, weight {weights[key]:g}): {_fmt(lo)}–{_fmt(hi)} "
            f"for every engine; "
            + (
                "its spread exceeds the interval half-width"
                if sep
                else "too few runs to say"
                if sep is None
                else f"its spread {_fmt(d.spread.iloc[0], 2)} is within the resampling "
                f"half-width {_fmt(d.half_width.iloc[0], 2)}: it does not separate"
            )
        )
        out.append(
            {
                "metric": key,
                "label": f"IMU {q} accuracy score (Eq. 8)",
                "method": "paper",
                "quantity": q,
                "low": float(lo),
                "high": float(hi),
                "n_runs": int(d.n_runs.iloc[0]),
                "best": best.engine.iloc[0],
                "second": best.engine.iloc[1] if len(best) > 1 else "",
                "p_value": float("nan"),
                "separates": sep,
                "runs_needed": float("nan"),
                "statement": statement,
            }
        )
    r = rank.sort_values("total", ascending=False)
    if len(r) >= 2:
        a, b = r.iloc[0], r.iloc[1]
        given = np.isfinite(a.total_low)
        sep = bool(a.total_low > b.total_high) if given else None
        spread_imu = float(r.imu_points.max() - r.imu_points.min())
        spread_other = float(r.other_points.max() - r.other_points.min())
        statement = (
            f"the paper's weighted total: {a.engine} {a.total:.3f}"
            + (f" [{a.total_low:.3f}, {a.total_high:.3f}]" if given else "")
            + f", {b.engine} {b.total:.3f}"
            + (f" [{b.total_low:.3f}, {b.total_high:.3f}]" if given else "")
            + f"; the IMU accuracy scores move the engines' totals by at most {spread_imu:.2f} points, the "
            f"qualitative facts, RTF and CPU by {spread_other:.2f}"
        )
        out.append(
            {
                "metric": "total",
                "label": "weighted total (the paper's method)",
                "method": "paper",
                "totals": statement.split(": ", 1)[1].split("; the IMU")[0],
                "n_runs": int(a.n_runs),
                "best": a.engine,
                "second": b.engine,
                "p_value": float("nan"),
                "separates": sep,
                "runs_needed": float("nan"),
                "statement": statement,
            }
        )
    return out
