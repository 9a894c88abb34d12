"""The report's calibration section (results/calibration/<source>/summary.csv, rules/calibration.smk)."""

from __future__ import annotations

import math
from typing import Any

import pandas as pd

from simpick.calibration import POOLED


def _cell(row, fig: str, variant: str) -> dict:
    def get(key):
        value = row.get(key)
        return None if value is None or (isinstance(value, float) and math.isnan(value)) else float(value)

    return {"mean": get(f"{fig}_{variant}"), "low": get(f"{fig}_{variant}_low"),
            "high": get(f"{fig}_{variant}_high")}


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


def calibration_section(summary: pd.DataFrame | None, engines: list[str], colors: dict[str, str]) -> dict[str, Any]:
    """Per class and model: parameters found, train and test objective (as configured and as
    calibrated, 95 % bootstrap intervals where there are enough units), the change, and the
    ranking before and after; per class whether the test-set winner changes."""
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
            rows.append({
                "engine": engine, "parameters": (test or train).get("parameters", ""),
                "configured": (test or train).get("parameters_configured", ""),
                "params": _parameters((test or train).get("parameters", ""),
                                      (test or train).get("parameters_configured", "")),
                "n_train": train.get("n_runs"), "n_test": test.get("n_runs"),
                "train": {v: _cell(train, "objective", v) for v in ("configured", "calibrated")} if train else None,
                "test": {v: _cell(test, "objective", v) for v in ("configured", "calibrated")} if test else None,
                "test_yaw": {v: _cell(test, "error_yaw_rate", v) for v in ("configured", "calibrated")} if test else None,
                "change": _cell({"change_x": test.get("change"), "change_x_low": test.get("change_low"),
                                 "change_x_high": test.get("change_high")}, "change", "x") if test else None,
                "rank_configured": test.get("rank_configured"), "rank_calibrated": test.get("rank_calibrated"),
                "failed": int((test.get("n_failed_configured") or 0) + (test.get("n_failed_calibrated") or 0)),
            })
        test = g[g.set == "test"]
        winner = {v: (test.sort_values(f"objective_{v}").engine.iloc[0] if len(test) and
                      test[f"objective_{v}"].notna().any() else None) for v in ("configured", "calibrated")}
        classes.append({"terrain_class": cls, "pooled": cls == POOLED, "rows": rows, "winner": winner,
                        "winner_changes": winner["configured"] != winner["calibrated"]})
    return {"given": True, "classes": classes}
