"""Figures of the studies: the engines' yaw-rate gain against the analytic mechanics (validation),
speed against accuracy over a swept setting (sweep), and the real robot's turning windows; each
answers one study's question, apart from the figures of the paper's method."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.report.figures.base import (
    _PALETTE,
    REFERENCE_COLOR,
    WIDTH_IN,
    _plt,
    save,
)


def validation_gain_figure(
    series: Sequence[tuple[str, Sequence[tuple[float, float, float, float]]]],
    analytic: float,
    colors: Mapping[str, str],
    path: str | Path,
) -> Path:
    """Yaw-rate gain against commanded w at v = 0.5 m/s, one line per engine (points: mean over
    the start headings, bars: min to max; w < 0: right turns), analytic line."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(5.6, 2.8))
    n = max(1, len(series))
    for i, (engine, points) in enumerate(series):
        ws, means, lows, highs = (np.asarray(c, dtype=float) for c in zip(*points))
        x = ws + (i - (n - 1) / 2) * 0.012  # engines side by side at each w
        label = engine
        for side in (ws < 0, ws > 0):  # right and left turns as two lines: no data between them
            if side.any():
                ax.errorbar(
                    x[side],
                    means[side],
                    # a mean over one heading is its min and max, to rounding: bars never below zero
                    yerr=np.clip([means[side] - lows[side], highs[side] - means[side]], 0.0, None),
                    fmt="o-",
                    color=colors.get(engine),
                    label=label,
                    lw=1.0,
                    ms=3.5,
                    capsize=2.0,
                    elinewidth=0.9,
                )
                label = None
    ax.axhline(analytic, color="black", lw=1.0, ls="--", label=f"Coulomb, quasi-static ({analytic:.3f})")
    ax.axhspan(analytic * 0.9, analytic * 1.1, color="black", alpha=0.07, lw=0, label="±10 %")
    ax.axvline(0.0, color="grey", lw=0.6)
    ax.set_xlabel("commanded yaw rate w (rad/s), v = 0.5 m/s; w < 0: right turns")
    ax.set_ylabel("yaw-rate gain (measured / w)")
    ax.set_ylim(0, max(1.0, max(p[3] for _, pts in series for p in pts) * 1.1))
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False, fontsize=7)
    return save(fig, path)


def sweep_figure(panels: Sequence[tuple[str, Sequence]], colors: Mapping[str, str], path: str | Path) -> Path:
    """Per class: mean angular error against real-time factor, one line per engine over the timesteps."""
    plt = _plt()
    n = len(panels)
    cols = min(n, 3)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.0 * cols + 1.2, 2.6 * rows), squeeze=False)
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
    return save(fig, path)


def turning_figure(windows: pd.DataFrame, path: str | Path) -> Path:
    """The real robot's yaw-rate gain per steady-command window against |speed|, turn radius and
    |wheel-speed difference|, one colour per terrain class, with the rigid-Coulomb prediction."""
    plt = _plt()
    fig, axs = plt.subplots(1, 3, figsize=(WIDTH_IN, 2.5), sharey=True)
    classes = sorted(windows["terrain_class"].unique())
    colors = {c: _PALETTE[i % len(_PALETTE)] for i, c in enumerate(classes)}
    columns = (
        ("|commanded speed| (m/s)", windows["v"].abs()),
        ("turn radius (m; 0 = spin)", windows["turn_radius"]),
        ("|v_right - v_left| (m/s)", windows["wheel_speed_difference"].abs()),
    )
    coulomb = windows["coulomb_gain"].dropna()
    for ax, (label, x) in zip(axs, columns):
        for c in classes:
            rows = windows["terrain_class"] == c
            ax.scatter(
                x[rows],
                windows.loc[rows, "yaw_rate_gain"],
                s=6,
                alpha=0.6,
                color=colors[c],
                label=c.replace("_", " "),
                linewidths=0,
            )
        if not coulomb.empty:
            ax.axhline(float(coulomb.median()), color=REFERENCE_COLOR, ls="--", lw=0.9, label="rigid Coulomb")
        ax.set_xlabel(label)
    axs[0].set_ylabel("real yaw-rate gain")
    handles, labels = axs[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", ncol=min(len(labels), 6), frameon=False, markerscale=2)
    fig.tight_layout(rect=(0, 0, 1, 0.88))
    return save(fig, path)
