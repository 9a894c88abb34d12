"""What the report expects of each table it reads: the columns it must have, which are text and
which are bool, and the real-data and verdict tables it looks for.

The stages' own column lists are the source where they exist; this module is the one place a
reader checks a table against, so a renamed column fails at load time with the file named
rather than deep in a template."""

from __future__ import annotations

from simpick.compare.real import REPLAY_TEST_COLUMNS, SEGMENT_TEST_COLUMNS, WINDOW_COLUMNS
from simpick.compare.rows import DETAIL_COLUMNS
from simpick.real.segments import COLUMNS as SEGMENT_COLUMNS
from simpick.score.answer import ANSWER_COLUMNS
from simpick.score.contributions import CONTRIBUTION_COLUMNS, DRIVER_COLUMNS
from simpick.score.equivalence import OUTCOME_COLUMNS
from simpick.score.scoring import METRICS
from simpick.score.verdict.headings import HEADING_COLUMNS
from simpick.score.verdict.paper import DISCRIMINATION_COLUMNS, RANKING_COLUMNS
from simpick.score.verdict.runs import SEPARATION_COLUMNS, TABLE_COLUMNS
from simpick.studies.calibration.turning import TARGET_COLUMNS, TURNING_COLUMNS
from simpick.studies.validation.judge import GAIN_COLUMNS

# the first page's row per engine: every column but the per-metric ones, which the report reads from outcomes,
# and the failed runs, which reach the page in the answer's sentences (answer.yaml), not from these tables
FAILED_COLUMNS = ("runs_completed", "runs_failed", "runs_all", "failed_runs")
ANSWER_REQUIRED = tuple(
    c
    for c in ANSWER_COLUMNS
    if not c.endswith(("_outcome", "_diff", "_low", "_high", "_margin")) and c not in FAILED_COLUMNS
)

# A table whose writer names its columns in a constant must have all of them (the writer's list, imported: one
# definition); the others list the columns the report reads. Not imported: the sweep's SUMMARY_COLUMNS
# (simpick.studies.sweep would bring the simulation code into the report's and every figure's code version).
COLUMNS: dict[str, tuple[str, ...]] = {
    "weighted": (*METRICS, "total", "excluded", "rank"),
    "runs": (
        "engine",
        "terrain",
        "motion",
        "sim_time",
        "wall_time",
        "cpu_time",
        "steps",
        "steps_per_s",
        "real_time_factor",
        "status",
        "reasons",
    ),
    "trace_stats": ("engine", "terrain", "motion", "quantity", "axis", "mean", "range", "status"),
    "reference_stats": ("terrain", "motion", "quantity", "axis", "mean", "range", "source"),
    "imu_errors": ("engine", "quantity", "error", "unit", "n_tests", "tests", "excluded"),
    "per_test_errors": ("engine", "terrain", "motion", "quantity", "axis", "range_error", "mean_error", "total_error"),
    "detail": tuple(DETAIL_COLUMNS),
    "rtf": ("engine", "sim_time", "wall_time", "real_time_factor", "n_runs"),
    "table11": (*METRICS, "total", "total_from_published_scores", "published_total"),
    "table11_comparison": ("simulator", "metric", "published", "recomputed", "difference", "matches"),
    "sweep": (
        "terrain_class",
        "engine",
        "timestep",
        "n_segments",
        "n_failed",
        "n_compared",
        "excluded",
        "error_angular",
        "error_linear",
        "gain_error",
        "real_time_factor",
        "steps_per_s",
    ),
    "calibration": (
        "terrain_class",
        "engine",
        "set",
        "n_units",
        "n_runs",
        "objective_configured",
        "objective_calibrated",
        "change",
        "parameters",
        "rank_configured",
        "rank_calibrated",
    ),
    "calibration_turning": tuple(TURNING_COLUMNS),
    "calibration_target": tuple(TARGET_COLUMNS),
    "validation": (
        "engine",
        "case",
        "kind",
        "quantity",
        "unit",
        "engine_value",
        "analytic_value",
        "error",
        "error_kind",
        "tolerance",
        "passed",
        "status",
    ),
    "validation_gains": tuple(GAIN_COLUMNS),
    # real robot data (rules/real.smk, simpick.compare.real)
    "accuracy_errors": ("engine", "quantity", "error", "unit", "n_tests", "tests", "excluded"),
    "accuracy_per_test": ("engine", "terrain_class", "segment", "run", "status"),
    "segments": tuple(SEGMENT_COLUMNS),
    "segments_per_test": tuple(SEGMENT_TEST_COLUMNS),
    "segments_summary": ("engine", "terrain_class", "n_tests"),
    "segments_pairwise": (
        "terrain_class",
        "figure",
        "engine_a",
        "engine_b",
        "mean_a_minus_b",
        "low",
        "high",
        "verdict",
    ),
    "segments_imu_errors": ("engine", "quantity", "error", "unit", "n_tests", "tests", "excluded"),
    "replay_per_window": tuple(WINDOW_COLUMNS),
    "replay_per_test": tuple(REPLAY_TEST_COLUMNS),
    "replay_summary": ("engine", "terrain_class", "n_tests"),
    "replay_pairwise": ("terrain_class", "figure", "engine_a", "engine_b", "mean_a_minus_b", "low", "high", "verdict"),
    "replay_imu_errors": ("engine", "quantity", "error", "unit", "n_tests", "tests", "excluded"),
    # simpick's verdict (simpick.score.verdict): the report prints these, it computes none of them
    "verdict_table": tuple(TABLE_COLUMNS),
    "verdict_separation": tuple(SEPARATION_COLUMNS),
    "verdict_ranking": tuple(RANKING_COLUMNS),
    "verdict_discrimination": tuple(DISCRIMINATION_COLUMNS),
    "verdict_metrics": ("run", "model", "metric", "value"),
    # the paper's weighted table cell by cell (simpick.score.contributions)
    "contributions": tuple(CONTRIBUTION_COLUMNS),
    # what puts the leader ahead of each engine, metric by metric (simpick.score.contributions.drivers)
    "drivers": tuple(DRIVER_COLUMNS),
    # the answer: every engine against the best per real-data metric, and the first page's row per engine
    # note: free text, optional
    "verdict_outcomes": tuple(c for c in OUTCOME_COLUMNS if c != "note" and c not in FAILED_COLUMNS),
    "verdict_answer": ANSWER_REQUIRED,
    "verdict_headings": tuple(HEADING_COLUMNS),
    # where each lab run ended against the command (rule figure_paths, beside its figure)
    "endpoints": ("engine", "terrain", "motion", "t", "dist", "dyaw_deg", "v_cmd", "w_cmd", "v_mean", "w_mean"),
}

# The real-data sets: one per way of comparing with the real robot (simpick.compare.real).
REAL_SETS: tuple[str, ...] = ("segments", "replay")
REAL_TABLES: tuple[str, ...] = ("per_test", "summary", "pairwise", "imu_errors")
VERDICT_TABLES: tuple[str, ...] = (
    "metrics",
    "table",
    "separation",
    "ranking",
    "discrimination",
    "headings",
    "outcomes",
    "answer",
)

# Text columns: read as strings, an empty cell becomes "" rather than NaN.
TEXT_COLUMNS = {
    "excluded",
    "reasons",
    "tests",
    "status",
    "source",
    "engine",
    "terrain",
    "motion",
    "quantity",
    "axis",
    "unit",
    "engine_version",
    "config_hash",
    "simulator",
    "metric",
    "terrain_class",
    "segment",
    "run",
    "kind",
    "figure",
    "engine_a",
    "engine_b",
    "verdict",
    "dataset",
    "case",
    "error_kind",
    "model",
    "next",
    "note",
    "label",
    "method",
    "best",
    "second",
    "statement",
    "floor_models",
    "outcome",
    "margin_basis",
    "group",
    "mechanics",
    "mechanics_note",
    "paper_flag",
}
# Bool columns per table: True/False in the CSV, read as bool (an empty cell as False); in every table a
# summary's <figure>_closest (simpick.compare.real.class_verdicts).
BOOL_COLUMNS = {
    "contributions": {"excluded"},
    "verdict_outcomes": {"is_best", "recommendable"},
    "table11_comparison": {"matches"},
}
