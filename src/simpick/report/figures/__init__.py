"""Report figures, drawn with Matplotlib (Agg) into PNG files by the figure rules
(rules/report.smk, :mod:`simpick.report.draw`); the report job embeds the files.

PNG rather than SVG: the time series and replay plots hold tens of thousands of points, which
WeasyPrint lays out slowly as SVG paths, and an SVG's text depends on the fonts of the machine
that opens it. Sizes fit an A4 page (about 180 mm of text width); 150 dpi keeps 5.5 pt bar
labels legible in the PDF while a report with a dozen traces stays a few megabytes.

The figures are split by what they show: the shared style, page size and file writing
(:mod:`.base`), the paper's IMU statistics (:mod:`.imu`), traces (:mod:`.traces`), the real
robot's logs (:mod:`.real_robot`), the studies (:mod:`.studies`) and the answer (:mod:`.answer`);
this package re-exports their names, which the draw and build modules read as ``figures.NAME``.
"""

from simpick.report.figures.answer import answer_figure
from simpick.report.figures.base import (
    _PALETTE as _PALETTE,
)
from simpick.report.figures.base import (
    AXES,
    DPI,
    QUANTITY_COLUMNS,
    QUANTITY_TITLES,
    REFERENCE_COLOR,
    REFERENCE_LABEL,
    WIDTH_IN,
    data_uri,
    engine_colors,
    nothing_to_draw,
    save,
)
from simpick.report.figures.base import (
    _plt as _plt,
)
from simpick.report.figures.base import (
    _short as _short,
)
from simpick.report.figures.imu import imu_stats_figure
from simpick.report.figures.real_robot import REAL_COLOR, REAL_LABEL, gain_figure, replay_figure
from simpick.report.figures.studies import sweep_figure, turning_figure, validation_gain_figure
from simpick.report.figures.traces import commanded_path, paths_figure, timeseries_figure

__all__ = [
    "AXES",
    "DPI",
    "QUANTITY_COLUMNS",
    "QUANTITY_TITLES",
    "REAL_COLOR",
    "REAL_LABEL",
    "REFERENCE_COLOR",
    "REFERENCE_LABEL",
    "WIDTH_IN",
    "answer_figure",
    "commanded_path",
    "data_uri",
    "engine_colors",
    "gain_figure",
    "imu_stats_figure",
    "nothing_to_draw",
    "paths_figure",
    "replay_figure",
    "save",
    "sweep_figure",
    "timeseries_figure",
    "turning_figure",
    "validation_gain_figure",
]
