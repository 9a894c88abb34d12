"""Each simulator calibrated on real runs within the settings its users can set: the calibrated profile.

The search space is data (``resources/simulators/calibration.yaml``): per simulator, the adapter settings that
move the robot's steady turning, each with the simulator's own name for it, its bounds and its source. Today
that is the wheels' lateral/longitudinal friction ratio wherever the simulator exposes two friction
directions (Gazebo's ``<mu2>`` with ``<fdir1>``, Webots' two ``coulombFriction`` values, a MuJoCo pair's two
tangential frictions); a simulator with isotropic friction only has none, says why, and its calibrated row is
its tuned profile.

The fit (:func:`calibrate`) is cheap because the steady turning gain falls monotonically with the ratio:

1. the real steady yaw-rate gain of the training runs' turning segments (firm classes, each run's segments
   averaged, then the runs);
2. the ratio whose anisotropic Coulomb gain equals it (:func:`simpick.coulomb.ratio_for_gain`);
3. the engine, as the simulator's tuned profile with that ratio, on the validation's steady-turn case
   (flat ground, the target classes' median friction), its gain measured, and the ratio corrected by
   secant steps until the engine's gain is within ``tolerance`` of the real one (2-4 engine runs; every
   trial recorded).

Per class, where a class has a training run that turns, the ratio is placed the same way from the class's
gain, shifted by the engine's offset from Coulomb at the pooled fit (not run on the engine: a user's start).
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

    @model_validator(mode="after")
    def _ordered(self):
        if not self.bounds[0] < self.bounds[1]:
            raise ValueError(f"bounds {list(self.bounds)}: low must be below high")
        return self


class Required(_Strict):
    """An adapter setting the fitted ones need (Webots' asymmetric friction follows the wheel)."""

    value: Any
    exposed_as: str
    source: str


class Alternative(_Strict):
    """Other values of settings the simulator exposes, tried with the fitted ones (each gets its own fit)."""

    settings: dict[str, Any]
    exposed_as: str
    source: str


class SearchSpace(_Strict):
    """A simulator's calibrated-profile search space."""

    searchable: bool = Field(description="a setting it exposes moves the steady turning")
    settings: dict[str, SearchSetting] = {}
    requires: dict[str, Required] = {}
    alternatives: list[Alternative] = Field(
        [],
        description="after the tuned values, other values of exposed settings the fit is repeated with (the "
        "engine's gain need not reach the real one at the tuned values); the nearest to the real gain is kept",
    )
    why_not: str | None = Field(None, description="searchable false: why, quoting the source")
    if_unbound: str | None = Field(
        None, description="the simulator exposes the settings, but simpick's adapter binds none of them: why"
    )

    @model_validator(mode="after")
    def _consistent(self):
        if self.searchable and not self.settings:
            raise ValueError("searchable true needs settings: the adapter settings the fit changes")
        if not self.searchable and not self.why_not:
            raise ValueError("searchable false needs why_not: why no setting it exposes moves the turning")
        if not self.searchable and (self.settings or self.requires or self.alternatives):
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
    missing = [k for k in [*space.settings, *space.requires, *(k for a in space.alternatives for k in a.settings)]]
    missing = [k for k in missing if k not in fields]
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
    commands: list[tuple[float, float]] | None = Field(
        None,
        description="(v m/s, w rad/s) of the steady-turn cases whose mean gain is fitted; None: the training "
        "runs' turning segments' own commands (an engine whose gain depends on the turn rate, ODE's force-"
        "dependent slip, is fitted where the robot turned)",
    )
    duration: Positive = Field(6.0, description="s of the steady-turn case (its second half is measured)")
    tolerance: Positive = Field(0.005, description="|engine gain - real gain| at which the fit stops")
    max_trials: Annotated[int, Field(ge=1, le=8)] = 5
    class_trials: Annotated[int, Field(ge=0, le=8)] = Field(
        3,
        description="engine trials of each class's own fit (its training runs' gain, its ground, its commands), "
        "started from the Coulomb placement; 0: the Coulomb placement alone",
    )
    drive_commands: Annotated[int, Field(ge=1, le=12)] = Field(
        4,
        description="kinds drive and replay: how many of the training units' commands the engine runs (the "
        "median unit of each of as many equal bins of |w|): DRIVE has some 170 training steps, a full BorealTC "
        "replay hundreds of turning windows, each a 6 s engine run",
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


def drive_commands(turns: pd.DataFrame, n: int) -> list[tuple[float, float]]:
    """(v, w) of ``n`` representative turning steps: the median step, by |w|, of each of ``n`` equal bins of
    the steps sorted by |w| (fewer where there are fewer steps)."""
    order = turns.assign(aw=turns.w.abs()).sort_values(["aw", "run"]).reset_index(drop=True)
    bins = np.array_split(np.arange(len(order)), min(n, len(order)))
    return [(round(float(order.v[b[len(b) // 2]]), 3), round(float(order.w[b[len(b) // 2]]), 3)) for b in bins]


def secant_fit(measure, target: float, start: float, coulomb_ratio, bounds, tolerance: float, max_trials: int):
    """Trials [(ratio, gain)] of ``measure`` (ratio -> engine gain, falling with the ratio) from ``start`` until
    a gain within ``tolerance`` of ``target``: the second trial corrects the target by the first trial's offset
    from it through ``coulomb_ratio`` (gain -> the Coulomb ratio, NaN outside its range); the later ones are
    secant steps, kept within the bracket of trials on either side of the target once there is one, and
    halving it where a secant step would leave it (an engine whose gain jumps: ODE's friction box locking).
    Returns (trials, the trial nearest the target)."""
    low, high = bounds
    clip = lambda r: float(min(max(r, low), high))  # noqa: E731
    trials = [(clip(start), float(measure(clip(start))))]
    while len(trials) < max_trials and abs(trials[-1][1] - target) > tolerance and math.isfinite(trials[-1][1]):
        r1, g1 = trials[-1]
        above = [t for t in trials if math.isfinite(t[1]) and t[1] > target]  # turn too much: ratio too low
        below = [t for t in trials if math.isfinite(t[1]) and t[1] < target]
        if len(trials) == 1:
            r = coulomb_ratio(target + (target - g1))
            if not math.isfinite(r):  # past Coulomb's range: a step the right way
                r = r1 * (0.8 if g1 < target else 1.25)
        elif above and below:
            a = max(above, key=lambda t: t[0])
            b = min(below, key=lambda t: t[0])
            lo, hi = sorted((a[0], b[0]))
            r = a[0] - (a[1] - target) * (b[0] - a[0]) / (b[1] - a[1]) if b[1] != a[1] else math.nan
            if not (math.isfinite(r) and lo + 0.05 * (hi - lo) < r < hi - 0.05 * (hi - lo)):
                r = 0.5 * (lo + hi)
        else:
            r0, g0 = trials[-2]
            if g1 == g0:
                break
            r = r1 - (g1 - target) * (r1 - r0) / (g1 - g0)
        r = clip(r)
        if any(abs(r - t[0]) < 1e-4 for t in trials):
            break
        trials.append((r, float(measure(r))))
    finite = [t for t in trials if math.isfinite(t[1])]
    best = min(finite, key=lambda t: abs(t[1] - target)) if finite else trials[-1]
    return trials, best


def calibrate(inputs: dict, params: dict, output: str) -> dict:
    """Rule simulator_calibrate: ``results/simulators/calibration/<simulator>.yaml`` (docs/simulators.md)."""
    from simpick.coulomb import contact_layout, ratio_for_gain, with_friction_ratio, yaw_rate_gain
    from simpick.studies.validation.cases import Setup, run_case

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
    layout = contact_layout(robot)
    track = p.robot.track
    name = "friction_ratio"
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
    if set(space.settings) != {name}:
        raise ValueError(f"the fit knows the setting {name!r} only; the search space has {sorted(space.settings)}")
    bounds = tuple(space.settings[name].bounds)
    mu = float(np.median([p.grounds[c] for c in classes]))
    fixed = {k: r.value for k, r in space.requires.items()}
    if p.commands:
        commands = p.commands
    elif p.kind in ("drive", "replay"):
        commands = drive_commands(turns, p.drive_commands)
    else:
        commands = [(round(float(r.v), 3), round(float(r.w), 3)) for r in turns.itertuples()]
    # the Coulomb placement at a moving turn: the quasi-static gain hardly depends on the command
    v0, w0 = 0.5, 0.5

    def coulomb_ratio(gain: float) -> float:
        return ratio_for_gain(layout, gain, v0, w0, track, bounds)

    def coulomb_gain(ratio: float) -> float:
        return yaw_rate_gain(with_friction_ratio(layout, ratio), v0, w0, track)

    start = coulomb_ratio(real)
    coulomb_start = start
    if not math.isfinite(start):  # the real gain lies beyond Coulomb's range within the bounds
        start = bounds[0] if real > coulomb_gain(bounds[0]) else bounds[1]
    fits = []
    for alternative in [None, *space.alternatives]:
        extra = {} if alternative is None else dict(alternative.settings)
        setup = Setup(
            engine=p.engine,
            robot=robot,
            timestep=p.physics.timestep,
            max_wheel_torque=p.robot.max_wheel_torque,
            track=track,
            settings={**p.engine_settings, **fixed, **extra},
        )
        measured = {}

        def measure(ratio: float, setup=setup, measured=measured) -> float:
            gains = [_engine_gain(run_case, setup, ratio, v, w, mu, p.duration) for v, w in commands]
            measured[round(ratio, 4)] = gains
            return float(np.mean(gains))

        trials, best = secant_fit(measure, real, start, coulomb_ratio, bounds, p.tolerance, p.max_trials)
        fits.append((alternative, extra, trials, best, measured, setup))
        if abs(best[1] - real) <= p.tolerance:
            break
    alternative, extra, trials, (ratio, engine_gain), measured, kept = min(
        fits, key=lambda f: abs(f[3][1] - real) if math.isfinite(f[3][1]) else math.inf
    )
    offset = engine_gain - coulomb_gain(ratio)
    out["per_class"] = _class_fits(
        p,
        kept,
        trained,
        real_turns(inputs, test, every),
        ratio,
        lambda gain: coulomb_ratio(gain - offset),
        bounds,
    )
    out["settings"] = {**fixed, **extra, name: _r(ratio)}
    text = space.settings[name].exposed_as.replace("r x mu", f"{_r(ratio)} x mu")
    out["exposed"] = {name: text, **{k: r.exposed_as for k, r in space.requires.items()}}
    if alternative is not None:
        out["exposed"].update({k: alternative.exposed_as for k in alternative.settings})
    out["fit"].update(
        {
            "coulomb_ratio": _r(coulomb_start),
            "cases": {"commands": [list(c) for c in commands], "mu": mu, "duration": p.duration},
            "trials": [[_r(r), _r(g)] for r, g in trials],  # (ratio, mean gain) at the kept settings
            "all_trials": [
                {"settings": {**e, name: _r(r)}, "gain": _r(g), "gains": [_r(x) for x in m.get(round(r, 4), [])]}
                for _, e, t, _, m, _ in fits
                for r, g in t
            ],
            "engine_gain": _r(engine_gain),
            "reached": bool(abs(engine_gain - real) <= p.tolerance),
            "tolerance": p.tolerance,
            "bounds": list(bounds),
        }
    )
    _write(out, output)
    return out


def _class_fits(p, setup, train: pd.DataFrame, test: pd.DataFrame, pooled: float, placed, bounds) -> dict:
    """Per terrain class with training turns: the ratio of the class's own fit (its training runs' gain on its
    own ground at its own commands, ``p.class_trials`` engine trials from the Coulomb placement ``placed``:
    gain -> ratio, shifted by the engine's offset at the pooled fit), and both fits judged on the class's
    held-out runs: the engine's steady gain at those runs' commands (DRIVE: 4 representative ones) against
    each run's real gain. That is a steady-turn case at their commands, not a replay of them: a replay runs
    the pooled fit only (the calibrated profile)."""
    from simpick.studies.validation.cases import run_case

    def commands(turns: pd.DataFrame) -> list[tuple[float, float]]:
        if p.kind in ("drive", "replay"):
            return drive_commands(turns, p.drive_commands)
        return [(round(float(r.v), 3), round(float(r.w), 3)) for r in turns.itertuples()]

    def engine(ratio: float, cmds, mu: float) -> float:
        return float(np.mean([_engine_gain(run_case, setup, ratio, v, w, mu, p.duration) for v, w in cmds]))

    out = {}
    for cls, t in train.groupby("terrain_class"):
        gains = real_gains(t)
        gain = float(gains.gain.mean())
        start = placed(gain)
        entry: dict[str, Any] = {
            "friction_ratio": _r(start),
            "real_gain": _r(gain),
            "runs": [f"{cls}/{r}" for r in gains.run],
            "placed_by": "anisotropic Coulomb, shifted by the engine's offset at the pooled fit (no engine run)",
        }
        mu = p.grounds.get(str(cls))
        if p.class_trials and mu is not None:
            cmds = commands(t)
            trials, (ratio, engine_gain) = secant_fit(
                lambda r, cmds=cmds, mu=mu: engine(r, cmds, mu),
                gain,
                start if math.isfinite(start) else pooled,
                placed,
                bounds,
                p.tolerance,
                p.class_trials,
            )
            # the pooled fit on the same training runs: the class's own fit is worth a file only where it
            # turns closer to them (decided on training runs alone)
            pooled_gain = engine(pooled, cmds, mu)
            entry.update(
                {
                    "friction_ratio": _r(ratio),
                    "placed_by": f"its own fit on the engine ({_trials(len(trials))} from the Coulomb placement)",
                    "coulomb_ratio": _r(start),
                    "engine_gain": _r(engine_gain),
                    "pooled_engine_gain": _r(pooled_gain),
                    # by more than the fit's tolerance: a tie within the engine's noise keeps the pooled file
                    "improves": bool(abs(engine_gain - gain) + p.tolerance < abs(pooled_gain - gain)),
                    "reached": bool(abs(engine_gain - gain) <= p.tolerance),
                    "cases": {"commands": [list(c) for c in cmds], "mu": mu, "duration": p.duration},
                    "trials": [[_r(r), _r(g)] for r, g in trials],
                }
            )
            held = test[test.terrain_class == cls]
            if len(held):
                runs = real_gains(held)
                hcmds = commands(held)
                own, pooled_gain = engine(ratio, hcmds, mu), engine(pooled, hcmds, mu)
                entry["heldout"] = {
                    "runs": len(runs),
                    "real_gain": _r(float(runs.gain.mean())),
                    "commands": [list(c) for c in hcmds],
                    "class_fit_gain": _r(own),
                    "pooled_fit_gain": _r(pooled_gain),
                    "class_fit_error": _r(float(np.mean(np.abs(own - runs.gain)))),
                    "pooled_fit_error": _r(float(np.mean(np.abs(pooled_gain - runs.gain)))),
                }
        out[str(cls)] = entry
    return out


def _trials(n: int) -> str:
    return f"{n} trial" + ("s" if n != 1 else "")


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
