"""The report's real-robot parts: which data the accuracy scores rest on, and the section
comparing every engine with the real Husky per terrain class (simpick.compare.real's tables).

Nothing here computes a statistic: the real robot's yaw-rate gain per class and its interval come
from the summarise job's table, what the accuracy scores can tell apart from the verdict rule's
(results/verdict/discrimination.csv). The figures are drawn by the figure rules
(simpick.report.draw); :func:`gain_panels` gives the yaw-rate-gain figure its data.

The real-robot parts are split by idea: what they share (:mod:`.common`), the accuracy scores'
data (:mod:`.accuracy`), the data sets and their rates (:mod:`.sets`) and the section itself
(:mod:`.section`); this package re-exports their names, which the build and draw modules read as
``real.NAME``.
"""

from simpick.report.real.accuracy import accuracy
from simpick.report.real.common import (
    ERROR_FIGURES,
    FIGURE_LABELS,
    FIGURE_UNITS,
    REAL_TABLE_NAMES,
    REPLAY_EXTRA,
    SET_TITLES,
    SET_UNITS,
    TIME_PLOT_MAX_S,
    class_order,
    group_tests,
    statistics,
)
from simpick.report.real.section import gain_panels, real_section
from simpick.report.real.sets import datasets

__all__ = [
    "ERROR_FIGURES",
    "FIGURE_LABELS",
    "FIGURE_UNITS",
    "REAL_TABLE_NAMES",
    "REPLAY_EXTRA",
    "SET_TITLES",
    "SET_UNITS",
    "TIME_PLOT_MAX_S",
    "accuracy",
    "class_order",
    "datasets",
    "gain_panels",
    "group_tests",
    "real_section",
    "statistics",
]
