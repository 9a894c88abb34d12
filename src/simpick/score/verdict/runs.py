"""simpick's own metrics per real run and what they tell apart: each figure averaged within a run,
the metric x model table with BCa intervals over runs, each engine against the next in the order of
the means (an exact sign-flip test), and the statement per metric of whether it separates them.

The run is the unit of every statistic here, so the per-run values (:func:`per_run_values`) and
everything computed from them share one module; the paper's scores and the job that writes the
tables read them."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from simpick.compare import realmetrics

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
