"""Every engine against the best, per real-data metric: worse, equivalent or undetermined.

"Not separated" is not "equal": with a handful of real runs two engines may fail to separate and
still differ by more than anyone would accept. So each engine is compared with the best engine of
a metric on the paired per-run values (a run's tests averaged first: simpick.score.verdict), by

- a one-sided paired t-test of "this engine's error is larger than the best's" (scipy), its
  p-values Holm-adjusted over the engines of the metric (statsmodels ``multipletests``);
- two one-sided paired t-tests against the practical margin (TOST, statsmodels ``ttost_paired``),
  whose p-value is the larger of the two;
- the t interval of the mean paired difference at the study's ``statistics.level``.

Outcomes (``OUTCOMES``): ``best``; ``equivalent`` when that interval lies inside +-margin (then
the TOST p is below (1 - level) / 2, stricter than alpha = 1 - level, and both are required);
``worse`` when the Holm-adjusted p is below alpha and the engine is not equivalent;
``undetermined`` otherwise, with about how many runs would decide it; ``too few runs`` below
``statistics.min_runs`` paired runs; ``not measurable`` where the data hold no value of the metric.

Every engine is judged on the same runs: the runs every compared engine completed (a run an engine
failed, by its health check or its watchdog, has no value of its own). An engine's mean over fewer runs
than the others' is a mean over other conditions, and the lowest of such means is no pick. The runs an
engine failed that another completed are listed with the reasons (``failed_runs``), so the answer can
say them beside any sentence that names the engine. An engine with fewer completed runs than
``statistics.min_runs`` is left out of that common set (it would shrink every comparison to its few
runs) and is compared with the best on the runs both have: too few to judge.

The best engine is the one with the lowest mean among the engines that pass the validation cases
the metric rests on (simpick.score.mechanics): an engine that fails them is compared and shown with
its figure and a flag, and is never the best, however low its error (an engine that under-turns by a
friction artefact looks closest where the real robot turns little).

The margin comes from the config (``verdict.margins``), fixed before looking at engine
differences: an absolute value in the metric's unit, or a factor times the real robot's own
run-to-run spread (pooled within-class standard deviation over runs) or mean of the figure behind
the metric (the real yaw-rate gain for the gain error).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from simpick.compare import realmetrics

OUTCOMES = ("best", "equivalent", "worse", "undetermined", "too few runs", "not measurable")
POWER = 0.8  # runs_to_decide: the runs at which the observed difference would be decided 4 times in 5
# the real robot's own figure behind a metric (a margin measured from the data takes it)
REAL_FIGURE = {"gain_error": ("yaw_rate_gain_real", "yaw-rate gain")}


def _run_values(per_test: pd.DataFrame, column: str) -> pd.DataFrame:
    """The real robot's figure per run (terrain class, run, value): every model's row of a test
    carries the same real value, so each test counts once, then a run's tests are averaged."""
    if column not in per_test or per_test.empty:
        return pd.DataFrame(columns=["terrain_class", "run", "value"])
    frame = per_test.assign(value=pd.to_numeric(per_test[column], errors="coerce"))
    frame = frame[np.isfinite(frame.value)].drop_duplicates(["terrain_class", "run", "test"])
    return frame.groupby(["terrain_class", "run"], as_index=False).value.mean()


def real_spread(per_test: pd.DataFrame, column: str) -> tuple[float, int, int]:
    """(pooled within-class standard deviation over runs, runs, classes) of the real robot's
    ``column``: how much the robot itself varies between runs on one terrain. Only classes with two
    runs or more count; NaN where none has."""
    runs = _run_values(per_test, column)
    groups = [g.value.to_numpy(float) for _, g in runs.groupby("terrain_class") if len(g) >= 2]
    dof = sum(g.size - 1 for g in groups)
    if not dof:
        return float("nan"), 0, 0
    pooled = sum(float(((g - g.mean()) ** 2).sum()) for g in groups) / dof
    return math.sqrt(pooled), sum(g.size for g in groups), len(groups)


def margin(per_test: pd.DataFrame, metric: str, spec: dict, unit: str = "") -> tuple[float, str]:
    """The practical margin of ``metric`` (``spec``: the config's ``basis`` and ``value``) and one
    sentence saying where it comes from."""
    basis, value = spec["basis"], float(spec["value"])
    unit = f" {unit}" if unit else ""
    if basis == "absolute":
        return value, f"declared in the config: {value:.3g}{unit}"
    column, label = REAL_FIGURE[metric]
    if basis == "real_spread":
        spread, n_runs, n_classes = real_spread(per_test, column)
        if not np.isfinite(spread):
            return float("nan"), (
                f"the real robot's run-to-run spread of its {label} cannot be measured here: no "
                "terrain class has two runs with it, so no margin and no equivalence"
            )
        factor = "" if value == 1 else f"{value:g} x "
        return value * spread, (
            f"{factor}the real robot's own run-to-run spread of its {label}: the pooled "
            f"within-class standard deviation over {n_runs} runs in {n_classes} terrain classes, "
            f"{spread:.3g}{unit}"
        )
    runs = _run_values(per_test, column)
    if runs.empty:
        return float("nan"), f"the real robot's {label} is not in this data: no margin and no equivalence"
    mean = abs(float(runs.value.mean()))
    return value * mean, (f"{value:g} of the real robot's mean {label} over {len(runs)} runs ({mean:.3g}{unit})")


def paired_comparison(engine, best, margin_value: float, level: float) -> dict:
    """One engine's per-run values against the best's over the same runs: the mean difference
    (engine - best), its t interval at ``level``, the one-sided p of "engine larger" (unadjusted)
    and the TOST p against +-``margin_value`` (NaN without a margin)."""
    from scipy.stats import ttest_1samp
    from statsmodels.stats.weightstats import ttost_paired

    x, y = np.asarray(engine, float), np.asarray(best, float)
    d = x - y
    out = {
        "n": int(d.size),
        "mean": float(d.mean()) if d.size else float("nan"),
        "low": float("nan"),
        "high": float("nan"),
        "p_worse": float("nan"),
        "p_equivalent": float("nan"),
        "sd": float(d.std(ddof=1)) if d.size > 1 else float("nan"),
    }
    if d.size < 2:
        return out
    finite_margin = bool(np.isfinite(margin_value) and margin_value > 0)
    if out["sd"] <= 1e-12 * max(1.0, abs(out["mean"])):  # every run differs by the same amount: no spread
        out["sd"] = 0.0
        out.update(low=out["mean"], high=out["mean"], p_worse=0.0 if out["mean"] > 0 else 1.0)
        if finite_margin:
            out["p_equivalent"] = 0.0 if abs(out["mean"]) < margin_value else 1.0
        return out
    one_sided = ttest_1samp(d, 0.0, alternative="greater")
    interval = ttest_1samp(d, 0.0).confidence_interval(level)
    out.update(low=float(interval.low), high=float(interval.high), p_worse=float(one_sided.pvalue))
    if finite_margin:
        out["p_equivalent"] = float(ttost_paired(x, y, -margin_value, margin_value)[0])
    return out


def holm(p_values) -> np.ndarray:
    """Holm-adjusted p-values (statsmodels ``multipletests``); NaN entries stay NaN and do not count."""
    from statsmodels.stats.multitest import multipletests

    p = np.asarray(p_values, float)
    out = np.full(p.shape, np.nan)
    finite = np.isfinite(p)
    if finite.any():
        out[finite] = multipletests(p[finite], method="holm")[1]
    return out


def runs_to_decide(mean: float, sd: float, margin_value: float, level: float, power: float = POWER) -> float:
    """About how many runs would decide an undetermined comparison at the observed mean difference
    and spread (normal approximation, one-sided tests at alpha = 1 - level): equivalence where the
    difference lies inside the margin, n = ((z_(1-alpha) + z_power) sd / (margin - |mean|))^2;
    worse where it lies beyond, n = ((z_(1-alpha) + z_power) sd / mean)^2. NaN where nothing
    could decide it (a difference exactly at the margin, no spread, or a difference in favour of
    the engine outside the margin)."""
    from scipy.stats import norm

    if not (np.isfinite(mean) and np.isfinite(sd)) or sd == 0:
        return float("nan")
    z = norm.ppf(level) + norm.ppf(power)
    if np.isfinite(margin_value) and abs(mean) < margin_value:
        gap = margin_value - abs(mean)
    elif mean > 0:
        gap = mean
    else:
        return float("nan")
    return float(math.ceil((z * sd / gap) ** 2))


def judge(row: dict, alpha: float, margin_value: float) -> str:
    """The outcome of one compared engine from its paired comparison (``row``: low, high,
    p_worse Holm-adjusted, p_equivalent)."""
    inside = bool(
        np.isfinite(margin_value)
        and np.isfinite(row["low"])
        and -margin_value < row["low"]
        and row["high"] < margin_value
    )
    if inside and row["p_equivalent"] < alpha:
        return "equivalent"
    if row["p_worse"] < alpha:
        return "worse"
    return "undetermined"


OUTCOME_COLUMNS = [
    "metric",
    "label",
    "unit",
    "engine",
    "n_runs",
    "mean",
    "low",
    "high",
    "best",
    "is_best",
    "diff_to_best",
    "diff_low",
    "diff_high",
    "margin",
    "margin_basis",
    "p_worse",
    "p_equivalent",
    "outcome",
    "runs_needed",
    "mechanics",
    "mechanics_failed",
    "mechanics_note",
    "recommendable",
    "runs_completed",
    "runs_failed",
    "runs_all",
    "failed_runs",
    "note",
]
FAILED_SEPARATOR = " | "  # between the runs of ``failed_runs``: a health reason holds "; " and ", " itself
# The scope of the rows over all the real data: the DRIVE comparison's outcomes (simpick.score.steps) hold
# those rows and then one set per terrain class (its ``scope`` column, simpick.compare.steps.ALL)
POOLED = "all"


def pooled(outcomes: pd.DataFrame) -> pd.DataFrame:
    """One row per metric x engine over all the real data, whichever comparison wrote ``outcomes``: the
    verdict's (results/verdict/outcomes.csv) as it is, the DRIVE comparison's (results/drive/<name>/
    outcomes.csv) its pooled rows (``scope`` all), so that the answer, its figure, the decision tree and
    the report read either through this one function."""
    if "scope" not in outcomes:
        return outcomes
    return outcomes[outcomes["scope"].astype(str) == POOLED].drop(columns="scope").reset_index(drop=True)


def _run_names(per_test: pd.DataFrame) -> pd.Series:
    """A real run's name across terrain classes, as simpick.score.verdict.run_key names the runs."""
    return per_test["terrain_class"].astype(str) + "/" + per_test["run"].astype(str)


def why_failed(per_test: pd.DataFrame, engine: str, run: str) -> str:
    """Why ``engine`` has no value on ``run``: its failed tests' health reasons (unique, in order), else
    what is known of them."""
    if per_test.empty or not {"engine", "terrain_class", "run"} <= set(per_test.columns):
        return "no result"
    rows = per_test[(per_test.engine == engine) & (_run_names(per_test) == run)]
    if rows.empty:
        return "not run"
    bad = rows[rows.status.astype(str) != "ok"] if "status" in rows else rows.iloc[0:0]
    if bad.empty:
        return "no value of this metric"
    reasons = []
    for r in bad.itertuples():
        text = str(getattr(r, "reasons", "") or "")
        text = text if text and text != "nan" else f"status {r.status}"
        if text not in reasons:
            reasons.append(text)
    return "; ".join(reasons)


def common_runs(wide: pd.DataFrame, engines: list[str], min_runs: int) -> tuple[list[str], pd.Index]:
    """(the engines compared on common runs, the runs every one of them completed): the engines with a
    value on at least ``min_runs`` runs (all of them where none has that many)."""
    counts = {e: int(wide[e].notna().sum()) for e in engines}
    compared = [e for e in engines if counts[e] >= min_runs] or list(engines)
    return compared, wide[compared].dropna().index if compared else wide.index[:0]


def outcomes_table(
    walls: dict[str, pd.DataFrame],
    per_test: pd.DataFrame,
    engines: list[str],
    metrics: dict[str, dict],
    mechanics: pd.DataFrame,
    settings: dict,
    statistics: dict | None = None,
    seed: int = 0,
    absent: dict[str, str] | None = None,
) -> pd.DataFrame:
    """One row per metric x engine (``OUTCOME_COLUMNS``; reference models are not in it).

    ``walls``: metric -> run x model per-run values (simpick.score.verdict.per_run_values);
    ``per_test``: the per-test table they come from (for a margin measured from the real robot);
    ``metrics``: metric -> label and unit; ``mechanics``: simpick.score.mechanics.mechanics_table;
    ``settings``: the config's ``verdict`` (``margins``, ``mechanics``); ``absent``: metric -> why
    it has no value (its note where the data cannot measure it)."""
    from simpick.score.mechanics import recommendable

    min_runs, level = realmetrics.statistics_settings(statistics)
    alpha = 1 - level
    mech = mechanics.set_index("engine")
    rows = []
    for metric, info in metrics.items():
        value, basis = margin(per_test, metric, settings["margins"][metric], info["unit"])
        allowed = recommendable(mechanics, settings["mechanics"][metric])
        wide = walls.get(metric, pd.DataFrame())
        base = {"metric": metric, "label": info["label"], "unit": info["unit"], "margin": value, "margin_basis": basis}
        present = [e for e in engines if e in wide.columns and wide[e].notna().any()]
        on_common, common = common_runs(wide, present, min_runs)
        stats = {}
        for engine in present:
            x = (wide.loc[common, engine] if engine in on_common else wide[engine].dropna()).to_numpy(float)
            mean, low, high, n = realmetrics.mean_ci(x, None, min_runs, level, seed)
            stats[engine] = {"n_runs": n, "mean": mean, "low": low, "high": high}
        eligible = [e for e in on_common if allowed.get(e)]
        best = min(eligible or on_common, key=lambda e: (stats[e]["mean"], e)) if on_common else ""
        # the runs each engine lacks that another completed, with why
        pool = wide[present].notna() if present else pd.DataFrame()
        failures = {}
        for engine in present:
            others = pool.drop(columns=engine).any(axis=1) if len(present) > 1 else pool[engine] & False
            lost = [str(r) for r in pool.index[others & ~pool[engine]]]
            failures[engine] = [(r, why_failed(per_test, engine, r)) for r in lost]
        compared = {}
        if best:
            for engine in present:
                if engine == best:
                    continue
                pair = wide.loc[common, [engine, best]] if engine in on_common else wide[[engine, best]].dropna()
                compared[engine] = paired_comparison(pair[engine], pair[best], value, level)
            testable = [e for e in compared if compared[e]["n"] >= max(min_runs, 2)]
            for engine, p in zip(testable, holm([compared[e]["p_worse"] for e in testable])):
                compared[engine]["p_worse_holm"] = float(p)
        for engine in engines:
            m = mech.loc[engine] if engine in mech.index else None
            row = dict(
                base,
                engine=engine,
                best=best,
                is_best=engine == best and bool(best),
                mechanics=m["mechanics"] if m is not None else "fail",
                mechanics_failed=int(m["mechanics_failed"]) if m is not None else 0,
                mechanics_note=m["mechanics_note"] if m is not None else "not validated",
                recommendable=bool(allowed.get(engine)),
                runs_completed=int(wide[engine].notna().sum()) if engine in present else 0,
                runs_failed=len(failures.get(engine, [])),
                runs_all=int(pool.any(axis=1).sum()) if present else 0,
                failed_runs=FAILED_SEPARATOR.join(f"{r}: {why}" for r, why in failures.get(engine, [])),
                note="",
                **stats.get(engine, {"n_runs": 0}),
            )
            if engine not in present:
                row.update(
                    outcome="not measurable", note=(absent or {}).get(metric) or f"no value of this metric for {engine}"
                )
            elif engine == best:
                row.update(outcome="best" if stats[engine]["n_runs"] >= min_runs else "too few runs", diff_to_best=0.0)
                if not row["recommendable"]:
                    row["note"] = (
                        "no engine passes the mechanics this metric rests on: the lowest mean is "
                        "shown as the reference of the comparison, not as a recommendation"
                    )
                elif stats[engine]["n_runs"] < min_runs:
                    row["note"] = f"too few runs ({stats[engine]['n_runs']} < {min_runs})"
            else:
                c = compared[engine]
                row.update(diff_to_best=c["mean"], diff_low=c["low"], diff_high=c["high"])
                if c["n"] < max(min_runs, 2):
                    row.update(outcome="too few runs", note=f"too few paired runs ({c['n']} < {min_runs})")
                else:
                    row.update(p_worse=c["p_worse_holm"], p_equivalent=c["p_equivalent"])
                    row["outcome"] = judge(
                        {
                            "low": c["low"],
                            "high": c["high"],
                            "p_worse": c["p_worse_holm"],
                            "p_equivalent": c["p_equivalent"],
                        },
                        alpha,
                        value,
                    )
                    if row["outcome"] == "undetermined":
                        row["runs_needed"] = runs_to_decide(c["mean"], c["sd"], value, level)
                        if c["mean"] < 0 and not (np.isfinite(value) and abs(c["mean"]) < value):
                            row["note"] = (
                                f"a lower mean than {best}, but it fails the mechanics this metric rests "
                                "on: shown, never recommended"
                            )
                if not row["recommendable"] and not row["note"]:
                    row["note"] = "fails the mechanics this metric rests on: shown, never recommended"
            rows.append(row)
    return pd.DataFrame(rows, columns=OUTCOME_COLUMNS)
