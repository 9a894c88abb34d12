"""Each simulator calibrated on real runs within the settings its users can set: the calibrated profile.

The search space is data (``resources/simulators/calibration.yaml``): per simulator, the adapter settings that
move the robot's steady turning, each with the simulator's own name for it, its bounds and its source: the
wheels' lateral/longitudinal friction ratio wherever the simulator exposes two friction
directions (Gazebo's ``<mu2>`` with ``<fdir1>``, Webots' two ``coulombFriction`` values, a MuJoCo pair's two
tangential frictions), and beside it what else the simulator's user sets that may move it (Gazebo Classic's
and Webots' force-dependent slip, MuJoCo's wheel servo gain; Gazebo's wheels' slip2 at a required slip1, listed
before its ratio, which only switches DART's turn where the slips grade it); a simulator with isotropic friction
only has none, says why, and its calibrated row is its tuned profile.

The fit (:func:`calibrate`) fits what the table judges. On the committed segments (kind ``segments``) the
objective is the held-out figure's own metric over the training runs: the training runs' turning segments (the
target classes', calibration.target.classes) are replayed on the engine as the calibrated profile's segments
simulate job replays them (simpick.simulate.real.prepare_segment, its params, the trial's settings merged over
them), each simulated gain taken as the comparison takes it (simpick.compare.real.segment_row, in the segment's
compared window), and the per-run gain residuals (engine - real) minimised by bounded least squares from the tuned
profile (:func:`least_squares_fit`), over each setting's range mapped to [0, 1]. The search space names the
optimizer: MuJoCo's profile is fitted by MuJoCo's own system identification (mujoco.sysid.optimize, its optimizer
"mujoco": mujoco.minimize.least_squares, with mujoco.minimize's finite-difference Jacobian), every other
simulator's by scipy.optimize.least_squares (trf, a forward-difference Jacobian); both get the same residuals and
the same budget of evaluations, and the file names the one that ran (its version, iterations and evaluations).
Each setting gets a 95 % interval from the Jacobian at the optimum (mujoco.sysid's from its calculate_intervals),
or is named unidentifiable from these runs; the file gives the tuned profile's training error (the first
evaluation) beside the optimum's, and keeps the tuned settings where the optimum is not below it. Kinds replay and
drive fit the same per-run residuals on what their own held-out tables replay: the full replay's training runs each
replayed from rest as its replay simulate job replays it up to the end of its first turning window of the held-out
comparison's grid, that window's gain taken as the comparison takes it (:func:`~.units.window_units`), and DRIVE's
training steps (up to ``drive_commands``, stratified by |w|) each replayed from its warm-up as DRIVE's replay does
(:func:`~.units.step_units`). The cap keeps an evaluation near the cost of the steady turns these kinds ran before.

Per class, where a class has a training run that turns, every setting the pooled fit fitted is fitted again on its
runs (in the pooled order, as many as its runs identify, the rest at the pooled fit's values, from the pooled
fit), beside the pooled fit, and both are judged on its held-out runs; the class's entry carries its ``settings``
and their intervals.
The split is the calibration's (:func:`simpick.studies.calibration.split.split_runs`: by run, seeded,
stratified by turning): nothing of a test run reaches the fit.

The modules, one idea each: ``space`` (the search space: its models, :func:`~.space.load_search_spaces`,
:func:`~.space.resolve`), ``params`` (:class:`~.params.CalibrateParams`, what rule simulator_calibrate's job
reads), ``runs`` (the real runs: the split of rule simulator_split, the training runs' turning units and real
gains, the full replay's turning windows, DRIVE's representative steps), ``fit`` (the least-squares machinery:
:class:`~.fit.Axis`, :class:`~.fit.Units`, :func:`~.fit.least_squares_fit` by scipy or mujoco.sysid, the
intervals, the step margins), ``units`` (what an evaluation runs on the engine: segments, full-replay windows or
DRIVE steps replayed) and ``job`` (rule simulator_calibrate's job: :func:`~.job.calibrate`, each part's share,
the classes' own fits).
"""

from __future__ import annotations

from simpick.score.split import read_split

# what a calibrated profile's simulate and validate jobs use, in a module of its own (they import nothing else)
from simpick.simulate.calibrated import read_calibrated, with_calibrated
from simpick.studies.simulator_calibration.fit import Axis, Units, least_squares_fit, step_margins
from simpick.studies.simulator_calibration.job import calibrate, part_shares
from simpick.studies.simulator_calibration.params import CalibrateParams
from simpick.studies.simulator_calibration.runs import (
    SPLIT_COLUMNS,
    real_gains,
    real_turns,
    representative_units,
    split_job,
    steps_key,
    turning_windows,
)
from simpick.studies.simulator_calibration.space import (
    CALIBRATED,
    Required,
    SearchSetting,
    SearchSpace,
    SearchSpaceError,
    load_search_spaces,
    resolve,
)
from simpick.studies.simulator_calibration.units import segment_units, step_units, window_units

__all__ = [
    "CALIBRATED",
    "SPLIT_COLUMNS",
    "Axis",
    "CalibrateParams",
    "Required",
    "SearchSetting",
    "SearchSpace",
    "SearchSpaceError",
    "Units",
    "calibrate",
    "least_squares_fit",
    "load_search_spaces",
    "part_shares",
    "read_calibrated",
    "read_split",
    "real_gains",
    "real_turns",
    "representative_units",
    "resolve",
    "segment_units",
    "split_job",
    "step_margins",
    "turning_windows",
    "step_units",
    "steps_key",
    "window_units",
    "with_calibrated",
]
