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
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
import pandas as pd
import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from simpick.engines.base import FRICTION_RATIO
from simpick.engines.simulators import SIMULATORS
from simpick.inputs.robot.settings import RobotParams
from simpick.params import JobParams, PhysicsStep, Positive
from simpick.score.simulators import read_split

CALIBRATED = "calibrated"

# what a calibrated profile's simulate and validate jobs use, in a module of its own (they import nothing else)
from simpick.simulate.calibrated import read_calibrated, with_calibrated  # noqa: E402,F401


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class SearchSetting(_Strict):
    """One adapter setting the fit may change, as the simulator exposes it."""

    exposed_as: str = Field(description="how the simulator's user sets it, in the simulator's own names")
    bounds: tuple[float, float] = Field(description="[low, high] of the adapter's value")
    source: str = Field(description="where the simulator reads it: repository path:line, or a manual page")
    log: bool = Field(False, description="fitted over the logarithm of its value (a setting spanning decades)")
    part: Literal["contact", "actuator"] = Field(
        "contact",
        description="what it belongs to: the wheel-ground contact (friction, slip, compliance) or the wheel "
        "actuator (a servo's gain, a drive's stiffness or damping, an effort limit); the fit reports each part's "
        "share of what it gained",
    )

    @model_validator(mode="after")
    def _ordered(self):
        if not self.bounds[0] < self.bounds[1]:
            raise ValueError(f"bounds {list(self.bounds)}: low must be below high")
        if self.log and not self.bounds[0] > 0:
            raise ValueError(f"bounds {list(self.bounds)}: a log setting needs a positive low bound")
        return self


class Required(_Strict):
    """An adapter setting the fitted ones need (Webots' asymmetric friction follows the wheel)."""

    value: Any
    exposed_as: str
    source: str


class SearchSpace(_Strict):
    """A simulator's calibrated-profile search space."""

    searchable: bool = Field(description="a setting it exposes moves the steady turning")
    settings: dict[str, SearchSetting] = {}
    requires: dict[str, Required] = {}
    why_not: str | None = Field(None, description="searchable false: why, quoting the source")
    scan: Annotated[int, Field(ge=0, le=12)] = Field(
        0,
        description="the fit first evaluates the first setting at this many points over its bounds and starts "
        "from the best (0: from the tuned profile): where the engine's gain jumps with it, a local fit cannot leave "
        "the jump it starts in; the reason is given beside it",
    )
    if_unbound: str | None = Field(
        None, description="the simulator exposes the settings, but simpick's adapter binds none of them: why"
    )
    optimizer: Literal["scipy", "mujoco.sysid"] = Field(
        "scipy",
        description="what fits the settings: scipy (scipy.optimize.least_squares, trf) or mujoco.sysid (MuJoCo's "
        "own system identification, mujoco.sysid.optimize with its optimizer 'mujoco', the intervals from its "
        "calculate_intervals); the residuals, the budget and the unidentifiability checks are the same",
    )

    @model_validator(mode="after")
    def _consistent(self):
        if self.searchable and not self.settings:
            raise ValueError("searchable true needs settings: the adapter settings the fit changes")
        if not self.searchable and not self.why_not:
            raise ValueError("searchable false needs why_not: why no setting it exposes moves the turning")
        if not self.searchable and (self.settings or self.requires):
            raise ValueError("searchable false takes no settings or requires")
        return self


class SearchSpaceError(ValueError):
    """A search-space file that cannot be used: the message names the file, the entry and the fix."""


def load_search_spaces(path: str | Path) -> dict[str, SearchSpace]:
    """Read and check the search spaces: registered simulators only, each entry complete, each setting with
    its bounds and source. Which settings its adapter binds is checked by :func:`resolve`."""
    path = Path(path)
    try:
        raw = yaml.safe_load(path.read_text())
    except OSError as exc:
        raise SearchSpaceError(f"{path}: cannot be read ({exc.strerror}); simulators.calibration names it") from None
    except yaml.YAMLError as exc:
        raise SearchSpaceError(f"{path}: not valid YAML ({exc})") from None
    if not isinstance(raw, dict) or not isinstance(raw.get("simulators"), dict):
        raise SearchSpaceError(f"{path}: needs a top-level mapping 'simulators:' of simulator name -> search space")
    out = {}
    for name, entry in raw["simulators"].items():
        if name not in SIMULATORS:
            raise SearchSpaceError(
                f"{path}: simulators.{name}: not a registered simulator; registered: {sorted(SIMULATORS)}"
            )
        try:
            out[name] = SearchSpace.model_validate(entry)
        except ValidationError as exc:
            err = exc.errors()[0]
            where = ".".join(str(p) for p in err["loc"])
            raise SearchSpaceError(f"{path}: simulators.{name}{'.' + where if where else ''}: {err['msg']}") from None
    return out


def resolve(path: str | Path, name: str, space: SearchSpace | None, engine: str) -> tuple[bool, str | None]:
    """(whether the calibrated profile of simulator ``name`` has settings to fit here, why not): a setting its
    engine's settings model lacks stops the plan, unless the entry says why the adapter cannot bind it
    (``if_unbound``), in which case the profile keeps its tuned settings and says so."""
    from simpick.engines import get_engine

    if space is None:
        raise SearchSpaceError(
            f"{path}: simulators.{name}: missing; every simulator whose profiles run needs its search space "
            "(searchable: false with why_not where it exposes no turning setting)"
        )
    if not space.searchable:
        return False, space.why_not
    fields = get_engine(engine).settings_model.model_fields
    missing = [k for k in [*space.settings, *space.requires] if k not in fields]
    if missing:
        if space.if_unbound:
            return False, space.if_unbound
        raise SearchSpaceError(
            f"{path}: simulators.{name}.settings.{missing[0]}: the {engine} adapter has no such setting "
            f"(its settings: {sorted(fields)}); name an adapter setting, or say why it cannot be bound (if_unbound)"
        )
    return True, None


# --- the fit ---


class CalibrateParams(JobParams):
    """What rule simulator_calibrate's job reads."""

    simulator: str
    engine: str
    robot_name: str = Field(description="the robot's URDF <robot name>")
    source: str = Field(description="the real data fitted on (segments-<dataset>, drive-<dataset>)")
    kind: Literal["segments", "replay", "drive"] = Field(
        "segments",
        description="segments: the committed segments' runs; replay: the full replay's runs, their steady "
        "turning windows; drive: DRIVE's steps, each a unit of its own, pooled over the target classes among "
        "the steps' (all of them where none is a target)",
    )
    engine_settings: dict[str, Any] = Field(description="the simulator's tuned profile in full (the fit starts there)")
    physics: PhysicsStep
    robot: RobotParams
    searchable: bool
    why_not: str | None
    space: dict[str, Any] = Field(description="the simulator's search space (SearchSpace)")
    classes: list[str] = Field(description="the firm terrain classes pooled (calibration.target.classes)")
    grounds: dict[str, Annotated[float, Field(gt=0)]] = Field(description="terrain class -> its friction")
    segments_case: dict[str, Any] | None = Field(
        None,
        description="kind segments: the calibrated profile's segments simulate job's params over every segment "
        "(simpick.simulate.real.SegmentsUnitParams, its plan-time settings: the tuned ones); the fit replays the "
        "training runs' turning segments with them, each trial's settings merged as the job merges the fit's",
    )
    commands: list[tuple[float, float]] | None = Field(
        None,
        description="kinds drive and replay: (v m/s, w rad/s) of steady-turn cases fitted against the training "
        "runs' pooled gain on the classes' median ground; None: the training units' own (representative_units)",
    )
    duration: Positive = Field(6.0, description="s of a steady-turn case, kinds drive and replay (its second half)")
    tolerance: Positive = Field(
        0.005,
        description="gain within which a fit is said to reach the real one, and by which a class's own fit must "
        "beat the pooled one on its training runs to get a file of its own (the engine's noise)",
    )
    max_nfev: Annotated[int, Field(ge=1, le=20)] = Field(
        6,
        description="the pooled fit's evaluations of the residuals (scipy's max_nfev; mujoco.sysid's iterations are "
        "one fewer, its rejected steps held to the same count), each a replay of the training runs' turning "
        "segments; the finite-difference Jacobian adds one evaluation per setting each",
    )
    class_nfev: Annotated[int, Field(ge=0, le=12)] = Field(
        3,
        description="the same for each class's own fit (its friction_ratio alone, from the pooled fit); 0: none",
    )
    diff_step: Annotated[float, Field(gt=0, lt=0.5)] = Field(
        0.05,
        description="the Jacobian's step, as a share of each setting's range (of its logarithm's for a log "
        "setting; scipy's forward, inward at a bound, mujoco.sysid's away from the nearer bound): well above the "
        "engines' roughness (ODE's gain moves by up to 0.01 between ratios 1e-3 apart), well below the range",
    )
    noise: Positive = Field(
        0.045,
        description="gain: the real robot's run-to-run spread within a class (the committed segments' 0.045, "
        "config verdict.margins.gain_error), the residuals' standard deviation of the intervals where the runs "
        "leave no degree of freedom (as many settings as runs)",
    )
    drive_commands: Annotated[int, Field(ge=1, le=12)] = Field(
        6,
        description="kinds drive and replay: how many training units (runs, DRIVE's steps) the fit runs, each "
        "at its own command and class ground against its own real gain (the median unit by |w| of each of as "
        "many equal bins): DRIVE has some 170 training steps, a full BorealTC replay hundreds of turning windows, "
        "each a 6 s engine run",
    )


SPLIT_COLUMNS = ("terrain_class", "run", "unit", "set")


def split_job(inputs: dict, test_fraction: float, seed: int, output: str) -> None:
    """Rule simulator_split: the real runs split as the calibration splits them (by run, seeded, stratified by
    turning): the committed segments' runs (``inputs["segments"]``), or DRIVE's steps (``inputs["steps"]``),
    each step a unit of its own: DRIVE draws each step's command independently at random, so steps are
    independent runs of the robot, and its 5 sessions are too few to hold out."""
    from simpick.studies.calibration.split import split_runs
    from simpick.tables import write_csv

    if "calibration_split" in inputs:  # the full replay's runs: the calibration's own split, as it is
        split = pd.read_csv(inputs["calibration_split"], dtype={"run": str, "unit": str})
        write_csv(split, output)
        return
    if "steps" in inputs:
        steps = pd.read_csv(inputs["steps"])
        key = steps_key(steps)
        rows = list(zip(steps.terrain_class, key, key, steps.turning.astype(bool)))
    else:
        with open(inputs["segments"], newline="") as handle:
            rows = [
                [r["terrain_class"], r["run"], r["segment"], r["kind"] == "turning"] for r in csv.DictReader(handle)
            ]
    units = pd.DataFrame(rows, columns=["terrain_class", "run", "unit", "turns"]).astype({"run": str})
    write_csv(split_runs(units, test_fraction, seed), output)


def steps_key(steps: pd.DataFrame) -> pd.Series:
    """A DRIVE step's run name in the split: its case, ``<session>/<step:03d>`` (the replay's and errors' key)."""
    return steps.session.astype(str) + "/" + steps.step.astype(int).map("{:03d}".format)


def real_turns(inputs: dict, runs: list[str], classes: list[str]) -> pd.DataFrame:
    """The units of ``runs`` (``class/run``) in ``classes`` that turn under a steady command with a real steady
    gain: (terrain_class, run, gain, v, w), from the committed segments (``inputs["segments"]``) or DRIVE's
    steps (``inputs["steps"]``: the gain over the wheels' measured speeds, the command those speeds)."""
    if "windows" in inputs:  # the full replay's steady turning windows (rule real_turning)
        win = pd.read_csv(inputs["windows"], dtype={"run": str})
        win = win[win.terrain_class.isin(classes) & (win.terrain_class + "/" + win.run).isin(set(runs))]
        win = win.rename(columns={"yaw_rate_gain": "gain", "w_kinematic": "w"})
        return win[np.isfinite(pd.to_numeric(win.gain, errors="coerce"))][["terrain_class", "run", "gain", "v", "w"]]
    if "steps" not in inputs:
        seg = turning_segments(inputs["segments"], runs, classes)
        return seg.rename(columns={"yaw_rate_gain": "gain"})[["terrain_class", "run", "gain", "v", "w"]]
    steps = pd.read_csv(inputs["steps"])
    steps = steps.assign(run=steps_key(steps))
    steps = steps[steps.turning.astype(bool) & steps.terrain_class.isin(classes)]
    steps = steps[(steps.terrain_class + "/" + steps.run).isin(set(runs))]
    steps = steps.rename(columns={"v_kin": "v", "w_kin": "w"})
    return steps[np.isfinite(pd.to_numeric(steps.gain, errors="coerce"))][["terrain_class", "run", "gain", "v", "w"]]


def turning_segments(segments: str | Path, runs: list[str], classes: list[str]) -> pd.DataFrame:
    """The turning segments of ``runs`` in ``classes`` with a real steady gain."""
    seg = pd.read_csv(segments, dtype={"run": str})
    seg = seg[(seg.kind == "turning") & seg.terrain_class.isin(classes)]
    seg = seg[(seg.terrain_class + "/" + seg.run).isin(set(runs))]
    return seg[np.isfinite(pd.to_numeric(seg.yaw_rate_gain, errors="coerce"))]


def real_gains(turns: pd.DataFrame) -> pd.DataFrame:
    """Per run of ``turns`` (:func:`real_turns`): the real steady yaw-rate gain, its turning units averaged
    (terrain_class, run, gain); runs with no turning unit are left out."""
    return turns.groupby(["terrain_class", "run"], as_index=False).gain.mean()


# a failed replay (the health checks) counts as this gain residual: the fit steers away from it
FAILED_RESIDUAL = 1.0
# a setting whose column of the Jacobian moves the residuals by less than this over its whole range, or that lies
# along a direction whose singular value is below RELATIVE_SINGULAR of the largest, is unidentifiable from the runs
MIN_SENSITIVITY, RELATIVE_SINGULAR = 0.01, 0.01
# a run's gain moving by more than this within one Jacobian step is a jump of the engine's (DART's friction box
# locking, PyBullet's), not a slope: the linearised interval is then no measure of what the runs fix
JUMP = 0.2
# A fitted value this close to a step of the engine's response is no calibration: a setting whose gain jumps within
# 2 % of it (DART's friction box in gz-physics locks the Husky's turn between a <mu2>/<mu> of 0.74 and 0.78) would
# turn differently in the user's simulator for any rounding of the value, another step size or another version.
# Each fitted value is stepped by STEP_MARGIN of itself both ways; a run's gain moving by more than STEP_GAIN there
# (about seven times what the anisotropic Coulomb slope moves it, 0.7 per unit of ratio) is a step.
STEP_MARGIN, STEP_GAIN = 0.02, 0.1
Z95 = 1.959964  # a normal 95 % interval


class Axis:
    """A fitted setting as the optimiser sees it: u in [0, 1] over its bounds (over their logarithms for a log
    setting), so that one Jacobian step and one trust region suit every setting."""

    def __init__(self, name: str, setting: SearchSetting):
        self.name, self.low, self.high, self.log = name, *map(float, setting.bounds), bool(setting.log)

    def to_u(self, x: float) -> float:
        if self.log:
            return math.log(x / self.low) / math.log(self.high / self.low)
        return (x - self.low) / (self.high - self.low)

    def to_x(self, u: float) -> float:
        u = min(max(float(u), 0.0), 1.0)
        if self.log:
            return self.low * (self.high / self.low) ** u
        return self.low + u * (self.high - self.low)

    def dx_du(self, u: float) -> float:
        return self.to_x(u) * math.log(self.high / self.low) if self.log else self.high - self.low


class Units:
    """The real units a fit is judged on: per unit its run (``class/run``), its real gain, and how the engine
    gives its simulated gain for a set of adapter settings (``simulate``: settings -> gains, NaN where failed)."""

    def __init__(self, runs: list[str], real: np.ndarray, names: list[str], simulate, describe: dict):
        self.runs, self.real, self.names, self.simulate, self.describe = (
            runs,
            np.asarray(real, float),
            names,
            simulate,
            describe,
        )
        counts = pd.Series(runs).value_counts()
        # each run weighs alike (the judged figure is a mean over runs of each run's mean over its units)
        self.weights = np.array([1.0 / math.sqrt(counts[r]) for r in runs])

    def residuals(self, sims: np.ndarray) -> np.ndarray:
        r = np.where(np.isfinite(sims), sims - self.real, FAILED_RESIDUAL)
        return r * self.weights

    def error(self, sims: np.ndarray) -> float:
        """The judged figure on these units: each run's mean |simulated - real gain| over its healthy units, then
        the mean over runs (simpick.compare.realmetrics.mean_ci, as the table's held-out columns)."""
        from simpick.compare.realmetrics import mean_ci

        ok = np.isfinite(sims)
        if not ok.any():
            return math.nan
        return mean_ci(np.abs(sims - self.real)[ok], np.asarray(self.runs, object)[ok], 10**9)[0]


def least_squares_fit(
    units: Units,
    axes: list[Axis],
    base: dict,
    start: dict,
    max_nfev: int,
    diff_step: float,
    noise: float,
    scan: int = 0,
    optimizer: str = "scipy",
):
    """Bounded least squares of the units' per-run gain residuals over the ``axes`` settings, the others ``base``,
    from ``start``, by ``optimizer`` (:data:`OPTIMIZERS`): scipy.optimize.least_squares (trf), or MuJoCo's own
    system identification (mujoco.sysid.optimize, its optimizer "mujoco"), both in the axes' u coordinates with
    ``max_nfev`` evaluations of the residuals and a finite-difference Jacobian of ``diff_step`` of each setting's
    range (scipy's forward, inward at a bound; mujoco.sysid's mujoco.minimize.jacobian_fd, away from the nearer
    bound), every evaluation cached and recorded. A setting whose column of the Jacobian at the start moves the
    residuals by less than MIN_SENSITIVITY over its whole range is not fitted (kept at its start: these runs cannot
    tell its values apart). Returns a dict: the optimum's settings, its gains and error, the first evaluation's
    (the start), the evaluations, the optimizer's report, and per setting its 95 % interval from the Jacobian at
    the optimum, or why it has none: scipy's covariance (J^T J)^-1 s^2 with a normal quantile,
    mujoco.sysid.calculate_intervals' (Student's t over the residuals' degrees of freedom) mapped from u to the
    setting's units; s^2 the residual variance, or ``noise`` squared (a normal quantile) where the runs leave no
    degree of freedom. ``scan``: first the first setting at as many points evenly over its bounds, the optimizer
    then starting from the one of the lowest sum of squares (the start included): an engine whose gain jumps with
    it (PyBullet's), where a local fit from the tuned value stays in the jump it starts in."""
    if optimizer not in OPTIMIZERS:
        raise ValueError(f"unknown optimizer {optimizer!r}; known: {sorted(OPTIMIZERS)}")
    evaluations: list[tuple[dict, np.ndarray]] = []
    cache: dict[tuple, np.ndarray] = {}
    u_start = {a.name: min(max(a.to_u(start[a.name]), 1e-6), 1 - 1e-6) for a in axes}

    def sims(at: dict) -> np.ndarray:
        """The units' simulated gains with the settings at ``at`` (name -> u; the others at the start)."""
        u = {**u_start, **at}
        key = tuple(round(float(u[a.name]), 6) for a in axes)
        if key not in cache:
            x = {a.name: a.to_x(u[a.name]) for a in axes}
            cache[key] = np.asarray(units.simulate({**base, **x}), float)
            evaluations.append((x, cache[key]))
        return cache[key]

    def residuals(active: list[Axis], points) -> np.ndarray:
        """The residuals at each column of ``points`` (the ``active`` settings' u), a column each."""
        columns = np.asarray(points, float).reshape(len(active), -1).T
        return np.stack([units.residuals(sims({a.name: v for a, v in zip(active, c)})) for c in columns], axis=1)

    def jacobian(active: list[Axis], u) -> np.ndarray:
        u = np.asarray(u, float).ravel()
        r0 = residuals(active, u)
        if optimizer == "mujoco.sysid":  # the finite differences mujoco.minimize.least_squares itself takes
            from mujoco import minimize

            box = [np.zeros((len(active), 1)), np.ones((len(active), 1))]
            point = u.reshape(-1, 1)
            return minimize.jacobian_fd(lambda p: residuals(active, p), point, r0, np.float64(diff_step), 0, box)[0]
        out = np.empty((r0.shape[0], len(active)))
        for j in range(len(active)):
            step = diff_step if u[j] + diff_step <= 1.0 else -diff_step
            v = u.copy()
            v[j] += step
            out[:, j] = (residuals(active, v)[:, 0] - r0[:, 0]) / step
        return out

    first = sims({})
    if scan:
        lead = axes[0].name
        points = [u_start[lead], *np.linspace(1e-6, 1 - 1e-6, scan)]
        best = min(points, key=lambda v: float(np.sum(units.residuals(sims({lead: v})) ** 2)))
        u_start[lead] = float(best)
    start_sensitivity = np.linalg.norm(jacobian(axes, [u_start[a.name] for a in axes]), axis=0)
    unidentifiable = {
        a.name: f"the gain moves {s:.4f} over its whole range at the start; kept at its start"
        for a, s in zip(axes, start_sensitivity)
        if s < MIN_SENSITIVITY
    }
    active = [a for a in axes if a.name not in unidentifiable]
    if not active:  # nothing moves the gain at the start: the first is fitted all the same (judged at the optimum)
        active = axes[:1]
        unidentifiable.pop(active[0].name)
    u0 = np.array([u_start[a.name] for a in active])
    u, J, report = OPTIMIZERS[optimizer](
        lambda p: residuals(active, p), lambda v: jacobian(active, v), u0, [a.name for a in active], max_nfev
    )
    u = np.clip(np.asarray(u, float), 0.0, 1.0)
    optimum = {**u_start, **{a.name: float(v) for a, v in zip(active, u)}}
    at = sims(optimum)
    r = residuals(active, u)[:, 0]
    m, n = J.shape
    dof = m - n
    s2 = float(r @ r) / dof if dof > 0 else noise**2
    sensitivity = np.linalg.norm(J, axis=0)
    if n > m:
        unidentifiable.update({a.name: "more settings than runs" for a in active[m:]})
    for a, s, column in zip(active, sensitivity, J.T):
        if s < MIN_SENSITIVITY:
            unidentifiable.setdefault(a.name, f"the gain moves {s:.4f} over its whole range at the optimum")
        jump = float(np.max(np.abs(column)) * diff_step)
        if jump > JUMP:
            unidentifiable.setdefault(
                a.name,
                f"a run's gain jumps by {jump:.3f} within the Jacobian's step at the optimum (a step, not a slope)",
            )
    scaled = J / np.where(sensitivity > 0, sensitivity, 1.0)
    _, singular, vt = np.linalg.svd(scaled, full_matrices=False)
    for k, sv in enumerate(singular):
        if sv < RELATIVE_SINGULAR * singular[0]:
            for a, load in zip(active, vt[k]):
                if abs(load) > 0.5:
                    unidentifiable.setdefault(a.name, "its column is near-collinear with another's")
    bounds_of = _sysid_intervals if optimizer == "mujoco.sysid" else _normal_intervals
    intervals, intervals_from = bounds_of(active, u, J, r, dof, noise)
    parameters = {}
    column = {a.name: j for j, a in enumerate(active)}
    for a, s0 in zip(axes, start_sensitivity):
        x = a.to_x(optimum[a.name])
        j = column.get(a.name)
        entry = {
            "value": _r(x),
            "bounds": [a.low, a.high],
            "log": a.log,
            "sensitivity": _r(float(sensitivity[j] if j is not None else s0)),
        }
        if j is not None and a.name not in unidentifiable and not all(map(math.isfinite, intervals[j][1:])):
            unidentifiable[a.name] = "its interval is unbounded (J^T J singular along it)"
        if a.name in unidentifiable:
            entry.update(identifiable=False, why=f"unidentifiable from these runs: {unidentifiable[a.name]}")
        else:
            sd, low, high = intervals[j]
            entry.update(identifiable=True, sd=_r(sd), interval=[_r(low), _r(high)])
        if optimum[a.name] <= 1e-3 or optimum[a.name] >= 1 - 1e-3:
            entry["at_bound"] = "low" if optimum[a.name] <= 1e-3 else "high"
        parameters[a.name] = entry
    return {
        "settings": {a.name: a.to_x(optimum[a.name]) for a in axes},
        "gains": at,
        "error": units.error(at),
        "start_gains": first,
        "start_error": units.error(first),
        "evaluations": evaluations,
        "parameters": parameters,
        "intervals_from": intervals_from,
        "fitted": [a.name for a in active],
        "residual_sd": math.sqrt(s2),
        "residual_sd_from": f"the residuals ({dof} degrees of freedom)"
        if dof > 0
        else f"no degree of freedom ({m} runs, {n} settings): the real robot's run-to-run spread {noise}",
        "report": {**report, "engine_evaluations": len(evaluations)},
    }


def _scipy_least_squares(residuals, jacobian, u0: np.ndarray, names: list[str], max_nfev: int):
    """scipy.optimize.least_squares (trf) over u in [0, 1]: (the optimum, the Jacobian there, its report)."""
    import scipy
    from scipy.optimize import least_squares

    result = least_squares(
        lambda u: residuals(u)[:, 0],
        u0,
        jac=jacobian,
        bounds=(0.0, 1.0),
        method="trf",
        max_nfev=max_nfev,
        x_scale=1.0,
        xtol=0.01,
        ftol=1e-3,
    )
    u = np.clip(result.x, 0.0, 1.0)
    report = {
        "name": "scipy.optimize.least_squares",
        "method": "trf, bounded",
        "version": scipy.__version__,
        # trf takes a new Jacobian after each accepted step, the first at the start
        "iterations": max(int(result.njev or 1) - 1, 0),
        "evaluations": int(result.nfev),
        "jacobians": int(result.njev or 0),
        "status": int(result.status),
        "message": str(result.message),
    }
    return u, jacobian(u), report


# mujoco.minimize.least_squares' regularizer (its Levenberg-Marquardt mu, added to J^T J over u): from the J^T J
# diagonal of the least sensitive setting the fit keeps (MIN_SENSITIVITY squared), a decade per rejected step
# (Marquardt's factor). MuJoCo's defaults, 1e-6 and 10^0.1, damp a step at all (mu a tenth of J^T J: 0.2 for the
# Husky's ratio, its column 1.5) only after some 50 rejected steps, each an evaluation that replays every training
# segment.
SYSID_MU = {"mu_min": MIN_SENSITIVITY**2, "mu_factor": 10.0}


def _sysid_least_squares(residuals, jacobian, u0: np.ndarray, names: list[str], max_nfev: int):
    """MuJoCo's own system identification over u in [0, 1]: mujoco.sysid.optimize with its optimizer "mujoco"
    (mujoco.minimize.least_squares: Gauss-Newton steps in the box, a Levenberg-Marquardt regularizer, Armijo's
    test), a mujoco.sysid ParameterDict of the settings (nominal the start), the residuals' Jacobian from
    mujoco.minimize.jacobian_fd: (the optimum, the optimizer's own Jacobian there, its report).

    Its iterations are bounded by ``max_iters``, its evaluations are not (each rejected step evaluates again):
    ``max_nfev`` bounds them as it bounds scipy's, ``max_nfev - 1`` iterations of one evaluation each after the
    start's. Once they are spent, a further step's residuals are infinite without an engine run, which the
    optimizer's Armijo test rejects until it stops at its last accepted point (its own "insufficient reduction")."""
    import io

    import mujoco
    from mujoco import sysid

    if not hasattr(sysid, "optimize"):  # mujoco.sysid imports nothing where one of the extra's packages is missing
        raise ImportError(
            "mujoco.sysid cannot be imported without its optional packages (absl-py, colorama, tabulate, ...): "
            "install simpick's dependencies, which include mujoco[sysid] (pip install -c constraints.txt -e .)"
        )
    m = residuals(u0).shape[0]
    spent = {"evaluations": 0, "refused": 0, "jacobians": 0}

    def residual_fn(x, params):  # mujoco.sysid's signature: the settings are x itself, in ``names``' order
        points = np.asarray(x, float).reshape(len(u0), -1)
        if spent["evaluations"] + points.shape[1] > max_nfev:
            spent["refused"] += points.shape[1]
            out = np.full((m, points.shape[1]), np.inf)
        else:
            spent["evaluations"] += points.shape[1]
            out = residuals(points)
        return [out if np.ndim(x) > 1 else out[:, 0]], [], []

    params = sysid.ParameterDict(
        {name: sysid.Parameter(name, nominal=float(v), min_value=0.0, max_value=1.0) for name, v in zip(names, u0)}
    )
    trace = io.StringIO()

    def jac(x, r):  # mujoco.minimize.jacobian_fd's, outside the budget: a Jacobian is one per iteration
        spent["jacobians"] += 1
        return jacobian(x[:, 0])

    fitted, result = sysid.optimize(
        params,
        residual_fn,
        optimizer="mujoco",
        verbose=False,
        max_iters=max(max_nfev - 1, 0),
        jacobian=jac,
        xtol=0.01,
        output=trace,
        **SYSID_MU,
    )
    u = np.array([float(fitted[name].value.item()) for name in names])
    lines = [line for line in trace.getvalue().splitlines() if line.startswith("Terminated")]
    message = lines[-1] if lines else ""
    if spent["refused"]:
        message += f" (its {max_nfev} evaluations spent: {spent['refused']} more refused without an engine run)"
    J = np.asarray(result.jac, float) if result.jac is not None else jacobian(u)
    report = {
        "name": "mujoco.sysid.optimize",
        "method": "optimizer 'mujoco': mujoco.minimize.least_squares, bounded",
        "version": mujoco.__version__,
        # the optimizer's log: one entry per accepted step, and the end point's
        "iterations": len(result.extras.get("objective", [None])) - 1,
        "evaluations": spent["evaluations"],
        "jacobians": spent["jacobians"],
        "message": message,
    }
    return u, J, report


OPTIMIZERS = {"scipy": _scipy_least_squares, "mujoco.sysid": _sysid_least_squares}


def _normal_intervals(active: list[Axis], u: np.ndarray, J: np.ndarray, r: np.ndarray, dof: int, noise: float):
    """Per active setting (sd, low, high) in its units: the covariance (J^T J)^-1 s^2 over the settings' units,
    a normal 95 % interval about the optimum clipped to the bounds (the linearisation does not know them)."""
    s2 = float(r @ r) / dof if dof > 0 else noise**2
    Jx = J / np.array([a.dx_du(v) for a, v in zip(active, u)])
    cov = np.linalg.pinv(Jx.T @ Jx) * s2
    out = []
    for j, (a, v) in enumerate(zip(active, u)):
        x, sd = a.to_x(v), math.sqrt(max(float(cov[j, j]), 0.0))
        out.append((sd, max(x - Z95 * sd, a.low), min(x + Z95 * sd, a.high)))
    source = "the residuals" if dof > 0 else f"the real robot's run-to-run spread {noise} (no degree of freedom)"
    return out, f"the Jacobian at the optimum: (J^T J)^-1 s^2, s^2 from {source}; 95 % normal, clipped to the bounds"


def _sysid_intervals(active: list[Axis], u: np.ndarray, J: np.ndarray, r: np.ndarray, dof: int, noise: float):
    """Per active setting (sd, low, high) in its units: mujoco.sysid.calculate_intervals at the optimum (95 %, its
    half-widths over u: Student's t over the residuals' degrees of freedom, s^2 from the residuals), u +- the
    half-width mapped to the setting's units (over the logarithm for a log setting) and clipped to the bounds.
    Without a degree of freedom it has no s^2: the real robot's spread ``noise`` stands for it, a normal quantile."""
    if dof > 0:
        from mujoco import sysid

        sigma, half = sysid.calculate_intervals([r], J, alpha=0.05)
        source = f"mujoco.sysid.calculate_intervals at the optimum: 95 %, Student's t with {dof} degrees of freedom"
    else:
        sigma = np.linalg.pinv(J.T @ J) * noise**2
        half = Z95 * np.sqrt(np.maximum(np.diag(sigma), 0.0))
        source = f"the Jacobian at the optimum, s the real robot's run-to-run spread {noise} (no degree of freedom): "
        source += "95 % normal"
    out = []
    for j, (a, v) in enumerate(zip(active, u)):
        sd = math.sqrt(max(float(sigma[j, j]), 0.0)) * a.dx_du(v)
        h = float(half[j])
        out.append((sd, a.to_x(v - h), a.to_x(v + h)) if math.isfinite(h) else (sd, math.nan, math.nan))
    return out, source + "; u +- the half-width in each setting's units, clipped to the bounds"


def step_margins(units: Units, base: dict, settings: dict, gains: np.ndarray, axes: list[Axis], fitted) -> dict:
    """Per fitted setting, the units' gains with it STEP_MARGIN of its value lower and higher (within its bounds),
    the others at the optimum ``settings``: the largest change of a unit's gain from the optimum's ``gains`` and
    whether that is a step (more than STEP_GAIN): two engine evaluations a setting."""
    out = {}
    for a in axes:
        if a.name not in fitted:
            continue
        x = float(settings[a.name])
        probes = sorted(
            {min(max(x * (1 - STEP_MARGIN), a.low), a.high), min(max(x * (1 + STEP_MARGIN), a.low), a.high)}
        )
        moved = []
        for value in probes:
            if value == x:
                continue
            at = np.asarray(units.simulate({**base, **settings, a.name: value}), float)
            both = np.isfinite(at) & np.isfinite(gains)
            # a run that fails on one side of the value and not the other is a step too
            moved.append(float(np.max(np.abs(at[both] - gains[both]))) if both.all() else math.inf)
        largest = max(moved) if moved else 0.0
        out[a.name] = {
            "probed": [_r(v) for v in probes],
            "largest_gain_change": _r(largest) if math.isfinite(largest) else "a run failed",
            "step": bool(largest > STEP_GAIN),
        }
    return out


def segment_units(p: CalibrateParams, inputs: dict, runs: list[str], classes: list[str]) -> Units:
    """The turning segments of ``runs`` in ``classes`` (the committed table), each replayed as the calibrated
    profile's segments simulate job replays it (simpick.simulate.real.prepare_segment with the job's params, the
    trial's settings merged over them as simpick.simulate.calibrated merges the fit's) and its simulated gain
    taken as the comparison takes it (simpick.compare.real.segment_row, in the segment's compared window)."""
    from simpick.compare.real import segment_row
    from simpick.simulate.real import prepare_segment, table_segment

    seg = turning_segments(inputs["segments"], runs, classes)
    names = list(seg.segment)
    rows = [table_segment(inputs["segments"], name) for name in names]
    track = p.robot.track

    def simulate(settings: dict) -> np.ndarray:
        params = dict(p.segments_case)  # the fit's settings over the job's, as with_calibrated merges a fit's
        params["engine_settings"] = {**dict(params["engine_settings"]), **settings}
        out = []
        for name, row in zip(names, rows):
            _, run = prepare_segment(inputs["urdf"], inputs, params, name)
            frame, meta = run()
            compared = segment_row(pd.DataFrame(frame), meta, row, track)
            out.append(float(compared.get("yaw_rate_gain_sim", math.nan)) if compared["status"] == "ok" else math.nan)
        return np.array(out)

    describe = {"segments": names, "window": "each segment's compared window in full (settle, then its duration)"}
    return Units(
        [f"{c}/{r}" for c, r in zip(seg.terrain_class, seg.run)],
        seg.yaw_rate_gain.to_numpy(float),
        names,
        simulate,
        describe,
    )


def steady_units(p: CalibrateParams, robot, commands, mu: float, real: float, runs: list[str]) -> Units:
    """Kinds drive and replay: the engine's steady turn from rest at each of ``commands`` on flat ground of
    friction ``mu`` (the validation's steady-turn case), each against the training units' real gain ``real``:
    a unit per command (not a replay of the runs: a DRIVE step or a full replay's window per evaluation costs
    more than these kinds' fits are given)."""
    from simpick.studies.validation.cases import Setup, run_case

    def simulate(settings: dict) -> np.ndarray:
        setup = Setup(
            engine=p.engine,
            robot=robot,
            timestep=p.physics.timestep,
            max_wheel_torque=p.robot.max_wheel_torque,
            track=p.robot.track,
            settings={**p.engine_settings, **settings},
        )
        ratio = float(settings.get("friction_ratio", p.engine_settings.get("friction_ratio", 1.0)))
        return np.array([_engine_gain(run_case, setup, ratio, v, w, mu, p.duration) for v, w in commands])

    describe = {"commands": [list(c) for c in commands], "mu": mu, "duration": p.duration}
    names = [f"v{v}_w{w}" for v, w in commands]
    return Units(names, np.full(len(commands), real), names, simulate, describe)


def calibrate(inputs: dict, params: dict, output: str) -> dict:
    """Rule simulator_calibrate: ``results/simulators/calibration/<simulator>.yaml`` (docs/simulators.md)."""
    from simpick.coulomb import contact_layout, ratio_for_gain

    p = CalibrateParams.model_validate(params)
    space = SearchSpace.model_validate(p.space)
    train, test = read_split(inputs["split"])
    # the classes fitted one by one: DRIVE's outside the target too (a gravel or grass robot's user reads theirs)
    every = sorted(p.grounds) if p.kind == "drive" else list(p.classes)
    trained = real_turns(inputs, train, every)
    classes = list(p.classes)
    if p.kind == "drive":  # the target classes among DRIVE's steps, else every class its steps have
        present = set(trained.terrain_class)
        classes = [c for c in classes if c in present] or sorted(present)
    turns = trained[trained.terrain_class.isin(classes)]
    gains = real_gains(turns)
    real = float(gains.gain.mean()) if len(gains) else math.nan
    robot = p.robot.spec(inputs["urdf"])
    out: dict[str, Any] = {
        "simulator": p.simulator,
        "robot": p.robot_name,
        "source": p.source,
        "train_runs": train,
        "test_runs": test,
        "searchable": bool(p.searchable),
        "why_not": p.why_not,
        "settings": {},
        "exposed": {},
        "per_class": {},
        "fit": {
            "real_gain": _r(real),
            "real_runs": [f"{c}/{r}" for c, r in zip(gains.terrain_class, gains.run)],
            "classes": classes,
        },
    }
    if not p.searchable or not math.isfinite(real):
        if p.searchable:
            out["why_not"] = "no training run of the target classes turns under a steady command: nothing to fit"
            out["searchable"] = False
        out["fit"]["note"] = "no setting fitted: the calibrated row is the tuned profile, the best it reaches"
        _write(out, output)
        return out
    if "friction_ratio" not in space.settings and "friction_ratio" not in space.requires:
        raise ValueError(
            "the fit needs friction_ratio among the settings, or fixed among the required ones (Gazebo's, where "
            f"the ratio only switches DART's turn); the search space has {sorted(space.settings)}"
        )
    fixed = {k: r.value for k, r in space.requires.items()}
    units = _units(p, inputs, robot, train, classes, turns, real)
    # as many settings as the runs can identify at most, in the params' order (the job's params are canonical, their
    # keys sorted: Gazebo Classic's and Webots' contact_slip before the ratio)
    names = list(space.settings)[: max(1, len(set(units.runs)))]
    axes = [Axis(k, space.settings[k]) for k in names]
    # the tuned profile's values; None where it does not set the setting (Gazebo's <slip2>: no slip written)
    tuned = {k: p.engine_settings.get(k, 1.0 if k == "friction_ratio" else None) for k in names}
    tuned = {k: None if v is None else float(v) for k, v in tuned.items()}
    # the fit starts from the tuned value, or from the middle of the bounds (of their logarithms for a log setting)
    # where the profile sets none: from a bound, scipy's trf starts its trust region as small as the start (u 1e-6)
    # and stops there
    start = {a.name: a.to_x(0.5) if tuned[a.name] is None else min(max(tuned[a.name], a.low), a.high) for a in axes}
    fit = least_squares_fit(units, axes, fixed, start, p.max_nfev, p.diff_step, p.noise, space.scan, space.optimizer)
    # the tuned profile's own error on the same units: the first evaluation, unless the required settings (or a
    # tuned value outside the bounds) make that evaluation differ from the tuned profile
    if fixed or start != tuned:
        tuned_gains = np.asarray(units.simulate({}), float)
    else:
        tuned_gains = fit["start_gains"]
    tuned_error = units.error(tuned_gains)
    improved = math.isfinite(fit["error"]) and (not math.isfinite(tuned_error) or fit["error"] < tuned_error)
    steps = step_margins(units, fixed, fit["settings"], fit["gains"], axes, fit["fitted"]) if improved else {}
    near_step = sorted(k for k, m in steps.items() if m["step"])
    improved = improved and not near_step
    kept = (
        {k: _r(v) for k, v in fit["settings"].items()}
        if improved
        else {k: _r(v) for k, v in tuned.items() if v is not None}
    )
    out["settings"] = {**fixed, **kept} if improved else kept
    # the ratio fitted, else fixed by the search space (Gazebo's), else the tuned one (not fitted: one run)
    ratio = float(kept.get("friction_ratio", fixed.get("friction_ratio", p.engine_settings.get("friction_ratio", 1.0))))
    at = fit["gains"] if improved else tuned_gains
    exposed = {}
    for k in (k for k in names if k in kept):
        text = space.settings[k].exposed_as
        exposed[k] = text.replace("r x mu", f"{_r(ratio)} x mu") if k == "friction_ratio" else f"{text} (= {kept[k]})"
    if improved:
        exposed.update({k: r.exposed_as for k, r in space.requires.items()})
    out["exposed"] = exposed
    layout = contact_layout(robot)
    ratio_space = space.settings.get("friction_ratio")
    bounds = tuple(ratio_space.bounds) if ratio_space else (FRICTION_RATIO.low, FRICTION_RATIO.high)
    coulomb = ratio_for_gain(layout, real, 0.5, 0.5, p.robot.track, bounds)
    engine_gain = float(np.nanmean(at)) if np.isfinite(at).any() else math.nan
    out["fit"].update(
        {
            "method": _method(space.optimizer, p.diff_step, p.max_nfev)
            + ": the per-run gain residuals (engine - real) of the training runs' turning "
            + (
                "segments replayed as the segments' simulate jobs replay them"
                if p.kind == "segments"
                else "units, each a steady-turn case at a representative command"
            ),
            "objective": "sum over training runs of each run's mean squared gain residual; judged as the held-out "
            "figure is: each run's mean |engine - real gain|, then the mean over runs",
            "cases": units.describe,
            "units": [
                {"run": r, "unit": n, "real_gain": _r(g), "tuned_gain": _r(t), "calibrated_gain": _r(c)}
                for r, n, g, t, c in zip(units.runs, units.names, units.real, tuned_gains, at)
            ],
            "start": {k: _r(v) for k, v in start.items()},
            "fixed": fixed,
            "train_error_tuned": _r(tuned_error),
            "train_error": _r(fit["error"]) if improved else _r(tuned_error),
            "optimum_error": _r(fit["error"]),
            "kept": "the fit"
            if improved
            else (
                f"the tuned settings: the optimum's {', '.join(near_step)} lies within {STEP_MARGIN:.0%} of a step in "
                "the engine's response (a run's gain moves by more than "
                f"{STEP_GAIN} there): not a calibration"
                if near_step
                else "the tuned settings: the optimum's training error "
                f"{_r(fit['error'])} is not below the tuned profile's {_r(tuned_error)}"
            ),
            "step_margins": steps,
            "parameters": fit["parameters"],
            "residual_sd": _r(fit["residual_sd"]),
            "intervals": fit["intervals_from"],
            "residual_sd_from": fit["residual_sd_from"],
            "optimizer": fit["report"],
            "coulomb_ratio": _r(coulomb),
            # (ratio, mean engine gain over the units) of each evaluation, in order
            "trials": [
                [_r(s.get("friction_ratio", ratio)), _r(float(np.nanmean(g)) if np.isfinite(g).any() else math.nan)]
                for s, g in fit["evaluations"]
            ],
            "all_trials": [
                {
                    "settings": {k: _r(v) for k, v in s.items()},
                    "gain": _r(float(np.nanmean(g)) if np.isfinite(g).any() else math.nan),
                    "gains": [_r(x) for x in g],
                    "error": _r(units.error(g)),
                }
                for s, g in fit["evaluations"]
            ],
            "engine_gain": _r(engine_gain),
            "reached": bool(math.isfinite(engine_gain) and abs(engine_gain - real) <= p.tolerance),
            "tolerance": p.tolerance,
            "bounds": list(bounds),
        }
    )
    out["fit"]["parts"] = part_shares(units, space, fixed, start, fit["settings"], tuned_error, fit["error"], improved)
    test_turns = real_turns(inputs, test, every)
    pooled = {**fixed, **fit["settings"]} if improved else {}
    tuned_by_unit = dict(zip(units.names, np.asarray(tuned_gains, float)))
    out["per_class"] = _class_fits(p, inputs, robot, trained, test_turns, pooled, space, fixed, tuned_by_unit)
    _write(out, output)
    return out


def part_shares(
    units: Units, space, fixed: dict, start: dict, fitted: dict, tuned_error: float, error: float, improved: bool
) -> dict:
    """The contact's and the actuator's share of the fit (:attr:`SearchSetting.part`): per part with a fitted
    setting, the training error with that part's settings at the fit and the other part's at their start (the
    tuned values), and its share of the fit's gain, (tuned error - that error) / (tuned error - the fit's error).
    The shares need not add to 1: what one part gains can depend on the other's value. A part alone in the fit
    has the whole fit's error and share 1, with no evaluation of its own."""
    parts: dict[str, list[str]] = {}
    for name in fitted:
        parts.setdefault(space.settings[name].part, []).append(name)
    gained = tuned_error - error
    out: dict[str, Any] = {}
    for part, names in sorted(parts.items()):
        entry: dict[str, Any] = {"settings": names}
        if not improved:
            entry["share"] = None
            entry["why_none"] = "the fit was not kept"
        elif len(parts) == 1:
            entry.update({"train_error": _r(error), "share": 1.0})
        else:
            alone = {k: (fitted[k] if k in names else start[k]) for k in fitted}
            part_error = units.error(np.asarray(units.simulate({**fixed, **alone}), float))
            share = (tuned_error - part_error) / gained if gained > 0 else math.nan
            entry.update({"train_error": _r(part_error), "share": _r(share)})
        out[part] = entry
    for part in ("contact", "actuator"):
        if part not in out:
            out[part] = {"settings": [], "share": 0.0, "why_none": f"no {part} setting in the search space"}
    return out


def _units(p: CalibrateParams, inputs: dict, robot, runs: list[str], classes: list[str], turns, real: float) -> Units:
    """The fitted units: the training runs' turning segments (kind segments), else steady-turn cases at their
    representative commands (:func:`steady_units`) on the classes' median friction."""
    if p.kind == "segments" and p.segments_case is not None:
        return segment_units(p, inputs, runs, classes)
    if not p.commands:  # each unit its own: the run's command, its class's ground, its real gain
        picked = representative_units(turns, p.drive_commands)
        return run_units(p, robot, picked)
    mu = float(np.median([p.grounds[c] for c in classes]))
    return steady_units(p, robot, p.commands, mu, real, runs)


def representative_units(turns: pd.DataFrame, n: int) -> pd.DataFrame:
    """Kinds drive and replay (and segments without a replay case): the training units the fit runs, at most
    ``n``, each with its own command, class and real gain. Per unit (a run; a DRIVE step is one) its turning window
    of median |w| gives the command and the mean of its windows' gains the real gain, as the held-out figure
    averages a run's windows; where there are more than ``n`` units, the median unit by |w| of each of ``n`` equal
    bins of them (terrain_class, run, v, w, gain)."""
    rows = []
    for (cls, run), g in turns.groupby(["terrain_class", "run"], sort=True):
        g = g.assign(aw=g.w.abs()).sort_values(["aw"], kind="stable").reset_index(drop=True)
        mid = g.iloc[len(g) // 2]
        rows.append({"terrain_class": cls, "run": run, "v": round(float(mid.v), 3), "w": round(float(mid.w), 3)})
        rows[-1]["gain"] = float(g.gain.mean())
    if not rows:
        return pd.DataFrame(columns=["terrain_class", "run", "v", "w", "gain"])
    order = pd.DataFrame(rows)
    order = order.assign(aw=order.w.abs()).sort_values(["aw", "terrain_class", "run"]).reset_index(drop=True)
    bins = np.array_split(np.arange(len(order)), min(n, len(order)))
    return order.iloc[[int(b[len(b) // 2]) for b in bins]].drop(columns="aw").reset_index(drop=True)


def run_units(p: CalibrateParams, robot, picked: pd.DataFrame) -> Units:
    """The engine's steady turn from rest at each picked unit's command on its class's ground (the validation's
    steady-turn case), against that unit's own real gain: the per-run gain residuals the held-out figure takes,
    at each run's representative command (a replay of every DRIVE step or full-replay window per evaluation costs
    more than these kinds' fits are given)."""
    from simpick.studies.validation.cases import Setup, run_case

    commands = list(zip(picked.v.astype(float), picked.w.astype(float)))
    grounds = [float(p.grounds[str(c)]) for c in picked.terrain_class]

    def simulate(settings: dict) -> np.ndarray:
        setup = Setup(
            engine=p.engine,
            robot=robot,
            timestep=p.physics.timestep,
            max_wheel_torque=p.robot.max_wheel_torque,
            track=p.robot.track,
            settings={**p.engine_settings, **settings},
        )
        ratio = float(settings.get("friction_ratio", p.engine_settings.get("friction_ratio", 1.0)))
        return np.array(
            [_engine_gain(run_case, setup, ratio, v, w, mu, p.duration) for (v, w), mu in zip(commands, grounds)]
        )

    runs = [f"{c}/{r}" for c, r in zip(picked.terrain_class, picked.run)]
    describe = {
        "units": runs,
        "commands": [[v, w] for v, w in commands],
        "grounds": grounds,
        "duration": p.duration,
        "from": "each unit's turning window of median |w| (a steady turn from rest on its class's ground), against "
        "its windows' mean real gain",
    }
    return Units(runs, picked.gain.to_numpy(float), runs, simulate, describe)


def _class_fits(
    p, inputs, robot, train: pd.DataFrame, test: pd.DataFrame, pooled: dict, space, fixed, tuned_by_unit=None
) -> dict:
    """Per terrain class with training turns: its own fit (the friction_ratio alone, one class's runs identifying
    no more, the other settings at the pooled fit's; ``p.class_nfev`` least-squares evaluations from the pooled
    fit) on its training runs' units, beside the pooled fit and the tuned profile on the same units (the tuned
    gains from ``tuned_by_unit``, unit -> the pooled fit's tuned evaluation, where it has them), and both fits
    judged on the class's held-out runs the same way (its turning segments replayed; kinds drive and replay:
    steady-turn cases at their commands). The class's own spread is the standard deviation of its runs' real
    gains, training and held-out (NaN below two runs). A class keeps a fit of its own only where its training
    error is below both the pooled fit's (by the fit's tolerance) and the tuned profile's."""
    out = {}
    tuned_by_unit = tuned_by_unit or {}
    # a ratio the search space fixes (Gazebo's) gets no class fit: every class is placed by the pooled fit
    ratio_axis = (
        Axis("friction_ratio", space.settings["friction_ratio"]) if "friction_ratio" in space.settings else None
    )
    pooled_ratio = float(pooled.get("friction_ratio", p.engine_settings.get("friction_ratio", 1.0)))
    for cls, t in train.groupby("terrain_class"):
        gains = real_gains(t)
        gain = float(gains.gain.mean())
        runs = [f"{cls}/{r}" for r in gains.run]
        held = test[test.terrain_class == cls]
        every = pd.concat([gains, real_gains(held)]) if len(held) else gains
        entry: dict[str, Any] = {
            "friction_ratio": _r(pooled_ratio),
            "real_gain": _r(gain),
            "runs": runs,
            "placed_by": "the pooled fit (no fit of its own)",
            "class_spread": _r(float(every.gain.std(ddof=1)) if len(every) > 1 else math.nan),
            "spread_runs": len(every),
        }
        if p.class_nfev and str(cls) in p.grounds and ratio_axis is not None:
            units = _units(p, inputs, robot, runs, [str(cls)], t, gain)
            others = {**fixed, **{k: v for k, v in pooled.items() if k != "friction_ratio"}}
            fit = least_squares_fit(
                units,
                [ratio_axis],
                others,
                {"friction_ratio": pooled_ratio},
                p.class_nfev,
                p.diff_step,
                p.noise,
                optimizer=space.optimizer,
            )
            own_ratio = float(fit["settings"]["friction_ratio"])
            pooled_gains = fit["start_gains"]
            pooled_error = units.error(pooled_gains)
            if all(n in tuned_by_unit for n in units.names):
                tuned_error = units.error(np.array([tuned_by_unit[n] for n in units.names], float))
            else:
                tuned_error = units.error(np.asarray(units.simulate({}), float))
            better = math.isfinite(fit["error"]) and fit["error"] < pooled_error
            steps = (
                step_margins(units, others, fit["settings"], fit["gains"], [ratio_axis], fit["fitted"])
                if better
                else {}
            )
            better = better and not any(m["step"] for m in steps.values())
            ratio = own_ratio if better else pooled_ratio
            at = fit["gains"] if better else pooled_gains
            engine_gain = float(np.nanmean(at)) if np.isfinite(at).any() else math.nan
            entry.update(
                {
                    "friction_ratio": _r(ratio),
                    "placed_by": "its own least-squares fit on the engine "
                    f"({_trials(fit['report']['engine_evaluations'])} from the pooled fit, {fit['report']['name']})",
                    "engine_gain": _r(engine_gain),
                    "pooled_engine_gain": _r(
                        float(np.nanmean(pooled_gains)) if np.isfinite(pooled_gains).any() else math.nan
                    ),
                    "train_error": _r(units.error(at)),
                    "pooled_train_error": _r(pooled_error),
                    "tuned_train_error": _r(tuned_error),
                    # by more than the fit's tolerance: a tie within the engine's noise keeps the pooled file; and
                    # below the tuned profile's: a class file that fits its runs worse than tuned has fitted nothing
                    "improves": bool(
                        better and units.error(at) + p.tolerance < pooled_error and units.error(at) < tuned_error
                    ),
                    "reached": bool(math.isfinite(engine_gain) and abs(engine_gain - gain) <= p.tolerance),
                    "parameters": fit["parameters"],
                    "step_margins": steps,
                    "cases": units.describe,
                    "trials": [[_r(s["friction_ratio"]), _r(float(np.nanmean(g)))] for s, g in fit["evaluations"]],
                }
            )
            if len(held):
                hgains = real_gains(held)
                hruns = [f"{cls}/{r}" for r in hgains.run]
                hunits = _units(p, inputs, robot, hruns, [str(cls)], held, float(hgains.gain.mean()))
                pooled_held = np.asarray(hunits.simulate({**fixed, **pooled}), float)
                own_held = (
                    np.asarray(hunits.simulate({**others, "friction_ratio": ratio}), float)
                    if abs(ratio - pooled_ratio) > 1e-9
                    else pooled_held
                )
                entry["heldout"] = {
                    "runs": len(hgains),
                    "real_gain": _r(float(hgains.gain.mean())),
                    "cases": hunits.describe,
                    "class_fit_gain": _r(float(np.nanmean(own_held))),
                    "pooled_fit_gain": _r(float(np.nanmean(pooled_held))),
                    "class_fit_error": _r(hunits.error(own_held)),
                    "pooled_fit_error": _r(hunits.error(pooled_held)),
                }
        out[str(cls)] = entry
    return out


def _method(optimizer: str, diff_step: float, max_nfev: int) -> str:
    """The fit's method in words (the file's ``method``)."""
    if optimizer == "mujoco.sysid":
        import mujoco

        return (
            f"MuJoCo's own system identification (mujoco.sysid.optimize, MuJoCo {mujoco.__version__}, optimizer "
            "'mujoco': mujoco.minimize.least_squares, bounded; its finite-difference Jacobian, mujoco.minimize."
            f"jacobian_fd, of {diff_step} of each setting's range; intervals from mujoco.sysid.calculate_intervals), "
            f"{max_nfev} evaluations at most"
        )
    return (
        "scipy.optimize.least_squares (trf, bounded; forward-difference Jacobian of "
        f"{diff_step} of each setting's range), max_nfev {max_nfev}"
    )


def _trials(n: int) -> str:
    return f"{n} engine evaluation" + ("s" if n != 1 else "")


def _engine_gain(run_case, setup, ratio: float, v: float, w: float, mu: float, duration: float) -> float:
    """The engine's steady yaw-rate gain on the validation's steady-turn case at ``ratio`` (NaN if it failed)."""
    case = {"kind": "yaw_gain", "v": v, "w": w, "mu": mu, "duration": duration, "friction_ratio": ratio}
    record = run_case(setup, f"calibrate_r{ratio:.4f}", case)
    checks = [c for c in record["checks"] if c["quantity"] == "yaw_rate_gain"]
    if record["status"] != "ok" or not checks:
        return math.nan
    return float(checks[0]["engine_value"])


def _r(x: float) -> float | None:
    return round(float(x), 4) if x is not None and math.isfinite(float(x)) else None


def _write(data: dict, output: str) -> None:
    Path(output).parent.mkdir(parents=True, exist_ok=True)
    Path(output).write_text(yaml.safe_dump(data, sort_keys=False, allow_unicode=True, width=110))
