"""The report's "Engines against analytic mechanics" section (results/validation/summary.csv)."""

from __future__ import annotations

from typing import Any

import pandas as pd

from simpick.report import figures
from simpick.validation import failures


@figures.cached
def _gain_figure(series: tuple, analytic: float, colors: tuple) -> str:
    """Yaw-rate gain against commanded w at v = 0.5 m/s, one line per engine, analytic line."""
    plt = figures._plt()
    fig, ax = plt.subplots(figsize=(5.2, 2.6))
    colors = dict(colors)
    for engine, points in series:
        ws, gains = zip(*points)
        ax.plot(ws, gains, "o-", color=colors.get(engine), label=engine, lw=1.2, ms=3.5)
    ax.axhline(analytic, color="black", lw=1.0, ls="--", label=f"Coulomb, quasi-static ({analytic:.3f})")
    ax.axhspan(analytic * 0.9, analytic * 1.1, color="black", alpha=0.07, lw=0, label="±10 %")
    ax.set_xlabel("commanded yaw rate w (rad/s), v = 0.5 m/s")
    ax.set_ylabel("yaw-rate gain (measured / w)")
    ax.set_ylim(0, max(1.0, max(g for _, pts in series for _, g in pts) * 1.1))
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    return figures.to_data_uri(fig)


def validation_section(summary: pd.DataFrame | None, engines: list[str], colors: dict[str, str]) -> dict[str, Any]:
    if summary is None or summary.empty:
        return {"given": False}
    order = {e: i for i, e in enumerate(engines)}
    present = sorted(summary.engine.unique(), key=lambda e: order.get(e, len(order)))
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
    gains = summary[(summary.quantity == "yaw_rate_gain") & (summary.v == 0.5)]
    mus = sorted(gains.mu.unique())
    mu = max(mus) if mus else None
    series = []
    for e in present:
        g = gains[(gains.engine == e) & (gains.mu == mu)].sort_values("w")
        if len(g):
            series.append((e, tuple(zip(g.w.round(6), g.engine_value.round(6)))))
    uri = (_gain_figure(tuple(series), float(gains[gains.mu == mu].analytic_value.iloc[0]),
                        tuple(sorted(colors.items()))) if series else None)
    failed = failures(summary)
    passed = [e for e in present if e not in failed]
    costs = summary.groupby("engine").steps_per_s.median().to_dict()
    return {"given": True, "engines": present, "rows": rows, "gain_uri": uri, "gain_mu": mu,
            "failed": failed, "passed": passed, "costs": costs, "n_cases": len(cases)}
