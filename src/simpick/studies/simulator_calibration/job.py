"""Rule simulator_calibrate's job (:func:`calibrate`): the pooled fit, each part's share of it, the
classes' own fits, and the file that says what was fitted and kept."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import yaml

from simpick.compare.realmetrics import statistics_settings
from simpick.engines.base import FRICTION_RATIO
from simpick.score.split import read_split
from simpick.studies.simulator_calibration.fit import (
    STEP_GAIN,
    STEP_MARGIN,
    Axis,
    Units,
    _r,
    _rs,
    least_squares_fit,
    step_margins,
)
from simpick.studies.simulator_calibration.params import CalibrateParams
from simpick.studies.simulator_calibration.runs import real_gains, real_turns
from simpick.studies.simulator_calibration.space import SearchSpace
from simpick.studies.simulator_calibration.units import _units


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
    # a simulator without a second friction direction (Drake, Isaac Sim) fits its contact's compliance and its
    # wheels' drive alone: no ratio is fitted, fixed or placed by Coulomb
    has_ratio = "friction_ratio" in space.settings or "friction_ratio" in space.requires
    fixed = {k: r.value for k, r in space.requires.items()}
    units = _units(p, inputs, robot, train, classes, turns)
    # as many settings as the runs can identify at most, in the search space's order (SearchSpace.order: the one
    # that moves the turn most first, so that a class with one training run fits it)
    names = space.fit_order()[: max(1, len(set(units.runs)))]
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
        {k: _rs(v) for k, v in fit["settings"].items()}
        if improved
        else {k: _rs(v) for k, v in tuned.items() if v is not None}
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
    coulomb = ratio_for_gain(layout, real, 0.5, 0.5, p.robot.track, bounds) if has_ratio else math.nan
    # each evaluation's (value, mean gain) of the ratio, else of the first fitted setting
    lead = "friction_ratio" if has_ratio else names[0]
    lead_tuned = ratio if has_ratio else tuned[lead] if tuned[lead] is not None else start[lead]
    engine_gain = float(np.nanmean(at)) if np.isfinite(at).any() else math.nan
    out["fit"].update(
        {
            "method": _method(space.optimizer, p.diff_step, p.max_nfev)
            + ": the per-run gain residuals (engine - real) of the training runs' turning "
            + REPLAYED[p.kind],
            "objective": "sum over training runs of each run's mean squared gain residual; judged as the held-out "
            "figure is: each run's mean |engine - real gain|, then the mean over runs",
            "cases": units.describe,
            "units": [
                {"run": r, "unit": n, "real_gain": _r(g), "tuned_gain": _r(t), "calibrated_gain": _r(c)}
                for r, n, g, t, c in zip(units.runs, units.names, units.real, tuned_gains, at)
            ],
            "start": {k: _rs(v) for k, v in start.items()},
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
            # (the lead setting's value, mean engine gain over the units) of each evaluation, in order
            "trials_of": lead,
            "trials": [
                [_rs(s.get(lead, lead_tuned)), _r(float(np.nanmean(g)) if np.isfinite(g).any() else math.nan)]
                for s, g in fit["evaluations"]
            ],
            "all_trials": [
                {
                    "settings": {k: _rs(v) for k, v in s.items()},
                    "gain": _r(float(np.nanmean(g)) if np.isfinite(g).any() else math.nan),
                    "gains": [_r(x) for x in g],
                    "error": _r(units.error(g)),
                }
                for s, g in fit["evaluations"]
            ],
            "engine_gain": _r(engine_gain),
            # the real gain the fit targets: its units' (a segment's, a replayed window's, a step's), not real_gain's
            # steady windows; reached compares the engine's mean gain with it
            "fitted_real_gain": _r(_mean(units.real)),
            "reached": bool(math.isfinite(engine_gain) and abs(engine_gain - _mean(units.real)) <= p.tolerance),
            "tolerance": p.tolerance,
            "bounds": list(bounds) if has_ratio else None,
        }
    )
    out["fit"]["parts"] = part_shares(units, space, fixed, start, fit["settings"], tuned_error, fit["error"], improved)
    test_turns = real_turns(inputs, test, every)
    pooled = {**fixed, **fit["settings"]} if improved else {}
    tuned_by_unit = dict(zip(units.names, np.asarray(tuned_gains, float)))
    # each class from the pooled fit's settings (the tuned ones where it was not kept), in the pooled fit's order
    kept_start = {k: float(pooled.get(k, start[k])) for k in names}
    out["per_class"] = _class_fits(
        p, inputs, robot, trained, test_turns, kept_start, space, fixed, tuned_by_unit, kept=out["settings"]
    )
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


# what an evaluation replays, per kind, in the file's method
REPLAYED = {
    "segments": "segments replayed as the segments' simulate jobs replay them",
    "replay": "windows of the full replay's held-out grid, each run replayed from rest as its replay simulate job "
    "replays it up to its last fitted window (its first turning windows: fit.cases)",
    "drive": "steps replayed as DRIVE's replay replays them (the warm-up at the real robot's wheel speeds, then the "
    "step's measured ones), at most drive_commands of them stratified by |w| (fit.cases)",
}


def _class_fits(
    p,
    inputs,
    robot,
    train: pd.DataFrame,
    test: pd.DataFrame,
    pooled: dict,
    space,
    fixed,
    tuned_by_unit=None,
    kept: dict | None = None,
) -> dict:
    """Per terrain class with training turns: its own fit of the pooled fit's settings (``pooled``: name -> the
    pooled fit's value, or its start where it was not kept, in the pooled fit's order; as many of them as the
    class's training runs can identify, the rest at the pooled values; ``p.class_nfev`` least-squares evaluations
    from the pooled values) on its training runs' units, beside the pooled fit and the tuned profile on the same
    units (the tuned gains from ``tuned_by_unit``, unit -> the pooled fit's tuned evaluation, where it has them),
    and both judged on the class's held-out runs the same way (what the held-out figure replays). The class's own
    spread is the standard deviation of its runs' real gains, training and held-out (NaN below two runs); on DRIVE,
    whose steps are drawn at independent commands, the class's step-to-step repeatability of its gain (the table's
    spread, :func:`simpick.compare.steps.gain_repeatability`, over the class's steps alone). A class
    keeps a fit of its own (its ``settings``: the required ones and the pooled fit's with its fitted values over them,
    each fitted value with its interval in ``parameters``) only where its
    training error is below the pooled fit's, no fitted value lies within a step of the engine's response, and it
    beats the pooled one by the fit's tolerance and the tuned profile (``improves``). ``kept``: the settings the
    pooled file holds (the fit's, or the tuned ones where it was not kept; default the start ``pooled``), against
    which a class's fit is compared on its training and held-out runs: where the fit was not kept and the tuned
    profile leaves a setting unset, the class's fit starts that setting at its bounds' middle, which is not what the
    pooled file does."""
    out = {}
    kept = {**fixed, **pooled} if kept is None else dict(kept)
    tuned_by_unit = tuned_by_unit or {}
    order = [k for k in pooled if k in space.settings]
    base = {**fixed, **pooled}
    # DRIVE's steps, read once: each class's spread is its step-to-step repeatability over them
    drive_steps = pd.read_csv(inputs["steps"]) if p.kind == "drive" and p.drive_tolerance is not None else None
    for cls, t in train.groupby("terrain_class"):
        gains = real_gains(t)
        gain = float(gains.gain.mean())
        runs = [f"{cls}/{r}" for r in gains.run]
        held = test[test.terrain_class == cls]
        every = pd.concat([gains, real_gains(held)]) if len(held) else gains
        entry: dict[str, Any] = {
            "settings": {k: _rs(v) if isinstance(v, float) else v for k, v in kept.items()},
            "real_gain": _r(gain),
            "runs": runs,
            "placed_by": "the pooled fit (no fit of its own)",
            **_class_spread(drive_steps, str(cls), every, p.drive_tolerance),
        }
        if p.class_nfev and str(cls) in p.grounds and order:
            units = _units(p, inputs, robot, runs, [str(cls)], t)
            axes = [Axis(k, space.settings[k]) for k in order[: max(1, len(set(units.runs)))]]
            fit = least_squares_fit(
                units,
                axes,
                base,
                {a.name: min(max(pooled[a.name], a.low), a.high) for a in axes},
                p.class_nfev,
                p.diff_step,
                p.noise,
                optimizer=space.optimizer,
            )
            # the pooled file's gains: the fit's start where that is what the file holds
            at_start = {**base, **{a.name: min(max(pooled[a.name], a.low), a.high) for a in axes}}
            same = _same_settings(kept, at_start)
            pooled_gains = fit["start_gains"] if same else np.asarray(units.simulate(kept), float)
            pooled_error = units.error(pooled_gains)
            if all(n in tuned_by_unit for n in units.names):
                tuned_error = units.error(np.array([tuned_by_unit[n] for n in units.names], float))
            else:
                tuned_error = units.error(np.asarray(units.simulate({}), float))
            better = math.isfinite(fit["error"]) and fit["error"] < pooled_error
            steps = step_margins(units, base, fit["settings"], fit["gains"], axes, fit["fitted"]) if better else {}
            better = better and not any(m["step"] for m in steps.values())
            own = {**base, **fit["settings"]} if better else dict(kept)
            at = fit["gains"] if better else pooled_gains
            engine_gain = float(np.nanmean(at)) if np.isfinite(at).any() else math.nan
            entry.update(
                {
                    "settings": {k: _rs(v) if isinstance(v, float) else v for k, v in own.items()},
                    "fitted": [a.name for a in axes],
                    # the training units the class's fit replays (their runs; DRIVE: at most drive_commands steps)
                    "fitted_runs": len(set(units.runs)),
                    "placed_by": "its own least-squares fit on the engine of "
                    f"{', '.join(a.name for a in axes)} ({_trials(fit['report']['engine_evaluations'])} from the "
                    f"pooled fit, {fit['report']['name']})",
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
                    "fitted_real_gain": _r(_mean(units.real)),
                    "reached": bool(math.isfinite(engine_gain) and abs(engine_gain - _mean(units.real)) <= p.tolerance),
                    "parameters": fit["parameters"],
                    "step_margins": steps,
                    "cases": units.describe,
                    "trials": [
                        {"settings": {k: _rs(v) for k, v in s.items()}, "gain": _r(float(np.nanmean(g)))}
                        for s, g in fit["evaluations"]
                    ],
                }
            )
            if len(held):
                hgains = real_gains(held)
                hruns = [f"{cls}/{r}" for r in hgains.run]
                hunits = _units(p, inputs, robot, hruns, [str(cls)], held)
                pooled_held = np.asarray(hunits.simulate(kept), float)
                own_held = np.asarray(hunits.simulate(own), float) if better else pooled_held
                min_runs, level = statistics_settings(p.statistics)
                own_ci = hunits.error_interval(own_held, min_runs, level, p.seed)
                pooled_ci = hunits.error_interval(pooled_held, min_runs, level, p.seed)
                entry["heldout"] = {
                    # the units judged (their runs; DRIVE: steps, at most drive_commands of them) and of how many
                    # held-out ones the class has
                    "runs": len(set(hunits.runs)),
                    "available": len(hgains),
                    "real_gain": _r(float(hgains.gain.mean())),
                    "cases": hunits.describe,
                    "class_fit_gain": _r(float(np.nanmean(own_held))),
                    "pooled_fit_gain": _r(float(np.nanmean(pooled_held))),
                    "class_fit_error": _r(hunits.error(own_held)),
                    # 95 % BCa over the class's held-out runs; null below statistics.min_runs runs
                    "class_fit_error_interval": [_r(own_ci[0]), _r(own_ci[1])] if math.isfinite(own_ci[0]) else None,
                    "pooled_fit_error": _r(hunits.error(pooled_held)),
                    "pooled_fit_error_interval": (
                        [_r(pooled_ci[0]), _r(pooled_ci[1])] if math.isfinite(pooled_ci[0]) else None
                    ),
                }
        out[str(cls)] = entry
    return out


def _class_spread(steps: pd.DataFrame | None, cls: str, every: pd.DataFrame, tolerance: float | None) -> dict:
    """A class's spread: the standard deviation of its runs' real gains (``every``: training and held-out; NaN
    below two runs), or where DRIVE's ``steps`` are given, the class's step-to-step repeatability of its gain over
    pairs of steps of similar command (within ``tolerance``), the table's spread over the class's steps alone."""
    if steps is None:
        return {
            "class_spread": _r(float(every.gain.std(ddof=1)) if len(every) > 1 else math.nan),
            "spread_runs": len(every),
        }
    from simpick.compare.steps import gain_repeatability

    sd, pairs = gain_repeatability(steps[steps.terrain_class == cls], tolerance)
    return {
        "class_spread": _r(sd),
        "spread_runs": pairs,
        "spread_basis": f"step-to-step repeatability of its gain over {pairs} pairs of steps of similar command",
    }


def _same_settings(a: dict, b: dict) -> bool:
    """The same settings, a number within the file's rounding (4 significant digits) of the other's."""
    if set(a) != set(b):
        return False
    for k in a:
        x, y = a[k], b[k]
        if isinstance(x, (int, float)) and isinstance(y, (int, float)) and not isinstance(x, bool):
            if not math.isclose(float(x), float(y), rel_tol=1e-3, abs_tol=1e-12):
                return False
        elif x != y:
            return False
    return True


def _mean(values) -> float:
    """The mean of the finite values (NaN where none is)."""
    values = np.asarray(values, float)
    return float(np.nanmean(values)) if np.isfinite(values).any() else math.nan


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


def _write(data: dict, output: str) -> None:
    Path(output).parent.mkdir(parents=True, exist_ok=True)
    Path(output).write_text(yaml.safe_dump(data, sort_keys=False, allow_unicode=True, width=110))
