"""The report's speed-accuracy section (results/sweeps/<name>/summary.csv, rules/sweep.smk)."""

from __future__ import annotations

import math
from typing import Any

import pandas as pd

from simpick.report import figures


@figures.cached
def _sweep_figure(panels: tuple, colors: tuple) -> str:
    """Per class: mean angular error against real-time factor, one line per engine over the timesteps."""
    plt = figures._plt()
    n = len(panels)
    cols = min(n, 3)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.0 * cols + 1.2, 2.6 * rows), squeeze=False)
    colors = dict(colors)
    for ax, (cls, series) in zip(axes.flat, panels):
        for engine, points in series:
            rtf, err, labels, failed = zip(*points)
            ax.plot(rtf, err, "-", color=colors.get(engine), lw=1.0, label=engine)
            for x, y, label, bad in points:
                ax.plot([x], [y], "o", ms=3.5, color=colors.get(engine), mfc="white" if bad else colors.get(engine))
                ax.annotate(label, (x, y), fontsize=5.5, xytext=(2, 2), textcoords="offset points")
        ax.set_xscale("log")
        ax.set_title(cls, fontsize=8)
        ax.set_xlabel("real-time factor (log)", fontsize=7)
        ax.set_ylabel("angular error (rad/s)", fontsize=7)
        ax.tick_params(labelsize=6)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="center right", frameon=False, fontsize=7)
    fig.tight_layout(rect=(0, 0, 1 - 1.1 / (3.0 * cols + 1.2), 1))
    return figures.to_data_uri(fig)


def sweep_section(summary: pd.DataFrame | None, engines: list[str], colors: dict[str, str]) -> dict[str, Any]:
    if summary is None or summary.empty:
        return {"given": False}
    order = {e: i for i, e in enumerate(engines)}
    summary = summary.assign(_o=summary.engine.map(lambda e: order.get(e, len(order))))
    summary = summary.sort_values(["terrain_class", "_o", "timestep"])
    panels = []
    for cls, g in summary.groupby("terrain_class", sort=True):
        series = []
        for engine, ge in g.groupby("_o", sort=True):
            pts = [(float(r.real_time_factor), float(r.error_angular), f"{r.timestep * 1000:g}", bool(r.n_failed))
                   for r in ge.itertuples() if pd.notna(r.real_time_factor) and pd.notna(r.error_angular)]
            if pts:
                series.append((ge.engine.iloc[0], tuple(pts)))
        if series:
            panels.append((cls, tuple(series)))
    timesteps = sorted({float(t) for t in summary.timestep})
    rows = []  # one per class and engine, a cell per timestep
    for (cls, _), g in summary.groupby(["terrain_class", "_o"], sort=True):
        by_dt = {float(r.timestep): r for r in g.itertuples()}
        cells = [None if dt not in by_dt else
                 {"error_angular": by_dt[dt].error_angular, "gain_error": by_dt[dt].gain_error,
                  "rtf": by_dt[dt].real_time_factor, "n_failed": int(by_dt[dt].n_failed),
                  "n_segments": int(by_dt[dt].n_segments)} for dt in timesteps]
        rows.append({"terrain_class": cls, "engine": g.engine.iloc[0], "cells": cells})
    failed = summary[summary.n_failed > 0]
    return {"given": True, "uri": _sweep_figure(tuple(panels), tuple(sorted(colors.items()))) if panels else None,
            "rows": rows, "timesteps_ms": [t * 1000 for t in timesteps],
            "failed": [f"{r.engine} {r.terrain_class} {r.timestep * 1000:g} ms ({int(r.n_failed)} of "
                       f"{int(r.n_segments)})" for r in failed.itertuples()]}
