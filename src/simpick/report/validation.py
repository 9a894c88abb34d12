"""The report's "Engines against analytic mechanics" section (results/validation/summary.csv)."""

from __future__ import annotations

from typing import Any

import pandas as pd

from simpick.report import figures
from simpick.validation import failures


def _present(summary: pd.DataFrame, engines: list[str]) -> list[str]:
    order = {e: i for i, e in enumerate(engines)}
    return sorted(summary.engine.unique(), key=lambda e: order.get(e, len(order)))


def gain_series(summary: pd.DataFrame, engines: list[str]) -> tuple[list, float | None, float | None]:
    """The gain figure's data: per engine (w, gain) at v = 0.5 m/s on the highest friction, the
    analytic gain, and that friction."""
    gains = summary[(summary.quantity == "yaw_rate_gain") & (summary.v == 0.5)]
    mus = sorted(gains.mu.unique())
    mu = max(mus) if mus else None
    series = []
    for e in _present(summary, engines):
        g = gains[(gains.engine == e) & (gains.mu == mu)].sort_values("w")
        if len(g):
            series.append((e, list(zip(g.w.round(6), g.engine_value.round(6)))))
    analytic = float(gains[gains.mu == mu].analytic_value.iloc[0]) if series else None
    return series, analytic, mu


def validation_section(summary: pd.DataFrame | None, engines: list[str], figure: str | None) -> dict[str, Any]:
    """``figure``: the gain figure's file (rule figure_validation), None when not drawn."""
    if summary is None or summary.empty:
        return {"given": False}
    present = _present(summary, engines)
    cases = list(dict.fromkeys(summary.case))
    rows = []
    for case in cases:
        for quantity, g in summary[summary.case == case].groupby("quantity", sort=False):
            first = g.iloc[0]
            cells = {}
            for e in present:
                r = g[g.engine == e]
                cells[e] = ({"value": r.engine_value.iloc[0], "error": r.error.iloc[0],
                             "passed": bool(r.passed.iloc[0]), "status": r.status.iloc[0]} if len(r) else None)
            rows.append({"case": case, "quantity": quantity, "unit": first.unit, "analytic": first.analytic_value,
                         "tolerance": first.tolerance, "error_kind": first.error_kind, "cells": cells})
    series, _, mu = gain_series(summary, engines)
    uri = figures.data_uri(figure) if figure and series else None
    failed = failures(summary)
    passed = [e for e in present if e not in failed]
    costs = summary.groupby("engine").steps_per_s.median().to_dict()
    gone = summary[summary.status == "skipped"].drop_duplicates("case")
    skipped = dict(zip(gone.case, gone.reasons))
    return {"given": True, "engines": present, "rows": rows, "gain_uri": uri, "gain_mu": mu,
            "failed": failed, "passed": passed, "costs": costs, "n_cases": len(cases), "skipped": skipped}
