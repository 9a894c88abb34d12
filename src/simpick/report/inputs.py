"""The report's input keys (documented in :mod:`simpick.report`): a module of their own, so that
the package and :mod:`simpick.report.load` both read them without importing each other."""

from __future__ import annotations

REQUIRED_INPUTS: tuple[str, ...] = ("weighted", "runs")
OPTIONAL_INPUTS: tuple[str, ...] = (
    "contributions",
    # the DRIVE comparison's tables and the turn map: read from their folder (params.drive) by simpick.report.steps
    "drive",
    # the DRIVE calibration's held-out multipliers (calibration.enabled): read by simpick.report.steps
    "drive_calibration",
    "turnmap",
    # the simulators' tables, read from their folder (params.simulators) by simpick.report.simulators
    "simulators",
    "drivers",
    "sweep",
    "calibration",
    "calibration_turning",
    "calibration_target",
    "trace_stats",
    "reference_stats",
    "imu_errors",
    "per_test_errors",
    "rtf",
    "cpu",
    "qualitative",
    "table11",
    "table11_comparison",
    "worked_example",
    "traces",
    "accuracy_errors",
    "accuracy_per_test",
    "scores_provenance",
    "validation",
    "validation_gains",
    "segments",
    "segments_provenance",
    "segments_per_test",
    "segments_summary",
    "segments_pairwise",
    "segments_imu_errors",
    "replay_per_window",
    "replay_per_test",
    "replay_summary",
    "replay_pairwise",
    "replay_imu_errors",
    "real_turning",
    "real_logs",
    "replay_traces",
    "figures",
    "endpoints",
    # simpick's verdict (rules/scores.smk rule verdict, simpick.score.verdict)
    "verdict_metrics",
    "verdict_table",
    "verdict_separation",
    "verdict_ranking",
    "verdict_discrimination",
    "verdict_headings",
    "verdict_headline",
    "verdict_outcomes",
    "verdict_answer",
    "verdict_sentences",
    # the decision tree (rules/tree.smk): its data for the interactive section, figures/tree.png for print
    "tree",
)
# Inputs that are lists of paths (the workflow script passes these as lists).
LIST_INPUTS: tuple[str, ...] = ("cpu", "traces", "real_logs", "replay_traces", "figures")
