"""simpick's verdict: which engine reproduces the real robot best, and how sure that is.

The paper's accuracy scores (Eq. 7 sums, Eq. 8 min/E) are kept exactly as it defines them, in
the weighted table (simpick.score.scoring). On real Husky data they cannot separate engines: Eq. 7 sums
per-axis ranges and means of the raw 100 Hz IMU, and the ranges are the real robot's vibration,
which no rigid-ground model has (the no-slip kinematic formula scores as well as any engine). So
beside the paper's method this module gives simpick's verdict from figures that measure what a
mobile-robot user needs from an engine, per real run:

- ``gain_error``: |simulated - real yaw-rate gain| on the turning tests (how much the robot turns
  for a commanded turn: skid-steer slip);
- ``heading_error``: |integral over a segment or replay window of (simulated - real) gyro z| (rad):
  the heading a simulated robot gains or loses on the real one, straight or turning;
- ``speed_error``: |simulated - real forward speed|, only where a log carries a speed measured
  independently of the wheel commands. BorealTC holds IMU and wheel speeds only, and the wheel
  speeds are the replay's input: its speed error cannot be computed, and the table says so rather
  than invent a speed from them.

Every figure is averaged within a run first (segments and windows of one run are not independent)
and pooled over every real run of the source (terrain classes together: runs are independent).
Intervals are BCa over runs, from the validated ``statistics.min_runs`` runs on. Two views of the
engines: each against the best, the one a user acts on (outcomes.csv: worse, equivalent within a
practical margin, or undetermined; simpick.score.equivalence, behind the mechanics gate of
simpick.score.mechanics), and each against the next in the order of the means (table.csv: an exact
sign-flip test of paired per-run differences, with roughly how many runs would separate the two).

The paper's weighted total gets an interval too (:func:`ranking`, run by simpick.score.answer:
the weights reach it): the runs resampled with replacement (each run's tests together, every engine
alike), the Eq. 7 totals and Eq. 8 scores recomputed per draw, the rest of the total (qualitative
facts, RTF, CPU) held as measured.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.compare import realmetrics
from simpick.compare.metrics import eq7_sum
from simpick.score.equivalence import outcomes_table
from simpick.score.mechanics import mechanics_table
from simpick.tables import write_csv

METRICS = {
    "gain_error": {
        "label": "yaw-rate gain error",
        "unit": "",
        "tests": "turning tests",
        "what": "|simulated - real yaw-rate gain| on the turning tests",
    },
    "heading_error": {
        "label": "heading error",
        "unit": "rad",
        "tests": "every test",
        "what": "|integral of (simulated - real) gyro z| over each segment or replay window",
    },
    "speed_error": {
        "label": "speed error",
        "unit": "m/s",
        "tests": "logs with a measured speed",
        "what": "|simulated - real forward speed|, where a log measures speed independently of the wheel commands",
    },
}
NO_SPEED = (
    "not measurable on this data: its logs hold IMU and wheel speeds only (no GNSS, motion capture or "
    "odometry independent of the commanded wheel speeds), and the wheel speeds are the replay's input"
)
TABLE_COLUMNS = [
    "metric",
    "label",
    "unit",
    "model",
    "is_engine",
    "n_runs",
    "mean",
    "low",
    "high",
    "rank",
    "next",
    "diff_to_next",
    "diff_low",
    "diff_high",
    "p_to_next",
    "separates_from_next",
    "runs_needed",
    "note",
]
SEPARATION_COLUMNS = [
    "metric",
    "label",
    "method",
    "n_runs",
    "best",
    "second",
    "p_value",
    "separates",
    "runs_needed",
    "statement",
]
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
POWER = 0.8  # runs_needed: the runs at which a difference of the observed size would be found 4 times in 5


def _stats(statistics: dict | None) -> tuple[int, float]:
    return realmetrics.statistics_settings(statistics)


def run_key(frame: pd.DataFrame) -> pd.Series:
    """A real run's name across terrain classes (run numbers repeat between classes)."""
    return frame["terrain_class"].astype(str) + "/" + frame["run"].astype(str)


def per_run_values(per_test: pd.DataFrame, metric: str) -> pd.DataFrame:
    """Run x model: the metric averaged over each run's healthy tests (NaN where a model has none)."""
    ok = per_test[(per_test.status == "ok")] if "status" in per_test else per_test
    if metric not in ok or ok.empty:
        return pd.DataFrame()
    ok = ok.assign(_run=run_key(ok), _v=pd.to_numeric(ok[metric], errors="coerce"))
    ok = ok[np.isfinite(ok._v)]
    if ok.empty:
        return pd.DataFrame()
    return ok.pivot_table(index="_run", columns="engine", values="_v", aggfunc="mean")


def per_run_long(walls: dict[str, pd.DataFrame]) -> pd.DataFrame:
    """metrics.csv: one row per real run, model and metric with a value (``walls``: metric -> the run x
    model frame of :func:`per_run_values`), the per-run values the answer's figure draws."""
    long = []
    for metric, wide in walls.items():
        for run, row in wide.iterrows():
            long += [{"run": run, "model": m, "metric": metric, "value": v} for m, v in row.items() if np.isfinite(v)]
    return pd.DataFrame(long, columns=["run", "model", "metric", "value"])


def runs_needed(differences, level: float, power: float = POWER) -> float:
    """Roughly how many runs a paired test would need to find a mean difference of the observed
    size at the observed spread: n = ((z_(1 - alpha/2) + z_power) sd / |mean|)^2 (normal
    approximation; NaN where the differences are all zero or fewer than two)."""
    from scipy.stats import norm

    d = np.asarray(differences, float)
    d = d[np.isfinite(d)]
    if d.size < 2 or d.mean() == 0:
        return float("nan")
    sd = float(d.std(ddof=1))
    if sd == 0:
        return float(d.size)
    z = norm.ppf(1 - (1 - level) / 2) + norm.ppf(power)
    return float(math.ceil((z * sd / abs(float(d.mean()))) ** 2))


def metric_table(
    per_test: pd.DataFrame, engines: list[str], statistics: dict | None = None, seed: int = 0
) -> pd.DataFrame:
    """Metric x model: mean over runs with its BCa interval, the engines' order by mean (smaller is
    closer to the real robot), and each engine against the next one: the paired difference over
    the runs both have, its sign-flip p-value, whether it separates, and about how many runs would.
    Models that are not engines (reference models) are listed for comparison, never ranked."""
    min_runs, level = _stats(statistics)
    rows = []
    for metric, info in METRICS.items():
        wide = per_run_values(per_test, metric)
        base = {"metric": metric, "label": info["label"], "unit": info["unit"]}
        if wide.empty:
            note = NO_SPEED if metric == "speed_error" else f"no {info['tests']} completed"
            models = sorted(set(per_test.engine)) if "engine" in per_test else []
            rows += [dict(base, model=m, is_engine=m in engines, n_runs=0, note=note) for m in models]
            continue
        stats = {}
        for model in wide.columns:
            x = wide[model].dropna().to_numpy(float)
            mean, low, high, n = realmetrics.mean_ci(x, None, min_runs, level, seed)
            stats[model] = {"mean": mean, "low": low, "high": high, "n_runs": n}
        ranked = sorted((m for m in wide.columns if m in engines), key=lambda m: (stats[m]["mean"], m))
        for model in list(wide.columns):
            row = dict(base, model=model, is_engine=model in engines, **stats[model], note="")
            if model in ranked:
                i = ranked.index(model)
                row["rank"] = i + 1
                if i + 1 < len(ranked):
                    nxt = ranked[i + 1]
                    pair = wide[[model, nxt]].dropna()
                    t = realmetrics.paired_test(
                        pair[model].to_numpy(), pair[nxt].to_numpy(), None, min_runs, level, seed
                    )
                    separates = None if t["verdict"] == "too few runs" else t["verdict"] == "b"
                    row.update(
                        next=nxt,
                        diff_to_next=t["mean"],
                        diff_low=t["low"],
                        diff_high=t["high"],
                        p_to_next=t["p_value"],
                        separates_from_next=separates,
                        runs_needed=(runs_needed(pair[model] - pair[nxt], level) if not separates else float("nan")),
                    )
                    if separates is None:
                        row["note"] = f"too few runs ({t['n_runs']} < {min_runs})"
            rows.append(row)
    return pd.DataFrame(rows, columns=TABLE_COLUMNS)


def _fmt(x: float, digits: int = 3) -> str:
    return "–" if x is None or not np.isfinite(x) else f"{x:.{digits}g}"


def _runs_text(n: float) -> str:
    """A runs-needed estimate in words: '1 100' rather than 1.12e+03 (rounded to 2 significant digits)."""
    if n is None or not np.isfinite(n):
        return "an unknown number of"
    n = int(n)
    if n >= 100:
        n = int(round(n, -(len(str(n)) - 2)))
    return f"{n:,}".replace(",", " ")


def separation_rows(table: pd.DataFrame, min_runs: int) -> list[dict]:
    """Per metric of simpick's verdict: does it separate the closest engine from the next?"""
    out = []
    for metric, g in table.groupby("metric", sort=False):
        info = METRICS[metric]
        first = g[(g["rank"] == 1)]
        if first.empty:
            note = g.note.dropna().iloc[0] if g.note.notna().any() else "no engine completed it"
            out.append(
                {
                    "metric": metric,
                    "label": info["label"],
                    "method": "simpick",
                    "n_runs": 0,
                    "best": "",
                    "second": "",
                    "p_value": float("nan"),
                    "separates": None,
                    "runs_needed": float("nan"),
                    "statement": f"{info['label']}: {note}",
                }
            )
            continue
        r = first.iloc[0]
        n = int(r.n_runs)
        if not isinstance(r.next, str) or not r.next:
            statement = f"{info['label']}: only {r.model} has runs"
            separates = None
        elif r.separates_from_next is True or r.separates_from_next == "True":
            separates = True
            statement = (
                f"{info['label']}: {r.model} is closest ({_fmt(r['mean'])} [{_fmt(r.low)}, {_fmt(r.high)}] "
                f"over {n} runs), separated from {r.next} (paired p {_fmt(r.p_to_next, 2)})"
            )
        else:
            separates = None if "too few" in str(r.note) else False
            tied = [r.model, r.next]
            # every engine whose mean the best one cannot be told apart from, down the order
            for _, s in g[g["rank"] >= 2].sort_values("rank").iterrows():
                if s.separates_from_next is True or s.separates_from_next == "True" or not isinstance(s.next, str):
                    break
                tied.append(s.next)
            why = (
                f"too few runs ({n} < {min_runs})"
                if separates is None
                else f"{r.model} against {r.next}: paired p {_fmt(r.p_to_next, 2)} over {n} runs; about "
                f"{_runs_text(r.runs_needed)} runs would separate them at the observed spread"
            )
            pairs = g[g.next.astype(str).isin(tied) & g.model.isin(tied) & g.p_to_next.notna()]
            if separates is False and len(pairs) > 1:
                near = pairs.sort_values("p_to_next").iloc[0]
                if near.model != r.model:
                    why += (
                        f"; closest to separating: {near.model} against {near.next}, paired p "
                        f"{_fmt(near.p_to_next, 2)}, about {_runs_text(near.runs_needed)} runs"
                    )
            statement = (
                f"{info['label']}: {', '.join(dict.fromkeys(tied))} cannot be told apart, none "
                f"separated from the next in that order ({why})"
            )
        out.append(
            {
                "metric": metric,
                "label": info["label"],
                "method": "simpick",
                "n_runs": n,
                "best": r.model,
                "second": r.next if isinstance(r.next, str) else "",
                "p_value": r.p_to_next,
                "separates": separates,
                "runs_needed": r.runs_needed,
                "statement": statement,
            }
        )
    return out


# --- the paper's method: what its accuracy scores and its total can tell apart --------------------------


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


HEADING_COLUMNS = [
    "model",
    "test",
    "terrain_class",
    "run",
    "start_heading_deg",
    "yaw_rate_gain_sim",
    "yaw_rate_gain_reference",
    "gain_ratio",
]
HEADING_REFERENCE = "coulomb"  # heading-independent by construction: the same command's gain on any heading


def heading_spread(per_test: pd.DataFrame, reference: str = HEADING_REFERENCE) -> pd.DataFrame:
    """Each model's yaw-rate gain on every turning test against the reference model's gain on the
    same test (``gain_ratio``), with the test's seeded start heading: on flat isotropic ground the
    ratio should not depend on the heading, so its spread over the tests' headings shows an engine
    whose turning does (PyBullet: 90-degree period). Empty without the reference model."""
    need = {"yaw_rate_gain_sim", "start_heading_deg", "engine", "test"}
    if not need <= set(per_test.columns) or reference not in set(per_test.engine):
        return pd.DataFrame(columns=HEADING_COLUMNS)
    ok = per_test[(per_test.status == "ok") & np.isfinite(pd.to_numeric(per_test.yaw_rate_gain_sim, errors="coerce"))]
    ref = ok[ok.engine == reference].set_index("test").yaw_rate_gain_sim.astype(float)
    rows = []
    for r in ok[ok.engine != reference].to_dict("records"):
        g_ref = ref.get(r["test"], float("nan"))
        rows.append(
            {
                "model": r["engine"],
                "test": r["test"],
                "terrain_class": r.get("terrain_class"),
                "run": r.get("run"),
                "start_heading_deg": float(r["start_heading_deg"]),
                "yaw_rate_gain_sim": float(r["yaw_rate_gain_sim"]),
                "yaw_rate_gain_reference": g_ref,
                "gain_ratio": float(r["yaw_rate_gain_sim"]) / g_ref if g_ref else float("nan"),
            }
        )
    return pd.DataFrame(rows, columns=HEADING_COLUMNS)


def scored_tests(imu_errors: str, engines: list[str]) -> list[str] | None:
    """The tests the accuracy scores rest on, as the Eq. 7 totals file lists them (the scores
    record the same list in their provenance)."""
    errors = pd.read_csv(imu_errors, dtype=str, keep_default_na=False)
    errors = errors[errors.engine.isin(engines)]
    tests = sorted({t for cell in errors.get("tests", []) for t in str(cell).split(";") if t.strip() and t != "nan"})
    return tests or None


def read_per_test(path: str) -> pd.DataFrame:
    tests = pd.read_csv(path, dtype={"run": str, "test": str, "segment": str})
    for col in ("engine", "terrain_class", "run", "status", "test"):
        if col not in tests:
            tests[col] = pd.Series(dtype=str)
    return tests


def verdict_job(inputs: dict, params: dict, outputs: dict) -> None:
    """results/verdict/: per-run metrics, the metric x model table (each engine against the next),
    each engine against the best (outcomes.csv: simpick.score.equivalence) with the mechanics gate
    it rests on (mechanics.csv: simpick.score.mechanics), the heading spread and what the paper's
    accuracy scores separate (discrimination). Nothing here reads the weights: a weight edit does
    not rerun these tests (the weighted ranking and the answer are rule ``answer``'s).

    ``inputs``: ``per_test`` (the verdict's real data), ``validation`` (the validation summary),
    ``accuracy_tests`` and ``accuracy_errors`` (the accuracy scores' per-test table and Eq. 7
    totals); ``params``: engines, baselines, statistics, seed, ``accuracy_set`` (lab, segments,
    replay or own) and ``verdict`` (the config's margins and mechanics)."""
    statistics = params.get("statistics")
    engines, floor_models = list(params["engines"]), list(params.get("baselines") or [])
    seed = int(params.get("seed", 0))
    tests = read_per_test(inputs["per_test"])
    walls = {metric: per_run_values(tests, metric) for metric in METRICS}
    write_csv(per_run_long(walls), outputs["metrics"])
    write_csv(metric_table(tests, engines, statistics, seed), outputs["table"])
    if outputs.get("headings"):
        write_csv(heading_spread(tests), outputs["headings"])

    mechanics = mechanics_table(pd.read_csv(inputs["validation"]), engines)
    write_csv(mechanics, outputs["mechanics"])
    absent = {"speed_error": NO_SPEED}
    outcomes = outcomes_table(walls, tests, engines, METRICS, mechanics, params["verdict"], statistics, seed, absent)
    write_csv(outcomes, outputs["outcomes"])

    disc = pd.DataFrame(columns=DISCRIMINATION_COLUMNS)
    if params.get("accuracy_set") not in (None, "lab") and Path(inputs["accuracy_tests"]).is_file():
        acc_per_test = read_per_test(inputs["accuracy_tests"])
        scored = [e for e in engines if e in set(acc_per_test.engine)]
        if len(acc_per_test) and scored:
            disc = score_discrimination(
                acc_per_test,
                scored,
                floor_models,
                scored_tests(inputs["accuracy_errors"], scored),
                statistics,
                seed=seed,
            )
    write_csv(disc, outputs["discrimination"])
