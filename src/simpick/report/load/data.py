"""The report's inputs once read: :class:`ReportData` (every table, record and figure file the
report and the figure jobs draw from, absent ones None or empty) and :class:`Trace`.

A plain record apart from the reading code, so that the modules that format the report depend on
the shape of the data only."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import pandas as pd


@dataclass
class Trace:
    engine: str
    terrain: str
    motion: str
    frame: pd.DataFrame
    meta: dict
    path: str


@dataclass
class ReportData:
    weighted: pd.DataFrame
    runs: pd.DataFrame
    contributions: pd.DataFrame | None = None  # the weighted table cell by cell (results/scores/contributions.csv)
    drivers: pd.DataFrame | None = None  # what puts the leader ahead of each engine (results/scores/drivers.csv)
    trace_stats: pd.DataFrame | None = None
    reference_stats: pd.DataFrame | None = None
    imu_errors: pd.DataFrame | None = None
    per_test_errors: pd.DataFrame | None = None
    rtf: pd.DataFrame | None = None
    cpu: list[dict] | None = None
    qualitative: dict | None = None
    table11: pd.DataFrame | None = None
    table11_comparison: pd.DataFrame | None = None
    worked_example: dict | None = None
    traces: list[Trace] | None = None
    # what the scores rest on (results/scores/provenance.yaml), the Eq. 7 totals it names and,
    # for real data, the per-test table beside them
    scores_provenance: dict | None = None
    accuracy_errors: pd.DataFrame | None = None
    accuracy_per_test: pd.DataFrame | None = None
    # engines against analytic mechanics (rules/validate.smk)
    validation: pd.DataFrame | None = None
    validation_gains: pd.DataFrame | None = None  # per engine, gain left / right over start headings
    # speed-accuracy sweep (rules/sweep.smk), when the study ran with one
    sweep: pd.DataFrame | None = None
    # calibration on training runs, judged on test runs (rules/calibration.smk), when run
    calibration: pd.DataFrame | None = None
    calibration_turning: pd.DataFrame | None = None  # held-out yaw-rate gains
    calibration_target: pd.DataFrame | None = None  # the turning target, per calibrated model
    # real robot data: the committed segment table, and per set ("segments", "replay") its tables
    segments: pd.DataFrame | None = None
    segments_provenance: dict | None = None
    real: dict[str, dict[str, pd.DataFrame]] = field(default_factory=dict)
    replay_per_window: pd.DataFrame | None = None
    real_turning: pd.DataFrame | None = None  # how the real robot turns (rule real_turning), per class
    # simpick's verdict (results/verdict/: simpick.score.verdict), table name -> table, and its headline
    verdict: dict[str, pd.DataFrame] = field(default_factory=dict)
    verdict_headline: dict | None = None
    verdict_sentences: dict | None = None  # answer.yaml: one sentence per user need
    tree: dict | None = None  # the decision tree (results/verdict/tree.json: simpick.score.tree)
    # real canonical logs and replay traces: paths only, read when the figures are drawn
    real_logs: list[str] | None = None
    replay_traces: list[str] | None = None
    # the figure rules' files (rules/report.smk): key (path under figures/, no suffix) -> PNG,
    # and the notes some of them write beside the PNG (key -> the JSON's mapping)
    figures: dict[str, str] = field(default_factory=dict)
    figure_notes: dict[str, dict] = field(default_factory=dict)
    endpoints: pd.DataFrame | None = None
    sources: dict[str, Any] = field(default_factory=dict)
