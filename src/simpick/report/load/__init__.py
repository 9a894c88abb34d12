"""Read the report's inputs (files written by the other workflow rules) and check their columns.

Split by idea: what each table must hold (:mod:`.columns`), the record the inputs are read into
(:mod:`.data`), reading and checking one file (:mod:`.files`) and reading them all
(:mod:`.assemble`); this package re-exports their names.
"""

from simpick.report.load.assemble import load_inputs
from simpick.report.load.columns import (
    ANSWER_REQUIRED,
    BOOL_COLUMNS,
    COLUMNS,
    FAILED_COLUMNS,
    REAL_SETS,
    REAL_TABLES,
    TEXT_COLUMNS,
    VERDICT_TABLES,
)
from simpick.report.load.data import ReportData, Trace
from simpick.report.load.files import DETAIL_VIEWS, figure_key

__all__ = [
    "ANSWER_REQUIRED",
    "BOOL_COLUMNS",
    "COLUMNS",
    "DETAIL_VIEWS",
    "FAILED_COLUMNS",
    "REAL_SETS",
    "REAL_TABLES",
    "TEXT_COLUMNS",
    "VERDICT_TABLES",
    "ReportData",
    "Trace",
    "figure_key",
    "load_inputs",
]
