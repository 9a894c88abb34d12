"""What every report figure shares: the page size and resolution, the colours and labels of the
reference and the engines, Matplotlib's style, writing a PNG byte for byte reproducibly, the panel
for a figure with nothing to draw, and embedding a PNG in the HTML.

One place for these keeps every figure the same size, style and palette, whichever module draws it."""

from __future__ import annotations

import base64
import io
import math
from collections.abc import Sequence
from pathlib import Path

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
