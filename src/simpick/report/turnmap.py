"""The turn-map figure: how the real robot's yaw-rate gain varies across DRIVE's command space, per
terrain, beside the Coulomb reference and each engine at the same commands (:mod:`simpick.studies.turnmap`)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from simpick.report.figures import REFERENCE_COLOR, WIDTH_IN, _plt, engine_colors, nothing_to_draw, save

VARIABLES = {  # binned variable -> panel title (the commanded value; x: its bins)
    "v_cmd": "|forward speed| (m/s)",
    "cmd_turn_radius": "turn radius (m; spin: 0)",
    "cmd_wheel_speed_difference": "|rim-speed difference| (m/s)",
}
COULOMB_COLOR = "#7f7f7f"


def turnmap_figure(table: pd.DataFrame, path: str | Path) -> Path:
    """One panel per terrain (rows) and binned variable (columns). In each, per bin (x: the bin, labelled by
    its edges): the real gain's median with its interquartile range as a bar (and the bin's step count),
    the Coulomb gain at the bin's representative command, and each engine's gain there (an engine with no
    finite gain on a terrain is named in the panel as not shown, with its status)."""
    if table.empty:
        return nothing_to_draw(path, "no turning DRIVE step: no gain to map")
    plt = _plt()
    terrains = sorted(table.terrain_class.unique())
    variables = [v for v in VARIABLES if v in set(table.variable)]
    engines = sorted(e for e in table.engine.dropna().unique() if e)
    colors = engine_colors(engines)
    fig, axes = plt.subplots(
        len(terrains),
        len(variables),
        figsize=(WIDTH_IN, 1.9 * len(terrains) + 0.5),
        squeeze=False,
        sharey=True,
    )
    width = 0.8 / (len(engines) + 2)
    for i, terrain in enumerate(terrains):
        for j, variable in enumerate(variables):
            ax = axes[i][j]
            rows = table[(table.terrain_class == terrain) & (table.variable == variable)]
            grid = rows.drop_duplicates(["bin"]).sort_values("value")
            x = np.arange(len(grid))
            ax.errorbar(
                x,
                grid.gain_median,
                yerr=[grid.gain_median - grid.gain_q25, grid.gain_q75 - grid.gain_median],
                fmt="o",
                color=REFERENCE_COLOR,
                ms=3.5,
                capsize=2,
                lw=1,
                label="real (median, IQR)",
            )
            for k, (n, y) in enumerate(zip(grid.steps, grid.gain_q75)):
                ax.annotate(f"{n}", (x[k], y), textcoords="offset points", xytext=(0, 2), ha="center", fontsize=5.5)
            ax.plot(x + width, grid.coulomb_gain, "s", color=COULOMB_COLOR, ms=3, label="Coulomb")
            missing = []
            for m, engine in enumerate(engines):
                e = rows[rows.engine == engine].set_index("bin").reindex(grid.bin)
                gains = e.engine_gain.to_numpy(float)
                if not np.isfinite(gains).any():
                    status = ", ".join(sorted(set(e.status.dropna().astype(str)) - {""})) or "no run"
                    missing.append(f"{engine}: {status}")
                    continue
                ax.plot(x + (m + 2) * width, gains, "^", color=colors[engine], ms=3, label=engine)
            if missing:
                ax.text(0.02, 0.02, "not shown: " + "; ".join(missing), transform=ax.transAxes, fontsize=5, va="bottom")
            ax.set_xticks(x + width * (len(engines) + 1) / 2)
            ax.set_xticklabels(grid.bin, rotation=30, ha="right", fontsize=5.5)
            if i == 0:
                ax.set_title(VARIABLES[variable], fontsize=7)
            if j == 0:
                ax.set_ylabel(f"{terrain}\nyaw-rate gain")
    handles, labels = [], []
    for ax in np.ravel(axes):
        for h, label in zip(*ax.get_legend_handles_labels()):
            if label not in labels:
                handles.append(h)
                labels.append(label)
    fig.suptitle("Yaw-rate gain against the command (bins of the commanded value; number: real steps)", fontsize=8)
    fig.legend(
        handles, labels, loc="lower center", ncol=min(len(labels), 6), frameon=False, bbox_to_anchor=(0.5, -0.02)
    )
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    out = save(fig, path)
    plt.close(fig)
    return out


def figure_job(table_csv, output) -> Path:
    """Rule turnmap_figure: the figure from the combined table (simpick.studies.turnmap's table_job)."""
    return turnmap_figure(pd.read_csv(table_csv, keep_default_na=False, na_values=[""]), output)
