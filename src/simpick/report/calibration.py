"""The report's calibration section (results/calibration/<source>/summary.csv, rules/calibration.smk)."""

from __future__ import annotations

import math
from typing import Any

import pandas as pd

from simpick.studies.calibration.summary import POOLED
from simpick.studies.calibration.turning import TARGET_POOL


def _cell(row, fig: str, variant: str) -> dict:
    def get(key):
        value = row.get(key)
        return None if value is None or (isinstance(value, float) and math.isnan(value)) else float(value)

    return {"mean": get(f"{fig}_{variant}"), "low": get(f"{fig}_{variant}_low"), "high": get(f"{fig}_{variant}_high")}


def _rank(value) -> int | None:
    """A rank cell (NA or NaN below statistics.min_runs runs) as an int or None."""
    try:
        return None if pd.isna(value) else int(value)
    except (TypeError, ValueError):
        return None


def _parameters(found: str, configured: str) -> list[dict]:
    """'friction=0.0573; cfm=6.03e-06' and its as-configured twin -> [{name, found, configured}]
    with 3 significant digits, one per line in the report."""

    def parse(text) -> dict[str, str]:
        out = {}
        for part in str(text or "").split(";"):
            if "=" in part:
                key, value = part.split("=", 1)
                try:
                    value = f"{float(value):.3g}"
                except ValueError:
                    value = value.strip()
                out[key.strip()] = value
        return out

    got, conf = parse(found), parse(configured)
    return [{"name": k.replace("_", " "), "found": v, "configured": conf.get(k, "–")} for k, v in got.items()]


def _num(value) -> float | None:
    try:
        value = float(value)
    except (TypeError, ValueError):
        return None
    return None if math.isnan(value) else value


def turning_rows(turning: pd.DataFrame | None, engines: list[str]) -> list[dict]:
    """Per class (the target classes pooled last): per model, as configured and as calibrated, the
    held-out mean yaw-rate gain against the real robot's, the gain error with its interval (or its
    range over runs below statistics.min_runs), and the equivalent wheel_separation_multiplier."""
    if turning is None or turning.empty:
        return []
    order = {e: i for i, e in enumerate(engines)}
    out = []
    for cls in sorted(turning.terrain_class.unique(), key=lambda c: (c == TARGET_POOL, c)):
        g = turning[turning.terrain_class == cls]
        rows = []
        for engine in sorted(g.engine.unique(), key=lambda e: (order.get(e, len(order)), e)):
            by = {r["variant"]: r for r in g[g.engine == engine].to_dict("records")}
            conf, cal = by.get("configured", {}), by.get("calibrated", {})
            rows.append(
                {
                    "engine": engine,
                    "n_runs": int((cal or conf).get("n_runs") or 0),
                    "variants": {
                        v: {
                            "gain": _num(r.get("gain_sim")),
                            "ratio": _num(r.get("gain_ratio")),
                            "error": _num(r.get("gain_error")),
                            "low": _num(r.get("gain_error_low")),
                            "high": _num(r.get("gain_error_high")),
                            "min": _num(r.get("gain_error_min")),
                            "max": _num(r.get("gain_error_max")),
                            "within": r.get("within_tolerance") in (True, "True", 1, 1.0),
                            "multiplier": _num(r.get("separation_multiplier")),
                        }
                        for v, r in (("configured", conf), ("calibrated", cal))
                        if r
                    },
                    "parameters": _parameters(cal.get("parameters", ""), "") if cal else [],
                }
            )
        first = g.iloc[0]
        out.append(
            {
                "terrain_class": cls,
                "pooled": cls == TARGET_POOL,
                "gain_real": _num(first.gain_real),
                "multiplier_real": _num(first.separation_multiplier_real),
                "rows": rows,
            }
        )
    return out


def target_summary(target: pd.DataFrame | None) -> dict[str, Any] | None:
    """The turning target as the summary judged it (simpick.studies.calibration.turning.target_table): the best
    calibrated engine, whether it meets the target, and every calibrated model's figures."""
    if target is None or target.empty:
        return None
    rows = target.to_dict("records")
    for r in rows:
        for key in (
            "error_calibrated",
            "error_configured",
            "error_reference",
            "vs_configured",
            "p_vs_configured",
            "vs_reference",
            "p_vs_reference",
            "worst_gain_ratio",
        ):
            r[key] = _num(r.get(key))
        for key in ("meets", "best", "is_engine", "lower_than_configured", "lower_than_reference"):
            r[key] = r.get(key) in (True, "True", 1, 1.0)
        r["classes_off_gain"] = "" if pd.isna(r.get("classes_off_gain")) else str(r.get("classes_off_gain"))
    best = next((r for r in rows if r["best"]), None)
    meeting = [r["engine"] for r in rows if r["meets"] and r["is_engine"]]
    return {"rows": rows, "best": best, "meeting": meeting}


def calibration_section(
    summary: pd.DataFrame | None,
    engines: list[str],
    colors: dict[str, str],
    turning: pd.DataFrame | None = None,
    target: pd.DataFrame | None = None,
) -> dict[str, Any]:
    """Per class and model: parameters found, train and test objective (as configured and as
    calibrated, intervals from statistics.min_runs runs on), the change and its paired verdict,
    and the ranking before and after (none below min_runs); per class the test-set winner as the
    summary judged it, and whether it changes."""
    if summary is None or summary.empty:
        return {"given": False}
    order = {e: i for i, e in enumerate(engines)}
    summary = summary.assign(_o=summary.engine.map(lambda e: order.get(e, len(order))))
    classes = []
    groups = dict(list(summary.sort_values(["terrain_class", "_o"]).groupby("terrain_class", sort=True)))
    # the classes in name order, then every class pooled (calibration.summarise)
    for cls in sorted(groups, key=lambda c: (c == POOLED, c)):
        g = groups[cls]
        rows = []
        for engine, ge in g.groupby("engine", sort=False):
            by_set = {r["set"]: r for r in ge.to_dict("records")}
            train, test = by_set.get("train", {}), by_set.get("test", {})
            rows.append(
                {
                    "engine": engine,
                    "parameters": (test or train).get("parameters", ""),
                    "configured": (test or train).get("parameters_configured", ""),
                    "params": _parameters(
                        (test or train).get("parameters", ""), (test or train).get("parameters_configured", "")
                    ),
                    "n_train": train.get("n_runs"),
                    "n_test": test.get("n_runs"),
                    "train": {v: _cell(train, "objective", v) for v in ("configured", "calibrated")} if train else None,
                    "test": {v: _cell(test, "objective", v) for v in ("configured", "calibrated")} if test else None,
                    "test_yaw": {v: _cell(test, "error_yaw_rate", v) for v in ("configured", "calibrated")}
                    if test
                    else None,
                    "change": _cell(
                        {
                            "change_x": test.get("change"),
                            "change_x_low": test.get("change_low"),
                            "change_x_high": test.get("change_high"),
                        },
                        "change",
                        "x",
                    )
                    if test
                    else None,
                    "change_verdict": test.get("change_verdict") if test else None,
                    "rank_configured": _rank(test.get("rank_configured")),
                    "rank_calibrated": _rank(test.get("rank_calibrated")),
                    "failed": int((test.get("n_failed_configured") or 0) + (test.get("n_failed_calibrated") or 0)),
                }
            )
        # the winner as the summary judged it (simpick.studies.calibration.summary._winners): a model's name only
        # where a paired test over at least statistics.min_runs runs separates it from the runner-up
        test = g[g.set == "test"]
        winner = {
            v: (str(test[f"winner_{v}"].iloc[0]) if len(test) and f"winner_{v}" in test else None)
            for v in ("configured", "calibrated")
        }
        named = {v: w for v, w in winner.items() if w and w in set(g.engine)}
        classes.append(
            {
                "terrain_class": cls,
                "pooled": cls == POOLED,
                "rows": rows,
                "winner": winner,
                "winner_changes": len(named) == 2 and named["configured"] != named["calibrated"],
                "winner_named": len(named) == 2,
            }
        )
    return {
        "given": True,
        "classes": classes,
        "turning": turning_rows(turning, engines),
        "target": target_summary(target),
    }
