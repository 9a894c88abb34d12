"""The report's "Engines against analytic mechanics" section (results/validation/summary.csv,
and the gain per turn direction and start heading, results/validation/gains.csv)."""

from __future__ import annotations

from typing import Any

import pandas as pd

from simpick.report import figures
from simpick.score.mechanics import failures


def _present(summary: pd.DataFrame, engines: list[str]) -> list[str]:
    order = {e: i for i, e in enumerate(engines)}
    return sorted(summary.engine.unique(), key=lambda e: order.get(e, len(order)))


def gain_series(gains: pd.DataFrame, engines: list[str]) -> tuple[list, float | None, float | None]:
    """The gain figure's data from the gain table: per engine, points (w, mean, min, max) at
    v = 0.5 m/s on the highest friction, w > 0 from its left turns and w < 0 from its right
    turns, min and max over the start headings; the analytic gain and that friction."""
    at = gains[gains.v == 0.5]
    mu = float(at.mu.max()) if len(at) else None
    at = at[at.mu == mu]
    series = []
    for e in _present(at, engines):
        points = []
        for r in at[at.engine == e].itertuples():
            if r.n_left:
                points.append((float(r.w), r.left_mean, r.left_min, r.left_max))
            if r.n_right:
                points.append((-float(r.w), r.right_mean, r.right_min, r.right_max))
        if points:
            series.append((e, sorted(points)))
    analytic = float(at.analytic.iloc[0]) if series else None
    return series, analytic, mu


def gain_rows(gains: pd.DataFrame | None, engines: list[str]) -> list[dict]:
    """The spread table: per (v, |w|, mu) with cases in both directions or at several headings,
    each engine's gain left and right (mean, min-max over headings) and its spread."""
    if gains is None or gains.empty:
        return []
    rows = []
    for (v, w, mu), g in gains.groupby(["v", "w", "mu"], sort=False):
        if not ((g.n_left > 0) & (g.n_right > 0)).any() and not ((g.n_left > 1) | (g.n_right > 1)).any():
            continue
        for e in _present(g, engines):
            r = g[g.engine == e].iloc[0]
            rows.append(
                {
                    "v": v,
                    "w": w,
                    "mu": mu,
                    "engine": e,
                    "analytic": r.analytic,
                    "left": (r.left_mean, r.left_min, r.left_max, int(r.n_left)),
                    "right": (r.right_mean, r.right_min, r.right_max, int(r.n_right)),
                    "spread": r.spread,
                    "headings": r.headings,
                }
            )
    return rows


def validation_headline(summary: pd.DataFrame | None, engines: list[str]) -> dict[str, Any]:
    """What the body says of the validation before its section (section 1 of the evidence, the ranking's
    mechanics column): the engines that passed every case, those that failed some (engine -> cases), the
    number of cases; without the section's tables, which take a report job most of its context time."""
    if summary is None or summary.empty:
        return {"given": False}
    present = _present(summary, engines)
    failed = failures(summary)
    return {
        "given": True,
        "engines": present,
        "failed": failed,
        "passed": [e for e in present if e not in failed],
        "n_cases": len(dict.fromkeys(summary[summary.kind != "invariance"].case)),
    }


def validation_section(
    summary: pd.DataFrame | None, engines: list[str], figure: str | None, gains: pd.DataFrame | None = None
) -> dict[str, Any]:
    """``figure``: the gain figure's file (rule figure_validation), None when not drawn;
    ``gains``: the gain table (results/validation/gains.csv), None when not given."""
    if summary is None or summary.empty:
        return {"given": False}
    headline = validation_headline(summary, engines)
    present = headline["engines"]
    rows = []
    for case in dict.fromkeys(summary.case):
        for quantity, g in summary[summary.case == case].groupby("quantity", sort=False):
            # a case some engines skip, or that hung or crashed on some: the analytic of one that ran
            ran = g[g.analytic_value.notna()]
            first = ran.iloc[0] if len(ran) else g.iloc[0]
            cells = {}
            for e in present:
                r = g[g.engine == e]
                cells[e] = (
                    {
                        "value": r.engine_value.iloc[0],
                        "error": r.error.iloc[0],
                        "passed": bool(r.passed.iloc[0]),
                        "status": r.status.iloc[0],
                    }
                    if len(r)
                    else None
                )
            rows.append(
                {
                    "case": case,
                    "quantity": quantity,
                    "unit": first.unit,
                    "analytic": first.analytic_value,
                    "tolerance": first.tolerance,
                    "error_kind": first.error_kind,
                    "cells": cells,
                }
            )
    uri = figures.data_uri(figure) if figure and gains is not None and len(gains) else None
    costs = (
        summary[~summary.kind.isin(["invariance"]) & (summary.status != "skipped")]
        .groupby("engine")
        .steps_per_s.median()
        .to_dict()
    )
    mu = float(gains[gains.v == 0.5].mu.max()) if gains is not None and (gains.v == 0.5).any() else None
    # skipped for every engine (not applicable to the robot): "case"; for some (an engine without
    # the setting a case needs, e.g. friction_ratio): "case (engines)"
    skipped = {}
    for case, gone in summary[summary.status == "skipped"].groupby("case", sort=False):
        ran = summary[(summary.case == case) & (summary.status != "skipped")]
        label = case if ran.empty else f"{case} ({', '.join(_present(gone, engines))})"
        skipped[label] = "; ".join(dict.fromkeys(gone.reasons))
    return {
        **headline,
        "rows": rows,
        "gain_uri": uri,
        "gain_mu": mu,
        "gain_rows": gain_rows(gains, engines),
        "costs": costs,
        "skipped": skipped,
    }
