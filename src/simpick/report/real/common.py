"""What every real-robot part of the report shares: the names and units of the real-data sets and
figures, reading a table cell as a number, the terrain classes in the config's order, the tests
grouped by class, and the config's statistics settings.

The accuracy block, the dataset list and the real-data section read the same tables the same way;
one module for these keeps their labels and their class order identical."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from simpick.report.load import ReportData

if TYPE_CHECKING:
    from simpick.report.params import ReportRealData
    from simpick.score.settings import Statistics

SET_TITLES = {"segments": "constant-command segments", "replay": "full replay", "own": "own logs"}
SET_UNITS = {"segments": "segment", "replay": "run", "own": "log"}
ERROR_FIGURES = ("error_angular", "error_linear")
FIGURE_LABELS = {
    "error_angular": "angular velocity",
    "error_linear": "linear acceleration",
    "yaw_rate_gain": "yaw-rate gain",
}
FIGURE_UNITS = {
    "error_angular": "rad/s",
    "error_linear": "m/s²",
    "rmse_yaw_rate": "rad/s",
    "rmse_ax": "m/s²",
    "psd_distance_az": "decades",
}
# Extra columns of the full replay's summary (simpick.compare.real.FIGURES).
REPLAY_EXTRA = (
    ("rmse_yaw_rate", "RMSE yaw rate (rad/s)"),
    ("rmse_ax", "RMSE a<sub>x</sub> (m/s²)"),
    ("psd_distance_az", "PSD distance a<sub>z</sub> (decades)"),
)
REAL_TABLE_NAMES = ("per_test", "summary", "pairwise")
TIME_PLOT_MAX_S = 120.0


def _isnan(x: Any) -> bool:
    try:
        return x is None or math.isnan(float(x))
    except (TypeError, ValueError):
        return False


def _f(x: Any) -> float:
    try:
        return float(x)
    except (TypeError, ValueError):
        return float("nan")


def class_order(data: ReportData, real_data: ReportRealData) -> list[str]:
    """The terrain classes in the config's order (``real_data.classes``), then any other the tables hold."""
    order = [str(c) for c in real_data.classes]
    frames = [data.segments] + [t for s in data.real.values() for t in s.values()]
    for df in frames:
        if df is not None and "terrain_class" in df.columns:
            for c in df["terrain_class"]:
                if c and c not in order:
                    order.append(c)
    return order


def _test_classes(data: ReportData) -> dict[str, str]:
    out: dict[str, str] = {}
    if data.segments is not None:
        out.update(zip(data.segments["segment"], data.segments["terrain_class"]))
    for tables in data.real.values():
        pt = tables.get("per_test")
        if pt is not None:
            out.update(zip(pt["segment"], pt["terrain_class"]))
    return out


def group_tests(data: ReportData, tests: Sequence[str], classes: Sequence[str]) -> list[dict[str, Any]]:
    """Tests grouped by terrain class (real-data tests are named ``{class}-...``)."""
    known = _test_classes(data)
    groups: dict[str, list[str]] = {}
    for t in tests:
        cls = known.get(t) or (t.split("-", 1)[0] if "-" in t else "")
        groups.setdefault(cls, []).append(t)
    order = list(classes) + [c for c in groups if c not in classes]
    out = []
    for c in order:
        if c not in groups:
            continue
        ts = groups[c]
        short = [t[len(c) + 1 :] if c and t.startswith(c + "-") else t for t in ts]
        out.append({"cls": c, "label": c.replace("_", " ") if c else "", "tests": ts, "short": short, "n": len(ts)})
    return out


def _cell(row: Mapping[str, Any] | None, fig: str) -> dict[str, Any] | None:
    if row is None or fig not in row:
        return None
    return {"mean": _f(row.get(fig)), "low": _f(row.get(f"{fig}_low")), "high": _f(row.get(f"{fig}_high"))}


def statistics(settings: Statistics) -> dict[str, Any]:
    """The statistics settings (minimum independent runs, level) as the templates and the summaries read
    them, with the smallest p-value a group below the minimum could give."""
    from simpick.compare.realmetrics import smallest_p

    st = settings.model_dump(mode="json")
    st["smallest_p_below"] = smallest_p(settings.min_runs - 1)
    return st
