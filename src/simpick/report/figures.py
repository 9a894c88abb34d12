"""Report figures, drawn with Matplotlib (Agg) into PNG files by the figure rules
(rules/report.smk, :mod:`simpick.report.draw`); the report job embeds the files.

PNG rather than SVG: the time series and replay plots hold tens of thousands of points, which
WeasyPrint lays out slowly as SVG paths, and an SVG's text depends on the fonts of the machine
that opens it. Sizes fit an A4 page (about 180 mm of text width); 150 dpi keeps 5.5 pt bar
labels legible in the PDF while a report with a dozen traces stays a few megabytes.
"""

from __future__ import annotations

import base64
import io
import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

DPI = 150
WIDTH_IN = 7.1  # inches: A4 width less the page margins
REFERENCE_LABEL = "real robot (reference)"
REFERENCE_COLOR = "#222222"
_PALETTE = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#17becf", "#e377c2"]
AXES = ("x", "y", "z")
QUANTITY_TITLES = {"angular": "Angular velocity (rad/s)", "linear": "Linear acceleration (m/s²)"}
QUANTITY_COLUMNS = {"angular": ("wx", "wy", "wz"), "linear": ("ax", "ay", "az")}


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update(
        {
            "font.size": 7.5,
            "axes.titlesize": 8,
            "axes.labelsize": 7.5,
            "legend.fontsize": 7,
            "xtick.labelsize": 7,
            "ytick.labelsize": 7,
            "axes.spines.top": False,
            "axes.spines.right": False,
            "axes.grid": True,
            "grid.alpha": 0.3,
            "grid.linewidth": 0.5,
            "svg.fonttype": "none",
        }
    )
    return plt


def engine_colors(engines: Sequence[str]) -> dict[str, str]:
    return {e: _PALETTE[i % len(_PALETTE)] for i, e in enumerate(engines)}


def save(fig, path: str | Path, dpi: int = DPI) -> Path:
    """Write ``fig`` as a PNG (no time stamp or software tag: the same figure, the same bytes)."""
    plt = _plt()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight", pad_inches=0.05, metadata={"Software": None})
    plt.close(fig)
    tmp = path.with_name(path.name + ".partial")
    tmp.write_bytes(buf.getvalue())
    tmp.replace(path)
    return path


def nothing_to_draw(path: str | Path, why: str) -> Path:
    """A figure rule must write its file: when there is no data, a small panel that says why."""
    plt = _plt()
    fig = plt.figure(figsize=(WIDTH_IN, 0.45))
    fig.text(0.5, 0.5, f"Nothing to draw: {why}", ha="center", va="center", fontsize=8, color="0.3")
    return save(fig, path)


def data_uri(path: str | Path) -> str:
    """The report embeds each figure file, so the HTML (and the PDF made from it) stands alone."""
    return "data:image/png;base64," + base64.b64encode(Path(path).read_bytes()).decode("ascii")


def _short(x: float) -> str:
    """Compact label for a bar: 3 significant figures."""
    if x is None or not math.isfinite(x):
        return "n/a"
    if x == 0:
        return "0"
    return f"{x:.3g}".replace("e-0", "e-").replace("e+0", "e")


# --------------------------------------------------------------------------
# Per-test IMU statistics (paper Figures 7-8)
# --------------------------------------------------------------------------


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


# --------------------------------------------------------------------------
# Traces
# --------------------------------------------------------------------------


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


# --------------------------------------------------------------------------
# Real robot data
# --------------------------------------------------------------------------

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


# --------------------------------------------------------------------------
# Engines against analytic mechanics; speed against accuracy
# --------------------------------------------------------------------------


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
                    yerr=[means[side] - lows[side], highs[side] - means[side]],
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


# --------------------------------------------------------------------------
# The answer (first page): per engine the per-run values and the difference to the best
# --------------------------------------------------------------------------


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
