"""Figures of simulated traces over time and in the plane: IMU time series per engine, and the
paths driven against the commanded one (:func:`commanded_path`, the ideal path of a constant
command), which show what the tables' numbers summarise."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.report.figures.base import (
    QUANTITY_COLUMNS,
    WIDTH_IN,
    _plt,
    save,
)


def timeseries_figure(series: Sequence[tuple[str, str, pd.DataFrame]], path: str | Path) -> Path:
    """ax, ay, az (left) and wx, wy, wz (right) against time, engines overlaid."""
    plt = _plt()
    fig, axs = plt.subplots(3, 2, figsize=(WIDTH_IN, 3.9), sharex=True)
    for col, quantity in enumerate(("linear", "angular")):
        unit = "m/s²" if quantity == "linear" else "rad/s"
        for row, column in enumerate(QUANTITY_COLUMNS[quantity]):
            ax = axs[row, col]
            for label, color, frame in series:
                ax.plot(
                    frame["time"].to_numpy(), frame[column].to_numpy(), color=color, lw=0.6, alpha=0.85, label=label
                )
            ax.set_ylabel(f"{column} ({unit})")
            if row == 2:
                ax.set_xlabel("time (s)")
    axs[0, 0].set_title("IMU linear acceleration (specific force)")
    axs[0, 1].set_title("IMU angular velocity")
    handles, labels = axs[0, 0].get_legend_handles_labels()
    if handles:
        fig.legend(
            handles, labels, loc="upper center", ncol=min(len(labels), 5), frameon=False, bbox_to_anchor=(0.5, 1.03)
        )
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    return save(fig, path)


def commanded_path(start: Sequence[float], v: float, w: float, duration: float, dt: float = 0.01) -> np.ndarray:
    """Unicycle path of the open-loop command (no slip): x, y columns."""
    t = np.arange(0.0, duration + dt / 2, dt)
    x0, y0, yaw0 = (float(s) for s in start)
    yaw = yaw0 + w * t
    if abs(w) < 1e-12:
        x = x0 + v * t * math.cos(yaw0)
        y = y0 + v * t * math.sin(yaw0)
    else:
        x = x0 + v / w * (np.sin(yaw) - math.sin(yaw0))
        y = y0 - v / w * (np.cos(yaw) - math.cos(yaw0))
    return np.column_stack([x, y])


def paths_figure(panels: Sequence[dict], path: str | Path, ncols: int = 2) -> Path:
    """Top-down x-y paths, one panel per test.

    Each panel: ``title``, ``series`` [(label, colour, frame)], optional ``strip``
    (x0, x1, y0, y1) and ``commanded`` (N x 2 array).
    """
    plt = _plt()
    n = max(1, len(panels))
    ncols = min(ncols, n)
    nrows = math.ceil(n / ncols)
    fig, axs = plt.subplots(nrows, ncols, figsize=(WIDTH_IN, 2.35 * nrows + 0.4), squeeze=False)
    legend = {}
    for ax, panel in zip(axs.flat, panels):
        strip = panel.get("strip")
        if strip is not None:
            x0, x1, y0, y1 = strip
            r = plt.Rectangle(
                (x0, y0),
                x1 - x0,
                y1 - y0,
                facecolor="#d9c9a3",
                alpha=0.45,
                edgecolor="#a08850",
                lw=0.6,
                label="terrain strip",
            )
            ax.add_patch(r)
            legend.setdefault("terrain strip", r)
        cmd = panel.get("commanded")
        if cmd is not None:
            (h,) = ax.plot(cmd[:, 0], cmd[:, 1], color="0.35", ls="--", lw=0.8, label="commanded (no slip)")
            legend.setdefault("commanded (no slip)", h)
        for label, color, frame in panel["series"]:
            (h,) = ax.plot(frame["x"].to_numpy(), frame["y"].to_numpy(), color=color, lw=1.0, label=label)
            ax.plot(frame["x"].iloc[-1], frame["y"].iloc[-1], "o", color=color, ms=2.5)
            legend.setdefault(label, h)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(panel["title"])
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    for ax in list(axs.flat)[len(panels) :]:
        ax.set_visible(False)
    if legend:
        fig.legend(
            list(legend.values()),
            list(legend.keys()),
            loc="upper center",
            ncol=min(len(legend), 5),
            frameon=False,
            bbox_to_anchor=(0.5, 1.0),
        )
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.35 / (2.35 * nrows + 0.4)))
    return save(fig, path)
