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
evaluation) beside the optimum's, and keeps the tuned settings where the optimum is not below it. Kinds drive and
replay fit the same per-run residuals, each run (a DRIVE step is one) a steady turn from rest at its own
representative command on its own class's ground against its own real gain (:func:`representative_units`,
:func:`run_units`): not a replay of every window, which costs more than these fits are given.

Per class, where a class has a training run that turns, its own ratio is fitted the same way on its runs (the
other settings at the pooled fit's), beside the pooled fit, and both are judged on its held-out runs.
The split is the calibration's (:func:`simpick.studies.calibration.split.split_runs`: by run, seeded,
stratified by turning): nothing of a test run reaches the fit.

The modules, one idea each: ``space`` (the search space: its models, :func:`~.space.load_search_spaces`,
:func:`~.space.resolve`), ``params`` (:class:`~.params.CalibrateParams`, what rule simulator_calibrate's job
reads), ``runs`` (the real runs: the split of rule simulator_split, the training runs' turning units and real
gains, the representative units), ``fit`` (the least-squares machinery: :class:`~.fit.Axis`,
:class:`~.fit.Units`, :func:`~.fit.least_squares_fit` by scipy or mujoco.sysid, the intervals, the step
margins), ``units`` (what an evaluation runs on the engine: the segments replayed, or steady-turn cases) and
``job`` (rule simulator_calibrate's job: :func:`~.job.calibrate`, each part's share, the classes' own fits).
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
from simpick.studies.simulator_calibration.units import run_units, segment_units

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
    "run_units",
    "segment_units",
    "split_job",
    "step_margins",
    "steps_key",
    "with_calibrated",
]
