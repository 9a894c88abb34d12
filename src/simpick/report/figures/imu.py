"""The per-test IMU statistics figure (the paper's Figures 7-8): per quantity and axis, each
engine's statistic of the IMU window beside the real robot's; the paper's own view of accuracy."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.report.figures.base import (
    AXES,
    QUANTITY_TITLES,
    REFERENCE_LABEL,
    WIDTH_IN,
    _plt,
    _short,
    save,
)


def imu_stats_figure(
    series: Sequence[tuple[str, str, pd.DataFrame]], path: str | Path, title: str | None = None
) -> Path:
    """Mean and trimmed range per axis, angular (left) and linear (right).

    ``series``: (label, colour, stats) where stats has columns quantity, axis, mean, range.
    The top row shows the means, the bottom row the ranges (Eq. 6: mean of the top 1 % of
    samples minus mean of the bottom 1 %), each bar labelled with its value. Eq. 7's error
    is the sum over axes of the gaps between an engine's bar and the reference's bar in
    both rows.
    """
    plt = _plt()
    fig, axs = plt.subplots(2, 2, figsize=(WIDTH_IN, 3.7), sharex=True)
    k = max(1, len(series))
    width = 0.8 / k
    x = np.arange(len(AXES))
    for col, quantity in enumerate(("angular", "linear")):
        for row, stat in enumerate(("mean", "range")):
            ax = axs[row, col]
            rotate = k > 2 or stat == "mean"
            for i, (label, color, stats) in enumerate(series):
                sub = stats[stats["quantity"] == quantity].set_index("axis")
                vals = np.array([float(sub.loc[a, stat]) if a in sub.index else np.nan for a in AXES])
                pos = x - 0.4 + width * (i + 0.5)
                hatch = "////" if label == REFERENCE_LABEL else None
                bars = ax.bar(
                    pos,
                    np.nan_to_num(vals),
                    width=width * 0.92,
                    color=color,
                    alpha=0.85 if hatch is None else 0.35,
                    hatch=hatch,
                    edgecolor=color,
                    linewidth=0.6,
                    label=label,
                )
                for b, v in zip(bars, vals):
                    h = b.get_height()
                    ax.annotate(
                        _short(v),
                        (b.get_x() + b.get_width() / 2, h),
                        xytext=(0, 1.5 if h >= 0 else -1.5),
                        textcoords="offset points",
                        ha="center",
                        va="bottom" if h >= 0 else "top",
                        fontsize=5.5,
                        rotation=90 if rotate else 0,
                    )
            ax.axhline(0, color="0.3", lw=0.6)
            ax.margins(y=0.35 if rotate else 0.18)
            ax.set_xticks(x, [f"{a}" for a in AXES])
            ax.grid(axis="x", visible=False)
            if row == 0:
                ax.set_title(QUANTITY_TITLES[quantity])
            ax.set_ylabel("mean" if stat == "mean" else "range (top 1 % − bottom 1 %)")
    handles, labels = axs[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", ncol=min(len(labels), 5), frameon=False, bbox_to_anchor=(0.5, 1.0))
    if title:
        fig.suptitle(title, y=1.05, fontsize=9)
    fig.tight_layout(rect=(0, 0, 1, 0.94))
    return save(fig, path)
