"""Figures of the engines against the real robot's logs: the yaw-rate gain per command, and a
replayed log's IMU signals beside the real ones (raw and smoothed, on limits the smoothed signals
set so that the real vibration does not flatten the comparison)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.report.figures.base import (
    WIDTH_IN,
    _plt,
    save,
)

REAL_LABEL = "real robot"
REAL_COLOR = "#222222"


def gain_figure(panels: Sequence[dict], path: str | Path) -> Path:
    """Yaw-rate gain per terrain class: the real robot against each engine.

    Each panel: ``title``, ``classes`` (x labels) and ``bars``, a list of
    {label, color, real (bool), mean, low, high} with one value per class; the error bars
    run from low to high where both are finite.
    """
    plt = _plt()
    n = max(1, len(panels))
    fig, axs = plt.subplots(n, 1, figsize=(WIDTH_IN, 2.25 * n + 0.35), squeeze=False)
    handles = {}
    for ax, panel in zip(axs[:, 0], panels):
        classes = list(panel["classes"])
        bars = list(panel["bars"])
        x = np.arange(len(classes))
        k = max(1, len(bars))
        width = 0.8 / k
        for i, b in enumerate(bars):
            mean = np.array([np.nan if v is None else float(v) for v in b["mean"]])
            low = np.array([np.nan if v is None else float(v) for v in b["low"]])
            high = np.array([np.nan if v is None else float(v) for v in b["high"]])
            pos = x - 0.4 + width * (i + 0.5)
            real = bool(b.get("real"))
            h = ax.bar(
                pos,
                np.nan_to_num(mean),
                width=width * 0.92,
                color=b["color"],
                alpha=0.35 if real else 0.85,
                hatch="////" if real else None,
                edgecolor=b["color"],
                linewidth=0.6,
                label=b["label"],
            )
            handles.setdefault(b["label"], h)
            has = np.isfinite(low) & np.isfinite(high) & np.isfinite(mean)
            if has.any():
                ax.errorbar(
                    pos[has],
                    mean[has],
                    yerr=[mean[has] - low[has], high[has] - mean[has]],
                    fmt="none",
                    ecolor="0.15",
                    elinewidth=0.8,
                    capsize=2,
                )
            for p, m, hi in zip(pos, mean, high):
                top = hi if np.isfinite(hi) else m
                ax.annotate(
                    f"{m:.2f}" if np.isfinite(m) else "n/a",
                    (p, max(top, 0) if np.isfinite(top) else 0),
                    xytext=(0, 1.5),
                    textcoords="offset points",
                    ha="center",
                    va="bottom",
                    fontsize=5.5,
                    rotation=90 if k * len(classes) > 18 else 0,
                )
        ax.axhline(1.0, color="0.4", ls=":", lw=0.8)
        ax.axhline(0.0, color="0.3", lw=0.6)
        ax.set_xticks(x, [c.replace("_", " ") for c in classes])
        ax.set_ylabel("yaw-rate gain")
        ax.set_title(panel["title"])
        ax.grid(axis="x", visible=False)
        top = max(
            [1.05]
            + [
                float(v)
                for b in bars
                for v in list(b["high"]) + list(b["mean"])
                if v is not None and np.isfinite(float(v))
            ]
        )
        ax.set_ylim(min(0.0, ax.get_ylim()[0]), top * 1.22)
    fig.legend(
        list(handles.values()),
        list(handles.keys()),
        loc="upper center",
        ncol=min(len(handles), 5),
        frameon=False,
        bbox_to_anchor=(0.5, 1.0),
    )
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.3 / (2.25 * n + 0.35)))
    return save(fig, path)


def _limits(values: Sequence[np.ndarray], smooth: Sequence[np.ndarray]) -> tuple[float, float]:
    """y limits that show every low-passed curve and most of the raw ones (1st-99th percentile)."""
    lo, hi = [], []
    for v in values:
        v = v[np.isfinite(v)]
        if v.size:
            lo.append(np.percentile(v, 1))
            hi.append(np.percentile(v, 99))
    for v in smooth:
        v = v[np.isfinite(v)]
        if v.size:
            lo.append(v.min())
            hi.append(v.max())
    if not lo:
        return -1.0, 1.0
    a, b = float(min(lo)), float(max(hi))
    pad = 0.08 * (b - a if b > a else 1.0)
    return a - pad, b + pad


def replay_figure(
    series: Sequence[tuple[str, str, pd.DataFrame]],
    psd: Sequence[tuple[str, str, np.ndarray, np.ndarray]],
    commanded: pd.DataFrame | None,
    rate_hz: float,
    path: str | Path,
    t_max: float | None = None,
    band: tuple[float, float] | None = None,
    cutoff_hz: float = 2.0,
) -> Path:
    """One terrain class of the full replay.

    Left: yaw rate (top) and longitudinal acceleration (bottom) of one run against time,
    each signal raw (faint) and low-passed at ``cutoff_hz`` (zero-phase Butterworth, the
    filter of simpick.compare.realmetrics); ``commanded`` (time, w) is the kinematic yaw rate of the
    recorded wheel commands. Right: Welch PSD of vertical acceleration, ``psd`` as
    (label, colour, f, power), with ``band`` shaded (the band of the PSD distance).
    ``series``: (label, colour, frame with time, wz, ax); the real robot first.
    """
    from simpick.compare.realmetrics import lowpass

    plt = _plt()
    fig = plt.figure(figsize=(WIDTH_IN, 3.1))
    gs = fig.add_gridspec(2, 3, width_ratios=(1.0, 1.0, 0.95), wspace=0.45, hspace=0.18)
    ax_w = fig.add_subplot(gs[0, :2])
    ax_a = fig.add_subplot(gs[1, :2], sharex=ax_w)
    ax_p = fig.add_subplot(gs[:, 2])
    handles = {}
    for ax, column, unit in ((ax_w, "wz", "rad/s"), (ax_a, "ax", "m/s²")):
        raws, smooths = [], []
        for label, color, frame in series:
            sel = frame if t_max is None else frame[frame["time"] <= t_max]
            t = sel["time"].to_numpy()
            y = sel[column].to_numpy(dtype=float)
            if len(y) < 2:
                continue
            ys = lowpass(y, rate_hz, cutoff_hz)
            real = label == REAL_LABEL
            ax.plot(t, y, color=color, lw=0.35, alpha=0.22)
            (h,) = ax.plot(
                t, ys, color=color, lw=1.3 if real else 0.9, alpha=0.95, label=label, zorder=3 if real else 2
            )
            handles.setdefault(label, h)
            raws.append(y)
            smooths.append(ys)
        if column == "wz" and commanded is not None and len(commanded):
            sel = commanded if t_max is None else commanded[commanded["time"] <= t_max]
            (h,) = ax.step(
                sel["time"].to_numpy(),
                sel["w"].to_numpy(),
                where="post",
                color="0.45",
                ls="--",
                lw=0.8,
                label="command (no slip)",
            )
            handles.setdefault("command (no slip)", h)
            smooths.append(sel["w"].to_numpy(dtype=float))
        ax.set_ylim(*_limits(raws, smooths))
        ax.set_ylabel(f"{column} ({unit})")
    ax_w.set_title(f"yaw rate and forward acceleration: raw (faint), low-passed at {cutoff_hz:g} Hz")
    plt.setp(ax_w.get_xticklabels(), visible=False)
    ax_a.set_xlabel("time (s)")
    if band is not None:
        ax_p.axvspan(band[0], band[1], color="0.92", zorder=0)
    for label, color, f, p in psd:
        keep = f > 0
        (h,) = ax_p.loglog(
            f[keep], np.maximum(p[keep], 1e-12), color=color, lw=1.3 if label == REAL_LABEL else 0.9, label=label
        )
        handles.setdefault(label, h)
    ax_p.set_xlabel("frequency (Hz)")
    ax_p.set_ylabel("PSD of az ((m/s²)²/Hz)")
    ax_p.set_title("vertical acceleration spectrum")
    fig.legend(
        list(handles.values()),
        list(handles.keys()),
        loc="upper center",
        ncol=min(len(handles), 5),
        frameon=False,
        bbox_to_anchor=(0.5, 1.05),
    )
    return save(fig, path)
