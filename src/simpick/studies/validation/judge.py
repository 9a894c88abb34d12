"""The validation's cases judged: each check's error against the config's tolerance, the invariance
checks drawn from the yaw_gain cases, the gains table, and the job that writes them. Judging reads
the stored records only, so that editing a tolerance re-judges them without stepping an engine."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.errors import InputError
from simpick.studies.validation.measures import CASE_QUANTITY, DEFAULT_HEADING, QUANTITIES
from simpick.tables import write_csv


def _row(
    engine: str,
    case: str,
    kind: str,
    quantity: str,
    value: float,
    analytic: float,
    tolerances: dict,
    status: str,
    reasons: str,
    **extra,
) -> dict:
    if quantity not in tolerances:
        raise InputError(
            f"validation.tolerances.{quantity}",
            "no tolerance given",
            f"add `{quantity}: <tolerance>` under validation.tolerances in the config",
        )
    unit, measure = QUANTITIES[quantity]
    error = abs(value - analytic) / abs(analytic) if measure == "relative" else abs(value - analytic)
    passed = bool(status == "ok" and np.isfinite(error) and error <= tolerances[quantity])
    return {
        "engine": engine,
        "case": case,
        "kind": kind,
        "quantity": quantity,
        "unit": unit,
        "engine_value": value,
        "analytic_value": analytic,
        "error": error,
        "error_kind": measure,
        "tolerance": float(tolerances[quantity]),
        "passed": passed,
        "status": status,
        "reasons": reasons,
        "v": extra.get("v"),
        "w": extra.get("w"),
        "mu": extra.get("mu"),
        "heading": extra.get("heading"),
        "steps_per_s": extra.get("steps_per_s"),
        "covers": extra.get("covers", ""),
        "friction_ratio": extra.get("friction_ratio"),
    }


def _label(x: float) -> str:
    return f"{float(x):g}"


def invariance_rows(rows: list[dict], tolerances: dict) -> list[dict]:
    """The turn_asymmetry and heading_spread checks of every engine, from its yaw_rate_gain rows
    (see simpick.studies.validation). A group's check fails when any of its cases failed."""
    gains = pd.DataFrame(
        [
            r
            for r in rows
            if r["quantity"] == "yaw_rate_gain"
            and r["w"] is not None
            and r["status"] != "skipped"
            and r.get("friction_ratio") is None
        ]
    )
    if gains.empty:
        return []
    gains = gains.astype({"v": float, "w": float, "mu": float})
    gains = gains.assign(
        ratio=gains.engine_value / gains.analytic_value,
        turn=np.sign(gains.w),
        speed=gains.w.abs(),
        heading=gains.heading.fillna(DEFAULT_HEADING),
    )
    out = []

    def status(cases) -> str:
        return "ok" if (cases.status == "ok").all() else "failed"

    for (engine, v, speed, mu), g in gains.groupby(["engine", "v", "speed", "mu"], sort=False):
        name = f"v{_label(v)}_w{_label(speed)}_mu{_label(mu)}"
        both = g.groupby("heading").filter(lambda h: set(h.turn) == {-1.0, 1.0})
        if len(both):
            differences = both.groupby("heading").apply(
                lambda h: abs(h.ratio[h.turn > 0].mean() - h.ratio[h.turn < 0].mean()), include_groups=False
            )
            out.append(
                _row(
                    engine,
                    f"left_right_{name}",
                    "invariance",
                    "turn_asymmetry",
                    float(differences.max()),
                    0.0,
                    tolerances,
                    status(both),
                    "",
                    v=v,
                    w=speed,
                    mu=mu,
                    covers=" ".join(both.case),
                )
            )
        for turn, t in g.groupby("turn", sort=False):
            if t.heading.nunique() > 1:
                w = float(turn * speed)
                out.append(
                    _row(
                        engine,
                        f"headings_v{_label(v)}_w{_label(w)}_mu{_label(mu)}",
                        "invariance",
                        "heading_spread",
                        float(t.ratio.max() - t.ratio.min()),
                        0.0,
                        tolerances,
                        status(t),
                        "",
                        v=v,
                        w=w,
                        mu=mu,
                        covers=" ".join(t.case),
                    )
                )
    return out


def summarise(results: list[dict], tolerances: dict[str, float]):
    """One row per (engine, case, quantity): values, error and pass/fail under ``tolerances``;
    then the invariance checks (:func:`invariance_rows`)."""
    rows = []
    for result in results:
        if not result["checks"]:  # skipped (not applicable), or failed before it measured: one row, the reason
            quantity = CASE_QUANTITY[result["kind"]]
            rows.append(
                {
                    "engine": result["engine"],
                    "case": result["case"],
                    "kind": result["kind"],
                    "quantity": quantity,
                    "unit": QUANTITIES[quantity][0],
                    "engine_value": math.nan,
                    "analytic_value": math.nan,
                    "error": math.nan,
                    "error_kind": QUANTITIES[quantity][1],
                    "tolerance": math.nan,
                    "passed": False,
                    "status": result["status"],
                    "reasons": "; ".join(result["reasons"]),
                    "v": result["params"].get("v"),
                    "w": result["params"].get("w"),
                    "mu": result["params"].get("mu"),
                    "heading": result["params"].get("heading"),
                    "steps_per_s": None,
                    "covers": "",
                    "friction_ratio": result["params"].get("friction_ratio"),
                }
            )
            continue
        for c in result["checks"]:
            rows.append(
                _row(
                    result["engine"],
                    result["case"],
                    result["kind"],
                    c["quantity"],
                    c["engine_value"],
                    c["analytic_value"],
                    tolerances,
                    result["status"],
                    "; ".join(result["reasons"]),
                    v=c.get("v"),
                    w=c.get("w"),
                    mu=c.get("mu"),
                    heading=c.get("heading"),
                    steps_per_s=result["steps_per_s"],
                    friction_ratio=c.get("friction_ratio"),
                )
            )
    return pd.DataFrame(rows + invariance_rows(rows, tolerances))


GAIN_COLUMNS = (
    "engine",
    "v",
    "w",
    "mu",
    "analytic",
    "n_left",
    "left_mean",
    "left_min",
    "left_max",
    "n_right",
    "right_mean",
    "right_min",
    "right_max",
    "min",
    "max",
    "spread",
    "headings",
)


def gain_table(summary):
    """Per engine and (v, |w|, mu): the Coulomb gain and the engine's gain turning left (w > 0)
    and right (w < 0): mean, min and max over the start headings; over both, min, max and the
    spread max - min relative to the Coulomb gain."""
    gains = summary[(summary.quantity == "yaw_rate_gain") & summary.w.notna() & (summary.status != "skipped")]
    if "friction_ratio" in gains:  # anisotropic cases: not the isotropic turning this table compares
        gains = gains[gains.friction_ratio.isna()]
    rows = []
    if gains.empty:
        return pd.DataFrame(columns=list(GAIN_COLUMNS))
    gains = gains.assign(speed=gains.w.abs(), heading=gains.heading.fillna(DEFAULT_HEADING))
    for (engine, v, speed, mu), g in gains.groupby(["engine", "v", "speed", "mu"], sort=False):
        left, right = g[g.w > 0].engine_value, g[g.w < 0].engine_value
        analytic = float(g.analytic_value.mean())
        rows.append(
            {
                "engine": engine,
                "v": v,
                "w": speed,
                "mu": mu,
                "analytic": analytic,
                "n_left": len(left),
                "left_mean": left.mean(),
                "left_min": left.min(),
                "left_max": left.max(),
                "n_right": len(right),
                "right_mean": right.mean(),
                "right_min": right.min(),
                "right_max": right.max(),
                "min": g.engine_value.min(),
                "max": g.engine_value.max(),
                "spread": (g.engine_value.max() - g.engine_value.min()) / analytic,
                "headings": " ".join(_label(h) for h in sorted(g.heading.unique())),
            }
        )
    return pd.DataFrame(rows, columns=list(GAIN_COLUMNS))


def summarise_job(inputs: list[str], outputs: dict, tolerances: dict) -> None:
    results = [json.loads(Path(p).read_text()) for p in inputs]
    summary = summarise(results, tolerances)
    write_csv(summary, outputs["summary"])
    write_csv(gain_table(summary), outputs["gains"])
