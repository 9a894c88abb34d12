"""simpick's verdict: which engine reproduces the real robot best, and how sure that is.

The paper's accuracy scores (Eq. 7 sums, Eq. 8 min/E) are kept exactly as it defines them, in
the weighted table (simpick.score.scoring). On real Husky data they cannot separate engines: Eq. 7 sums
per-axis ranges and means of the raw 100 Hz IMU, and the ranges are the real robot's vibration,
which no rigid-ground model has (the no-slip kinematic formula scores as well as any engine). So
beside the paper's method this package gives simpick's verdict from figures that measure what a
mobile-robot user needs from an engine, per real run:

- ``gain_error``: |simulated - real yaw-rate gain| on the turning tests (how much the robot turns
  for a commanded turn: skid-steer slip);
- ``heading_error``: |integral over a segment or replay window of (simulated - real) gyro z| (rad):
  the heading a simulated robot gains or loses on the real one, straight or turning;
- ``speed_error``: |simulated - real forward speed|, only where a log carries a speed measured
  independently of the wheel commands. BorealTC holds IMU and wheel speeds only, and the wheel
  speeds are the replay's input: its speed error cannot be computed, and the table says so rather
  than invent a speed from them.

Every figure is averaged within a run first (segments and windows of one run are not independent)
and pooled over every real run of the source (terrain classes together: runs are independent).
Intervals are BCa over runs, from the validated ``statistics.min_runs`` runs on. Two views of the
engines: each against the best, the one a user acts on (outcomes.csv: worse, equivalent within a
practical margin, or undetermined; simpick.score.equivalence, behind the mechanics gate of
simpick.score.mechanics), and each against the next in the order of the means (table.csv: an exact
sign-flip test of paired per-run differences, with roughly how many runs would separate the two).

The paper's weighted total gets an interval too (:func:`ranking`, run by simpick.score.answer:
the weights reach it): the runs resampled with replacement (each run's tests together, every engine
alike), the Eq. 7 totals and Eq. 8 scores recomputed per draw, the rest of the total (qualitative
facts, RTF, CPU) held as measured.

The verdict is split by idea: simpick's metrics per run and what they separate (:mod:`.runs`), the
paper's method on the same runs (:mod:`.paper`), the heading diagnostic (:mod:`.headings`) and the
job that reads and writes the tables (:mod:`.job`); this package re-exports their names.
"""

from simpick.score.verdict.headings import HEADING_COLUMNS, HEADING_REFERENCE, heading_spread
from simpick.score.verdict.job import read_per_test, scored_tests, verdict_job
from simpick.score.verdict.paper import (
    DISCRIMINATION_COLUMNS,
    IMU_SCORES,
    RANKING_COLUMNS,
    paper_rows,
    ranking,
    score_discrimination,
)
from simpick.score.verdict.runs import (
    METRICS,
    NO_SPEED,
    POWER,
    SEPARATION_COLUMNS,
    TABLE_COLUMNS,
    metric_table,
    per_run_long,
    per_run_values,
    run_key,
    runs_needed,
    separation_rows,
)

__all__ = [
    "DISCRIMINATION_COLUMNS",
    "HEADING_COLUMNS",
    "HEADING_REFERENCE",
    "IMU_SCORES",
    "METRICS",
    "NO_SPEED",
    "POWER",
    "RANKING_COLUMNS",
    "SEPARATION_COLUMNS",
    "TABLE_COLUMNS",
    "heading_spread",
    "metric_table",
    "paper_rows",
    "per_run_long",
    "per_run_values",
    "ranking",
    "read_per_test",
    "run_key",
    "runs_needed",
    "score_discrimination",
    "scored_tests",
    "separation_rows",
    "verdict_job",
]
