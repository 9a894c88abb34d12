"""The report's first figure: per real-data metric, each engine's value on every run with its mean,
and its difference to the best engine with the interval and the practical margin; the verdict at
a glance, drawn apart because it is the one figure every reader sees."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from simpick.report.figures.base import (
    WIDTH_IN,
    _plt,
    _short,
    save,
)


def answer_figure(metrics: Sequence[dict], colors: Mapping[str, str], path: str | Path) -> Path:
    """One column per real-data metric. Top: each engine's value on every real run (dots) and its
    mean over runs (bar). Bottom: the engine's difference to the best engine with its interval,
    the practical margin shaded; an engine that fails the mechanics the metric rests on is drawn
    hollow and marked, since the verdict never recommends it.

    ``metrics``: per metric {label, unit, margin, engines: [{engine, values, mean, diff, low, high,
    outcome, recommendable, is_best}]}, engines top to bottom."""
    plt = _plt()
    shown = [m for m in metrics if m["engines"]]
    n = max((len(m["engines"]) for m in shown), default=1)
    fig, axs = plt.subplots(2, max(len(shown), 1), figsize=(WIDTH_IN, 0.14 * n * 2 + 1.0), squeeze=False)
    for col, m in enumerate(shown):
        rows = m["engines"]
        y = np.arange(len(rows))[::-1]
        top, bottom = axs[0, col], axs[1, col]
        for yi, r in zip(y, rows):
            c = colors.get(r["engine"], "#777777")
            face = c if r["recommendable"] else "none"
            vals = np.asarray([v for v in r["values"] if v is not None and math.isfinite(v)], float)
            if len(vals):
                jitter = np.linspace(-0.18, 0.18, len(vals)) if len(vals) > 1 else np.zeros(1)
                top.scatter(vals, yi + jitter, s=7, facecolors=face, edgecolors=c, linewidths=0.6, zorder=3)
            if r["mean"] is not None:
                top.plot([r["mean"]] * 2, [yi - 0.3, yi + 0.3], color=c, lw=1.6, zorder=4)
            if r["is_best"]:
                bottom.plot([0], [yi], marker="*", ms=7, color=c, zorder=4)
            elif r["diff"] is not None:
                lo = r["diff"] - r["low"] if r["low"] is not None else 0.0
                hi = r["high"] - r["diff"] if r["high"] is not None else 0.0
                bottom.errorbar(
                    [r["diff"]],
                    [yi],
                    xerr=[[lo], [hi]],
                    fmt="o",
                    ms=3.5,
                    color=c,
                    mfc=face,
                    capsize=2,
                    lw=1.0,
                    zorder=4,
                )
            bottom.text(
                1.02,
                yi,
                r["outcome"],
                transform=bottom.get_yaxis_transform(),
                va="center",
                fontsize=6,
                color="0.25" if r["recommendable"] else "#a11",
            )
        labels = [r["engine"] + ("" if r["recommendable"] else " ✗") for r in rows]
        for ax in (top, bottom):
            ax.set_yticks(y, labels)
            ax.set_ylim(-0.6, len(rows) - 0.4)
            ax.grid(axis="y", visible=False)
        if m["margin"] is not None:
            bottom.axvspan(
                -m["margin"], m["margin"], color="#2ca02c", alpha=0.15, lw=0, label=f"margin ±{_short(m['margin'])}"
            )
        bottom.axvline(0, color="0.3", lw=0.7)
        unit = f" ({m['unit']})" if m["unit"] and m["unit"] != "1" else ""
        top.set_title(f"{m['label']}{unit}")
        top.set_xlabel("per real run (dots), mean (bar)", fontsize=6.5)
        bottom.set_xlabel("difference to the best, interval", fontsize=6.5)
        if m["margin"] is not None:
            bottom.legend(loc="lower right", fontsize=6, frameon=False, handlelength=1.0)
    if not shown:
        axs[0, 0].set_axis_off()
        axs[1, 0].set_axis_off()
    fig.text(
        0.0,
        -0.01,
        "✗ / hollow: fails the analytic mechanics this metric rests on (never recommended)",
        fontsize=6,
        color="#a11",
    )
    fig.tight_layout(w_pad=4.0)
    return save(fig, path)
