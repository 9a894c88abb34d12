"""Turning on held-out runs: each engine's yaw-rate gain and wheel-separation multiplier, before and
after calibration, against the real robot's, and the verdict on the config's turning target."""

from __future__ import annotations

import math

import pandas as pd

from simpick.compare.realmetrics import paired_test
from simpick.coulomb import wheel_separation_multiplier
from simpick.studies.calibration.intervals import interval_over_runs, stats_of

TARGET_POOL = "target classes"  # turning.csv's pooled rows: the held-out runs of calibration.target.classes
TURNING_COLUMNS = [
    "terrain_class",
    "engine",
    "variant",
    "n_runs",
    "gain_real",
    "gain_sim",
    "gain_ratio",
    "within_tolerance",
    "gain_error",
    "gain_error_low",
    "gain_error_high",
    "gain_error_min",
    "gain_error_max",
    "error_yaw_rate",
    "separation_multiplier",
    "separation_multiplier_real",
    "parameters",
]
TARGET_COLUMNS = [
    "engine",
    "is_engine",
    "n_runs",
    "error_calibrated",
    "error_configured",
    "error_reference",
    "vs_configured",
    "vs_configured_low",
    "vs_configured_high",
    "p_vs_configured",
    "vs_reference",
    "vs_reference_low",
    "vs_reference_high",
    "p_vs_reference",
    "lower_than_configured",
    "lower_than_reference",
    "worst_gain_ratio",
    "classes_off_gain",
    "gain_within_tolerance",
    "meets",
    "best",
]


def _per_run(frame: pd.DataFrame, column: str) -> pd.Series:
    """A figure averaged within each real run first (a run's segments are not independent), keyed
    by class/run (run numbers repeat across classes)."""
    ok = frame[frame.status == "ok"].dropna(subset=[column])
    return ok.groupby(ok.terrain_class + "/" + ok.run.astype(str))[column].mean()


def turning_table(
    evals: pd.DataFrame,
    best: dict[tuple[str, str], dict],
    track: float,
    separation: float,
    target: dict,
    statistics: dict | None = None,
) -> pd.DataFrame:
    """Per terrain class, model and variant, on the held-out (test) runs that turn: the real and the
    simulated yaw-rate gain (each averaged within a run, then over runs), their ratio and whether it
    is within ``target['gain_tolerance']``, the gain error |sim - real| with its interval over runs
    (none below ``statistics.min_runs``; the range over runs always), the yaw-rate error, and the
    ``wheel_separation_multiplier`` a ROS diff_drive_controller user would set to turn this model
    (and the real robot) as commanded (simpick.coulomb.wheel_separation_multiplier). Then the same
    over the held-out runs of ``target['classes']`` together (``TARGET_POOL``)."""
    min_runs, level = stats_of(statistics)
    test = evals[evals.set == "test"]
    if "gain_error" not in test:
        return pd.DataFrame(columns=TURNING_COLUMNS)
    tol = float(target["gain_tolerance"])
    classes = sorted(test.terrain_class.unique())
    pools = [(cls, test[test.terrain_class == cls]) for cls in classes]
    pools.append((TARGET_POOL, test[test.terrain_class.isin(target.get("classes") or classes)]))
    rows = []
    for cls, frame in pools:
        for (engine, variant), g in frame.groupby(["engine", "variant"], sort=True):
            gain_error, real, sim = (_per_run(g, c) for c in ("gain_error", "yaw_rate_gain_real", "yaw_rate_gain_sim"))
            if gain_error.empty:
                continue
            mean, low, high = interval_over_runs(gain_error.to_numpy(), list(gain_error.index), min_runs, level)
            g_real, g_sim = float(real.mean()), float(sim.mean())
            ratio = g_sim / g_real if g_real else math.nan
            found = best.get((engine, cls), {}) if variant == "calibrated" else {}  # best.yaml (a result file)
            rows.append(
                {
                    "terrain_class": cls,
                    "engine": engine,
                    "variant": variant,
                    "n_runs": int(gain_error.size),
                    "gain_real": g_real,
                    "gain_sim": g_sim,
                    "gain_ratio": ratio,
                    "within_tolerance": bool(abs(ratio - 1) <= tol) if cls != TARGET_POOL else math.nan,
                    "gain_error": mean,
                    "gain_error_low": low,
                    "gain_error_high": high,
                    "gain_error_min": float(gain_error.min()),
                    "gain_error_max": float(gain_error.max()),
                    "error_yaw_rate": float(_per_run(g, "error_yaw_rate").mean()),
                    "separation_multiplier": wheel_separation_multiplier(g_sim, track, separation),
                    "separation_multiplier_real": wheel_separation_multiplier(g_real, track, separation),
                    "parameters": "; ".join(f"{k}={v:.4g}" for k, v in (found.get("parameters") or {}).items()),
                }
            )
    return pd.DataFrame(rows, columns=TURNING_COLUMNS)


def target_table(
    evals: pd.DataFrame, turning: pd.DataFrame, engines: list[str], target: dict, statistics: dict | None = None
) -> pd.DataFrame:
    """The turning target (calibration.target), per calibrated model, on the held-out runs of ``target['classes']``
    together: its per-run yaw-rate error as calibrated against (a) its own as configured and (b) the
    ``target['reference']`` model as configured (rigid Coulomb mechanics), each by the paired
    sign-flip test over runs at ``statistics.level``; and per class whether its mean calibrated gain
    is within ``target['gain_tolerance']`` of the real robot's. ``meets`` when all three hold; ``best``
    marks the engine (a simulator, not a reference model) with the lowest mean calibrated error."""
    min_runs, level = stats_of(statistics)
    classes = target.get("classes") or sorted(evals.terrain_class.unique())
    test = evals[(evals.set == "test") & evals.terrain_class.isin(classes)]
    if test.empty:
        return pd.DataFrame(columns=TARGET_COLUMNS)
    test = test.assign(
        key=test.terrain_class + "/" + test.unit.astype(str), runkey=test.terrain_class + "/" + test.run.astype(str)
    )
    ok = test[test.status == "ok"]
    wide = ok.pivot_table(index="key", columns=["engine", "variant"], values="error_yaw_rate")
    run_of = test.drop_duplicates("key").set_index("key").runkey
    reference = (target["reference"], "configured")
    rows = []
    for engine in sorted(test.engine.unique()):
        if (engine, "calibrated") not in wide:
            continue
        cal = wide[(engine, "calibrated")]
        row = {
            "engine": engine,
            "is_engine": engine in engines,
            "n_runs": int(run_of.reindex(cal.dropna().index).nunique()),
            "error_calibrated": float(
                _per_run(ok[(ok.engine == engine) & (ok.variant == "calibrated")], "error_yaw_rate").mean()
            ),
        }
        for name, col in (("configured", (engine, "configured")), ("reference", reference)):
            other = wide[col] if col in wide else pd.Series(math.nan, index=wide.index)
            row[f"error_{name}"] = float(
                _per_run(ok[(ok.engine == col[0]) & (ok.variant == col[1])], "error_yaw_rate").mean()
            )
            t = paired_test(cal.to_numpy(), other.to_numpy(), run_of.reindex(wide.index).to_numpy(), min_runs, level)
            row.update(
                {
                    f"vs_{name}": t["mean"],
                    f"vs_{name}_low": t["low"],
                    f"vs_{name}_high": t["high"],
                    f"p_vs_{name}": t["p_value"],
                    f"lower_than_{name}": t["verdict"] == "b",
                }
            )
        gains = turning[
            (turning.engine == engine) & (turning.variant == "calibrated") & turning.terrain_class.isin(classes)
        ]
        off = [
            c if c in set(gains.terrain_class) else f"{c} (no held-out turning run)"
            for c in classes
            if c not in set(gains.terrain_class)
            or not bool(gains.loc[gains.terrain_class == c, "within_tolerance"].iloc[0])
        ]
        row["worst_gain_ratio"] = (
            float(gains.gain_ratio.iloc[(gains.gain_ratio - 1).abs().argmax()]) if len(gains) else math.nan
        )
        row["classes_off_gain"] = "; ".join(off)
        row["gain_within_tolerance"] = not off
        row["meets"] = bool(row["lower_than_configured"] and row["lower_than_reference"] and not off)
        rows.append(row)
    out = pd.DataFrame(rows, columns=TARGET_COLUMNS)
    sims = out[out.is_engine & out.error_calibrated.notna()]
    out["best"] = False
    if len(sims):
        out.loc[sims.error_calibrated.idxmin(), "best"] = True
    return out
