"""The report's speed-accuracy section (results/sweeps/<name>/summary.csv, rules/sweep.smk)."""

from __future__ import annotations

from typing import Any

import pandas as pd

from simpick.report import figures


def _ordered(summary: pd.DataFrame, engines: list[str]) -> pd.DataFrame:
    order = {e: i for i, e in enumerate(engines)}
    summary = summary.assign(_o=summary.engine.map(lambda e: order.get(e, len(order))))
    return summary.sort_values(["terrain_class", "_o", "timestep"])


def sweep_panels(summary: pd.DataFrame, engines: list[str]) -> list:
    """The figure's data: per class, per engine (rtf, error, timestep label, failed) points."""
    summary = _ordered(summary, engines)
    panels = []
    for cls, g in summary.groupby("terrain_class", sort=True):
        series = []
        for _, ge in g.groupby("_o", sort=True):
            pts = [
                (float(r.real_time_factor), float(r.error_angular), f"{r.timestep * 1000:g}", bool(r.n_failed))
                for r in ge.itertuples()
                if pd.notna(r.real_time_factor) and pd.notna(r.error_angular)
            ]
            if pts:
                series.append((ge.engine.iloc[0], pts))
        if series:
            panels.append((cls, series))
    return panels


def sweep_section(summary: pd.DataFrame | None, engines: list[str], figure: str | None) -> dict[str, Any]:
    """``figure``: the sweep figure's file (rule figure_sweep), None when not drawn."""
    if summary is None or summary.empty:
        return {"given": False}
    summary = _ordered(summary, engines)
    timesteps = sorted({float(t) for t in summary.timestep})
    rows = []  # one per class and engine, a cell per timestep
    for (cls, _), g in summary.groupby(["terrain_class", "_o"], sort=True):
        by_dt = {float(r.timestep): r for r in g.itertuples()}
        cells = [
            None
            if dt not in by_dt
            else {
                "error_angular": by_dt[dt].error_angular,
                "gain_error": by_dt[dt].gain_error,
                "rtf": by_dt[dt].real_time_factor,
                "n_failed": int(by_dt[dt].n_failed),
                "n_segments": int(by_dt[dt].n_segments),
            }
            for dt in timesteps
        ]
        rows.append({"terrain_class": cls, "engine": g.engine.iloc[0], "cells": cells})
    failed = summary[summary.n_failed > 0]
    return {
        "given": True,
        "uri": figures.data_uri(figure) if figure else None,
        "rows": rows,
        "timesteps_ms": [t * 1000 for t in timesteps],
        "failed": [
            f"{r.engine} {r.terrain_class} {r.timestep * 1000:g} ms ({int(r.n_failed)} of {int(r.n_segments)})"
            for r in failed.itertuples()
        ],
    }
