"""Calibrate each engine on some real runs, judge it on the others.

A user tunes an engine's contact parameters to their robot and ground before trusting it. This
module asks: after the best calibration each engine allows, how close does it get on runs it
has not seen, and at what cost (after Acosta, Posa et al. 2022, who did this for cube tosses)?

- **Split** (:func:`split_runs`): per terrain class the real *runs* (never windows or segments of
  one run) are shuffled with a seeded generator and a fraction goes to the test set; the split
  is a result file (``results/calibration/<source>/split.csv``).
- **Parameters**: each engine adapter (and reference model) declares ``calibratable``, a mapping
  of parameter name to :class:`simpick.engines.base.Calibratable` bounds, each with the reason for
  its bounds. ``friction`` is the terrain class's Coulomb coefficient (``real_data.classes.<c>.
  friction``); any other name is one of the adapter's own settings (``engines.<e>.<name>``).
  :func:`apply_parameters` is the only place that knows this, and it knows no engine by name.
- **Objective** (:func:`objective_terms`): on every training unit, the low-passed yaw-rate error
  (rad/s) and the low-passed longitudinal-acceleration error (m/s^2), each divided by its scale
  from the config (``calibration.scales``) and summed; the objective is the mean over the
  training units. A unit is a committed segment (the real table keeps only its window means: a
  constant command's low-passed signal is its mean, so the errors are |mean sim - mean real|) or,
  for the full replay, a run (RMS of the difference of the two signals after the same 2 Hz
  low-pass, :func:`simpick.compare.realmetrics.aligned_rmse`, as the replay metrics). A unit the engine
  fails (health check) counts :data:`FAILED_UNIT` instead.
  Constant offsets no engine can model (an accelerometer bias, a slope's g sin(angle))
  are removed from the longitudinal-acceleration term: on a replayed run it is the RMS of the
  low-passed difference less its mean over the run; on a committed segment, whose real table
  keeps only window means under a constant command (where the true acceleration is zero, so the
  mean *is* the offset), nothing is left of it and the segment's objective is its yaw-rate term
  alone. The yaw rate, and so the yaw-rate gain (yaw rate / commanded turn), then carries the
  objective's weight on turning units; ``error_accel_x`` is reported as measured (offset
  included) beside it. A unit that turns under a steady command adds its steady yaw-rate gain error
  over ``scales.yaw_rate_gain`` (:func:`objective_terms`).
- **Optimiser**: Optuna's TPE sampler with a journal file as storage
  (``results/calibration/<source>/<engine>/<class>/optuna.journal``): an interrupted job resumes
  the finished trials from the file and runs only the missing ones. The sampler is seeded per
  trial from (seed, number of finished trials), so a resumed calibration proposes exactly what
  an uninterrupted one would have. Trial 0 is always the as-configured engine, so the best
  parameters are never worse on the training units than the configured ones.

Everything here drives the engines as the segments and replay sources' jobs do
(:mod:`simpick.simulate.real`), the same paths as the study's real-data comparison.
"""

from __future__ import annotations

import copy
import json
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from simpick.compare import realmetrics
from simpick.compare.real import compared_window, real_imu_at, trace_rate
from simpick.compare.realmetrics import mean_ci, paired_test, statistics_settings
from simpick.coulomb import wheel_separation_multiplier
from simpick.engines import get_engine
from simpick.errors import InputError
from simpick.inputs.robot import load_robot
from simpick.real.logs import read_canonical
from simpick.real.turning import turning_windows
from simpick.simulate.real import class_segments, replay_log, simulate_segment
from simpick.simulate.run import config_hash, stable_seed
from simpick.simulate.watchdog import DEFAULT_TIMEOUT_S, Watchdog, hung_reason
from simpick.tables import write_csv

FAILED_UNIT = 10.0  # objective counted for a unit the engine fails (10x the scale of either error)
SPLIT_COLUMNS = ("terrain_class", "run", "unit", "set")


# --- the split --------------------------------------------------------------------------------------


def split_runs(units: pd.DataFrame, test_fraction: float, seed: int) -> pd.DataFrame:
    """Per terrain class, the runs shuffled by a seeded generator; ``round(test_fraction x n)``
    of them (at least 1, at most n - 1) are test runs, the rest training runs. A class with a
    single run keeps it for training (nothing to test on). Every unit of a run goes where its
    run goes. ``units`` needs columns terrain_class, run, unit.

    With a boolean column ``turns`` (a run turns under a steady command), the runs that
    turn and those that do not are split apart, each as above: the turning parameters are then
    calibrated on turning runs and judged on others, where a class has two or more. (Unstratified,
    the seed put every turning run of sandy loam in the test set and its training runs drove
    straight: nothing constrained the friction ratio.)"""
    rows = []
    stratified = "turns" in units
    for cls in sorted(units.terrain_class.unique()):
        g = units[units.terrain_class == cls]
        if stratified:
            turning = g.groupby(g.run.astype(str))["turns"].any()
            strata = [(("turning",), sorted(turning.index[turning])), (("straight",), sorted(turning.index[~turning]))]
            # a stratum of one run cannot be split: such runs are split together (a class of one turning
            # and one straight run keeps a test run, as unstratified)
            single = sorted(r for _, runs in strata if len(runs) == 1 for r in runs)
            strata = [s for s in strata if len(s[1]) > 1] + ([(("rest",), single)] if single else [])
        else:
            strata = [((), sorted(str(r) for r in g.run.unique()))]
        test = set()
        for key, runs in strata:
            order = np.random.default_rng(stable_seed(int(seed), "calibration-split", cls, *key)).permutation(len(runs))
            n_test = 0 if len(runs) < 2 else min(max(int(round(test_fraction * len(runs))), 1), len(runs) - 1)
            test |= {runs[i] for i in order[:n_test]}
        for r in g.sort_values(["run", "unit"]).itertuples():
            rows.append(
                {
                    "terrain_class": cls,
                    "run": str(r.run),
                    "unit": r.unit,
                    "set": "test" if str(r.run) in test else "train",
                }
            )
    return pd.DataFrame(rows, columns=list(SPLIT_COLUMNS))


def run_turns(log, track: float, steady: dict, duration: float | None) -> bool:
    """Whether a replayed run has a steady-command turning window within the compared seconds."""
    windows = steady_windows(log, track, steady)
    return bool(len(windows) and (duration is None or (windows.t_end <= float(duration)).any()))


def split_job(
    units: list[dict],
    test_fraction: float,
    seed: int,
    output: str,
    logs: list[str] | None = None,
    strata: dict | None = None,
) -> None:
    """Rule calibration_split. ``units`` rows are (class, run, unit[, turns]); with ``logs`` (a
    replay) each run's ``turns`` is read from its log under ``strata`` (track, steady, duration)."""
    columns = ["terrain_class", "run", "unit", "turns"]
    frame = pd.DataFrame(units, columns=columns[: len(units[0])] if units else columns[:3]).astype({"run": str})
    if logs:
        turns = {}
        for path in logs:
            log = read_canonical(path)
            key = (str(log.meta["terrain_class"]).lower(), str(log.meta["run_id"]))
            turns[key] = run_turns(log, float(strata["track"]), strata["steady"], strata.get("duration"))
        frame["turns"] = [turns.get((c, r), False) for c, r in zip(frame.terrain_class, frame.run)]
    write_csv(split_runs(frame, test_fraction, seed), output)


def read_split(path: str, terrain_class: str) -> pd.DataFrame:
    split = pd.read_csv(path, dtype={"run": str, "unit": str})
    return split[split.terrain_class == terrain_class]


# --- parameters ---------------------------------------------------------------------------------------


def parameter_space(engine: str, overrides: dict | None = None) -> dict:
    """name -> Calibratable: what the adapter declares, with the config's bounds overrides."""
    space = dict(get_engine(engine).calibratable)
    for name, bounds in (overrides or {}).items():
        if name not in space:
            raise InputError(
                f"calibration.bounds.{engine}.{name}",
                f"{engine} has no calibratable parameter {name!r}",
                f"use one of {sorted(space)}",
            )
        space[name] = replace(space[name], low=float(bounds[0]), high=float(bounds[1]))
    return space


def configured_values(params: dict, space: dict) -> dict:
    """The as-configured value of each parameter (clipped into its bounds)."""
    engine = params["engine"]
    settings = get_engine(engine).settings_model.of(params.get("engine_settings"), engine)
    out = {}
    for name, p in space.items():
        value = float(params["class"]["friction"]) if name == "friction" else getattr(settings, name)
        out[name] = min(max(value, p.low), p.high)
    return out


def apply_parameters(params: dict, values: dict) -> dict:
    """A copy of a real-data job's params with the parameter values in place: ``friction`` is the
    class's ground friction, every other name an engine setting."""
    out = copy.deepcopy(params)
    for name, value in values.items():
        if name == "friction":
            out["class"] = dict(out["class"], friction=float(value))
        else:
            out["engine_settings"] = dict(out.get("engine_settings") or {}, **{name: float(value)})
    return out


# --- one unit's errors ----------------------------------------------------------------------------------


def segment_errors(seg: pd.Series, urdf: str, params: dict, window: float | None) -> dict:
    """A committed segment: |mean sim - mean real| of yaw rate and longitudinal acceleration over
    the first ``window`` seconds of its compared window (all of it when None)."""
    seg = seg.copy()
    if window is not None:
        seg["duration"] = min(float(seg.duration), float(window))
    frame, meta = simulate_segment(seg, urdf, params)
    out = {"status": meta["health"]["status"], "wall_time": float(meta["wall_time"]), "steps": int(meta["steps"])}
    if out["status"] == "ok":
        w = compared_window(pd.DataFrame(frame), meta)
        out["error_yaw_rate"] = abs(float(w.wz.mean()) - float(seg.angular_z_mean))
        out["error_accel_x"] = abs(float(w.ax.mean()) - float(seg.linear_x_mean))
        out["error_accel_x_offset_free"] = 0.0  # a window mean less its mean (module docstring)
        if np.isfinite(float(seg.yaw_rate_gain)):  # a turning segment: the gain under its constant command
            kinematic = (float(seg.v_right) - float(seg.v_left)) / float(params["robot"]["track"])
            out.update(_gain_figures(float(w.wz.mean()) / kinematic, float(seg.yaw_rate_gain), 1))
    return out


def _gain_figures(sim_gain: float, real_gain: float, windows: int) -> dict:
    """A unit's steady yaw-rate gain, simulated and real (mean yaw rate over the kinematic one under a
    steady command), their absolute difference and the number of steady windows behind them."""
    return {
        "yaw_rate_gain_sim": sim_gain,
        "yaw_rate_gain_real": real_gain,
        "gain_error": abs(sim_gain - real_gain),
        "gain_windows": windows,
    }


def steady_windows(log, track: float, steady: dict) -> pd.DataFrame:
    """The log's steady-command turning windows (simpick.real.turning.turning_windows with the real
    turning analysis' ``steady`` settings: window, settle, tolerance, min_turn)."""
    return turning_windows(log, track, **{k: float(v) for k, v in steady.items()})


def replay_errors(log, urdf: str, params: dict, duration: float | None, steady: dict | None = None) -> dict:
    """A replayed run: RMS difference of the low-passed yaw rate and longitudinal acceleration
    (the replay metrics' rmse_yaw_rate and rmse_ax, over the first ``duration`` seconds), and the
    steady yaw-rate gain, simulated and real, in its steady-command turning windows."""
    frame, meta = replay_log(log, urdf, params, duration=duration)
    out = {"status": meta["health"]["status"], "wall_time": float(meta["wall_time"]), "steps": int(meta["steps"])}
    if out["status"] == "ok":
        sim = pd.DataFrame(frame)
        rate = trace_rate(sim, meta)
        real = real_imu_at(log.imu, sim.time.to_numpy(), ("wz", "ax"))
        for col, key in (("wz", "error_yaw_rate"), ("ax", "error_accel_x")):
            out[key] = realmetrics.aligned_rmse(real[col], sim[col].to_numpy(), rate)
        out["error_accel_x_offset_free"] = realmetrics.aligned_rmse(
            real["ax"], sim["ax"].to_numpy(), rate, offset_free=True
        )
        # the steady yaw-rate gain: in the log's steady-command turning windows inside the
        # compared seconds (simpick.real.turning.turning_windows, the real turning figure's windows), the
        # mean yaw rate over the kinematic one, simulated and real, averaged over the run's windows.
        # Not a fit over every turning sample: the real yaw rate lags a changed command by ~0.3 s, which
        # would mix the response's lag into the gain of a run with many short turns
        windows = steady_windows(log, float(params["robot"]["track"]), steady or {})
        windows = windows[windows.t_end <= float(sim.time.iloc[-1])]
        if len(windows):
            t, wz = sim.time.to_numpy(), sim.wz.to_numpy()
            sim_gains = [
                float(wz[(t >= w.t_start) & (t < w.t_end)].mean()) / w.w_kinematic for w in windows.itertuples()
            ]
            out.update(_gain_figures(float(np.mean(sim_gains)), float(windows.yaw_rate_gain.mean()), len(windows)))
    return out


def objective_terms(row: dict, scales: dict) -> float:
    """One unit's contribution to the objective (dimensionless): the yaw-rate error and the
    offset-free longitudinal-acceleration error (module docstring), each over its scale, plus, on a
    unit that turns under a steady command, the steady yaw-rate gain error over
    ``scales['yaw_rate_gain']`` (the gain gets a weight of its own, not only through the
    yaw rate, whose RMS over a whole run is dominated by transients)."""
    if row.get("status") != "ok" or not np.isfinite(row.get("error_yaw_rate", np.nan)):
        return FAILED_UNIT
    accel = row.get("error_accel_x_offset_free", row["error_accel_x"])
    total = row["error_yaw_rate"] / scales["yaw_rate"] + accel / scales["accel_x"]
    gain = row.get("gain_error", math.nan)
    if scales.get("yaw_rate_gain") and gain is not None and np.isfinite(gain):
        total += gain / scales["yaw_rate_gain"]
    return total


class Units:
    """The real units of one terrain class (segments or replayed runs), by unit id."""

    def __init__(
        self,
        source: str,
        segments_csv: str | None = None,
        logs: list[str] | None = None,
        terrain_class: str | None = None,
    ):
        self.source = source
        if source == "segments":
            self.segments = class_segments(segments_csv, terrain_class)
            self.ids = [str(s) for s in self.segments.index]
            self.runs = {str(s): str(self.segments.loc[s, "run"]) for s in self.segments.index}
        else:
            self.logs = {}
            for path in logs or []:
                log = read_canonical(path)
                self.logs[str(log.meta["run_id"])] = log
            self.ids = sorted(self.logs)
            self.runs = {r: r for r in self.ids}

    def errors(self, unit: str, urdf: str, params: dict, settings: dict) -> dict:
        if self.source == "segments":
            return segment_errors(self.segments.loc[unit], urdf, params, settings.get("segment_seconds"))
        return replay_errors(self.logs[unit], urdf, params, settings.get("replay_seconds"), settings.get("steady"))


def evaluate(units: Units, ids: list[str], urdf: str, params: dict, settings: dict) -> list[dict]:
    rows = []
    for unit in ids:
        row = {"unit": unit, "run": units.runs[unit], **units.errors(unit, urdf, params, settings)}
        row["objective"] = objective_terms(row, settings["scales"])
        rows.append(row)
    return rows


# --- the optimisation ---------------------------------------------------------------------------------


def _storage(path: Path):
    from optuna.storages import JournalStorage
    from optuna.storages.journal import JournalFileBackend

    path.parent.mkdir(parents=True, exist_ok=True)
    return JournalStorage(JournalFileBackend(str(path)))


def study_name(params: dict, settings: dict, train: list[str] | None = None) -> str:
    """Names the study by everything its trials depend on except the budget, so raising
    ``n_trials`` continues the same study and any other edit starts a new one: the parameters,
    the settings (with the job's code version, ``settings["code"]``: an edit to the objective or
    an engine) and the training units (a new split): a trial of other units or code is never reused."""
    keyed = {"params": params, "settings": {k: v for k, v in settings.items() if k != "n_trials"}}
    if train is not None:
        keyed["train"] = sorted(str(u) for u in train)
    return f"{params['engine']}-{params['terrain_class']}-{config_hash(keyed)}"


def calibrate(
    units: Units, train: list[str], urdf: str, params: dict, settings: dict, journal: Path, evaluate_fn=evaluate
) -> tuple[dict, pd.DataFrame, dict]:
    """Run (or resume) the study until ``settings["n_trials"]`` trials have finished.

    Returns the best parameter values, the trial history and run facts (trials run now, wall s).
    """
    import optuna  # only a search imports it (the report reads this module's constants)
    from optuna.trial import TrialState

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    space = parameter_space(params["engine"], (settings.get("bounds") or {}).get(params["engine"]))
    if not space:
        raise InputError(f"engines.{params['engine']}", "declares no calibratable parameters")
    storage = _storage(journal)
    name = study_name(params, settings, train)
    # the sampler's seed: from the parameters and settings alone, so an edit to unrelated code starts a
    # new study (its name) that proposes the same trials as the old one did
    seed_key = study_name(params, {k: v for k, v in settings.items() if k != "code"})
    study = optuna.create_study(study_name=name, storage=storage, direction="minimize", load_if_exists=True)
    # a trial left RUNNING by a killed job never finishes: mark it failed (one job owns a study)
    for t in study.get_trials(deepcopy=False, states=(TrialState.RUNNING,)):
        storage.set_trial_state_values(t._trial_id, TrialState.FAIL)
    done = lambda s: len(s.get_trials(deepcopy=False, states=(TrialState.COMPLETE,)))  # noqa: E731
    if done(study) == 0 and not study.get_trials(deepcopy=False, states=(TrialState.WAITING,)):
        study.enqueue_trial(configured_values(params, space), user_attrs={"as_configured": True})

    def objective(trial):
        values = {}
        for pname, p in space.items():
            values[pname] = trial.suggest_float(pname, p.low, p.high, log=p.log)
        start = time.perf_counter()
        rows = evaluate_fn(units, train, urdf, apply_parameters(params, values), settings)
        trial.set_user_attr("units", json.dumps(rows, default=float))
        trial.set_user_attr("wall_time", time.perf_counter() - start)
        trial.set_user_attr("n_failed", sum(r["status"] != "ok" for r in rows))
        for key in ("error_yaw_rate", "error_accel_x"):
            vals = [r[key] for r in rows if r["status"] == "ok"]
            trial.set_user_attr(key, float(np.mean(vals)) if vals else float("nan"))
        return float(np.mean([r["objective"] for r in rows]))

    ran, start = 0, time.perf_counter()
    while done(study) < int(settings["n_trials"]):
        sampler = optuna.samplers.TPESampler(
            seed=stable_seed(int(settings["seed"]), seed_key, done(study)),
            n_startup_trials=int(settings["startup_trials"]),
        )
        study = optuna.load_study(study_name=name, storage=storage, sampler=sampler)
        study.optimize(objective, n_trials=1)
        ran += 1
    complete = study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,))
    history = pd.DataFrame(
        [
            {
                "trial": t.number,
                "as_configured": bool(t.user_attrs.get("as_configured", False)),
                **{f"param_{k}": v for k, v in t.params.items()},
                "objective": t.value,
                "error_yaw_rate": t.user_attrs.get("error_yaw_rate"),
                "error_accel_x": t.user_attrs.get("error_accel_x"),
                "n_failed": t.user_attrs.get("n_failed"),
                "wall_time": t.user_attrs.get("wall_time"),
            }
            for t in complete
        ]
    )
    # the best of the first n_trials finished trials (a larger earlier budget may have left more)
    history = history.sort_values("trial").head(int(settings["n_trials"])).reset_index(drop=True)
    best = history.loc[history.objective.idxmin()]
    values = {k: float(best[f"param_{k}"]) for k in space}
    facts = {
        "study": name,
        "trials_run_now": ran,
        "wall_time_now": time.perf_counter() - start,
        "best_trial": int(best.trial),
        "best_objective": float(best.objective),
        "configured_objective": float(history.loc[history.as_configured, "objective"].iloc[0])
        if history.as_configured.any()
        else None,
        "bounds": {k: {"low": p.low, "high": p.high, "log": p.log, "why": p.why} for k, p in space.items()},
    }
    return values, history, facts


def calibrate_job(
    inputs: dict, params: dict, settings: dict, outputs: dict, timeout: float = DEFAULT_TIMEOUT_S
) -> None:
    """One engine x terrain class: calibrate on the training units; write best.yaml and trials.csv.

    Under the watchdog (``timeout`` s of wall time, simpick.simulate.watchdog.runtime_timeout of the rule's
    runtime): a study still running then writes best.yaml with ``status: failed`` and the reason
    and no parameters (the journal keeps the finished trials, so a rerun resumes), and the
    evaluation reports every calibrated unit of the class as failed instead of inventing a best."""
    split = read_split(inputs["split"], params["terrain_class"])
    units = Units(settings["source"], inputs.get("segments"), inputs.get("logs"), params["terrain_class"])
    train = [u for u in split[split.set == "train"].unit if u in units.ids]
    if not train:
        raise InputError(inputs["split"], f"class {params['terrain_class']!r} has no training units")
    journal = Path(outputs["best"]).with_name("optuna.journal")
    as_configured = configured_values(
        params, parameter_space(params["engine"], (settings.get("bounds") or {}).get(params["engine"]))
    )

    def write_best(status: str, reasons: list[str], values: dict, facts: dict) -> None:
        Path(outputs["best"]).write_text(
            yaml.safe_dump(
                {
                    "engine": params["engine"],
                    "terrain_class": params["terrain_class"],
                    "status": status,
                    "reasons": reasons,
                    "parameters": values,
                    "as_configured": as_configured,
                    "train_units": train,
                    "n_trials": int(settings["n_trials"]),
                    "journal": str(journal),
                    **facts,
                },
                sort_keys=False,
            )
        )

    def hung() -> None:
        reason = hung_reason(timeout)
        print(f"simpick: calibrate {params['engine']} {params['terrain_class']}: {reason}", file=sys.stderr)
        write_csv(pd.DataFrame(columns=["trial", "as_configured", "objective"]), outputs["trials"])
        write_best("failed", [reason], {}, {"best_trial": None, "best_objective": None, "configured_objective": None})

    with Watchdog(timeout, hung):
        values, history, facts = calibrate(units, train, inputs["urdf"], params, settings, journal)
    write_csv(history, outputs["trials"])
    write_best("ok", [], values, facts)


def _failed_rows(units: Units, ids: list[str], reason: str) -> list[dict]:
    """Units not evaluated (the watchdog stopped the job, or there is no calibrated best): failed,
    with the reason, counted like any failed unit (objective FAILED_UNIT, n_failed_*)."""
    return [
        {
            "unit": u,
            "run": units.runs[u],
            "status": "failed",
            "reasons": reason,
            "error_yaw_rate": math.nan,
            "error_accel_x": math.nan,
            "objective": FAILED_UNIT,
        }
        for u in ids
    ]


def evaluate_job(inputs: dict, params: dict, settings: dict, output: str, timeout: float = DEFAULT_TIMEOUT_S) -> None:
    """Every unit of the class (train and test), as configured and as calibrated: one row each.

    Under the watchdog (``timeout``, as :func:`calibrate_job`): a job still running then writes
    the rows it has and every unit not yet evaluated as failed with the reason."""
    split = read_split(inputs["split"], params["terrain_class"])
    units = Units(settings["source"], inputs.get("segments"), inputs.get("logs"), params["terrain_class"])
    best = yaml.safe_load(Path(inputs["best"]).read_text())
    sets = dict(zip(split.unit, split.set))
    ids = [u for u in split.unit if u in units.ids]
    rows: list[dict] = []
    key = {"engine": params["engine"], "terrain_class": params["terrain_class"]}
    plan = [("configured", params)]
    if best.get("status", "ok") == "ok":
        plan.append(("calibrated", apply_parameters(params, best["parameters"])))
    else:  # the calibration failed (hung): nothing to evaluate as calibrated
        why = "no calibrated parameters: " + "; ".join(best.get("reasons") or ["the calibration failed"])
        rows += [{**key, "set": sets[r["unit"]], "variant": "calibrated", **r} for r in _failed_rows(units, ids, why)]

    def hung() -> None:
        done = list(rows)
        seen = {(r["variant"], r["unit"]) for r in done}
        left = [
            {**key, "set": sets[r["unit"]], "variant": variant, **r}
            for variant, _ in plan
            for r in _failed_rows(units, [u for u in ids if (variant, u) not in seen], hung_reason(timeout))
        ]
        print(
            f"simpick: evaluate {params['engine']} {params['terrain_class']}: {len(left)} unit(s) not done: "
            f"{hung_reason(timeout)}",
            file=sys.stderr,
        )
        write_csv(pd.DataFrame(done + left), output)

    with Watchdog(timeout, hung):
        for variant, p in plan:
            for unit in ids:
                row = evaluate(units, [unit], inputs["urdf"], p, settings)[0]
                rows.append({**key, "set": sets[row["unit"]], "variant": variant, **row})
    write_csv(pd.DataFrame(rows), output)


# --- the summary ----------------------------------------------------------------------------------------


def _stats(statistics: dict | None) -> tuple[int, float]:
    """(min_runs, level) of the validated ``statistics`` settings (simpick.plan: Plan.statistics_params)."""
    return statistics_settings(statistics)


def _ci(values, runs, min_runs: int, level: float) -> tuple[float, float, float]:
    """(mean, low, high) over runs (a run's units averaged first): the real-data statistics'
    rule (simpick.compare.realmetrics.mean_ci), so no interval below ``min_runs`` runs."""
    values = np.asarray(values, float)
    if len(values) == 0:
        return (math.nan, math.nan, math.nan)
    mean, low, high, _ = mean_ci(values, runs, min_runs, level)
    return mean, low, high


POOLED = "all classes"  # the summary's pooled rows: every class's units, each class calibrated on its own


def _change_verdict(test: dict, min_runs: int) -> str:
    """A change judged by the paired sign-flip test over runs (simpick.compare.realmetrics.paired_test of
    calibrated against configured): improved, worse, no clear difference, or too few runs."""
    if test["verdict"] == "too few runs":
        return f"too few runs ({test['n_runs']} < {min_runs})"
    return {"a": "worse", "b": "improved"}.get(test["verdict"], test["verdict"])


def _summary_row(g: pd.DataFrame, runs: pd.Series, min_runs: int, level: float) -> dict:
    """One engine and set over the units in ``g`` (as configured and as calibrated), with intervals
    over the independent runs named by ``runs`` (one key per unit), and the change (calibrated
    minus configured, per unit) judged by a paired test over runs."""
    conf = g[g.variant == "configured"].set_index("unit")
    cal = g[g.variant == "calibrated"].set_index("unit")
    run_of = dict(zip(g.unit, runs))
    row = {
        "n_units": len(conf),
        "n_runs": len({run_of[u] for u in conf.index}),
        "n_failed_configured": int((conf.status != "ok").sum()),
        "n_failed_calibrated": int((cal.status != "ok").sum()),
    }
    for variant, frame in (("configured", conf), ("calibrated", cal)):
        for fig in ("objective", "error_yaw_rate", "error_accel_x"):
            ok = frame[fig].notna()
            mean, lo, hi = _ci(frame.loc[ok, fig].to_numpy(), [run_of[u] for u in frame.index[ok]], min_runs, level)
            row.update({f"{fig}_{variant}": mean, f"{fig}_{variant}_low": lo, f"{fig}_{variant}_high": hi})
    common = conf.index.intersection(cal.index)
    keys = [run_of[u] for u in common]
    test = paired_test(
        cal.loc[common, "objective"].to_numpy(), conf.loc[common, "objective"].to_numpy(), keys, min_runs, level
    )
    mean = test["mean"]
    row.update(
        {
            "change": mean,
            "change_low": test["low"],
            "change_high": test["high"],
            "change_p": test["p_value"],
            "change_verdict": _change_verdict(test, min_runs),
        }
    )
    return row


def _normalised(frame: pd.DataFrame) -> pd.DataFrame:
    """Each class's objectives divided by that class's mean configured objective over every model
    (per set): a change pooled across classes is then a share of the class's own error, and models
    stay comparable (the objective of snow is about ten times asphalt's on the committed segments;
    unnormalised, snow would decide every pooled figure)."""
    conf = frame[frame.variant == "configured"]
    scale = conf.groupby(["terrain_class", "set"])["objective"].mean()
    keys = pd.MultiIndex.from_arrays([frame.terrain_class, frame.set])
    return frame.assign(objective=frame.objective.to_numpy() / scale.reindex(keys).to_numpy())


def _winners(out: pd.DataFrame, evals: pd.DataFrame, min_runs: int, level: float) -> pd.DataFrame:
    """Per class (and pooled) and set: the model with the smallest mean objective as configured and
    as calibrated, named only where a paired test over runs separates it from the runner-up
    (otherwise ``no separation`` or ``too few runs``); ranks only from ``min_runs`` runs on."""
    for variant in ("configured", "calibrated"):
        out[f"rank_{variant}"] = pd.array([pd.NA] * len(out), dtype="Int64")
        out[f"winner_{variant}"] = ""
    for (cls, set_), g in out.groupby(["terrain_class", "set"]):
        enough = g[g.n_runs >= min_runs]
        for variant in ("configured", "calibrated"):
            col = f"objective_{variant}"
            out.loc[enough.index, f"rank_{variant}"] = enough[col].rank(method="min").astype("Int64")
            ranked = g.dropna(subset=[col]).sort_values(col)
            if len(ranked) < 2:
                verdict = ranked.engine.iloc[0] if len(ranked) == 1 and len(enough) == 1 else "–"
            elif len(enough) < len(g):
                verdict = f"too few runs ({int(g.n_runs.min())} < {min_runs})"
            else:
                best, second = ranked.engine.iloc[0], ranked.engine.iloc[1]
                units = evals[evals.set == set_]
                if cls != POOLED:
                    units = units[units.terrain_class == cls]
                else:  # normalised by each class's configured objective, as the pooled rows are
                    units = _normalised(units)
                units = units[units.variant == variant]
                units = units.assign(
                    key=units.terrain_class + "/" + units.unit.astype(str),
                    runkey=units.terrain_class + "/" + units.run.astype(str),
                )
                wide = units.pivot_table(index="key", columns="engine", values="objective")
                if best not in wide or second not in wide:
                    out.loc[g.index, f"winner_{variant}"] = "no paired comparison"
                    continue
                run_of = units.drop_duplicates("key").set_index("key").runkey.reindex(wide.index)
                t = paired_test(wide[best].to_numpy(), wide[second].to_numpy(), run_of.to_numpy(), min_runs, level)
                verdict = best if t["verdict"] == "b" else f"{best} and {second} not separated (p {t['p_value']:.2g})"
            out.loc[g.index, f"winner_{variant}"] = verdict
    return out


def summarise(evals: pd.DataFrame, best: dict[tuple[str, str], dict], statistics: dict | None = None) -> pd.DataFrame:
    """Per class, engine, set and variant: mean objective and errors with BCa intervals over runs
    (none below ``statistics.min_runs`` runs), the change against as configured judged by a paired
    sign-flip test over runs (``change_verdict``: improved, worse, no clear difference, too few
    runs), and the models' rank and winner in the class as configured and as calibrated (none below
    ``min_runs`` runs; a winner only where the paired test separates it from the runner-up).
    Then the same over every class pooled (terrain_class ``POOLED``), on per-class normalised
    objectives (``normalised`` true: each class's objective over its mean as configured over every
    model, so a change is a share of each class's own error): a class has only a few runs (BorealTC 4-8, so 2-4
    test runs), too few for an interval, while the runs of all classes together may be enough; a
    run is named by class and run there, since run numbers repeat across classes."""
    min_runs, level = _stats(statistics)
    rows = []
    for (cls, engine, set_), g in evals.groupby(["terrain_class", "engine", "set"], sort=True):
        row = {
            "terrain_class": cls,
            "engine": engine,
            "set": set_,
            "normalised": False,
            **_summary_row(g, g.run, min_runs, level),
        }
        params = best.get((engine, cls), {})
        row["parameters"] = "; ".join(f"{k}={v:.4g}" for k, v in (params.get("parameters") or {}).items())
        row["parameters_configured"] = "; ".join(f"{k}={v:.4g}" for k, v in (params.get("as_configured") or {}).items())
        rows.append(row)
    if evals.terrain_class.nunique() > 1:
        for (engine, set_), g in _normalised(evals).groupby(["engine", "set"], sort=True):
            # units are unique within a class only: pool under class-qualified names
            g = g.assign(unit=g.terrain_class + "/" + g.unit.astype(str))
            rows.append(
                {
                    "terrain_class": POOLED,
                    "engine": engine,
                    "set": set_,
                    "normalised": True,
                    **_summary_row(g, g.unit.str.rsplit("/", n=1).str[0] + "/" + g.run.astype(str), min_runs, level),
                    "parameters": "",
                    "parameters_configured": "",
                }
            )
    out = pd.DataFrame(rows)
    if out.empty:
        return out
    return _winners(out, evals, min_runs, level)


def summary_job(
    evals: list[str],
    bests: list[str],
    split: str,
    outputs: dict,
    statistics: dict | None = None,
    turning: dict | None = None,
    urdf: str | None = None,
) -> None:
    """Rule calibration_summary: the summary, the units, the parameters found and, with ``turning``
    (the robot's track, the engines, calibration.target), the held-out turning table and the
    target's verdict; the wheels' geometric separation comes from ``urdf``."""
    frame = pd.concat([pd.read_csv(p, dtype={"run": str, "unit": str}) for p in evals], ignore_index=True)
    best = {}
    for path in bests:
        b = yaml.safe_load(Path(path).read_text())
        best[(b["engine"], b["terrain_class"])] = b
    summary = summarise(frame, best, statistics)
    write_csv(summary, outputs["summary"])
    write_csv(frame, outputs["units"])
    params = pd.DataFrame(
        [
            {
                "engine": e,
                "terrain_class": c,
                "parameter": k,
                "calibrated": v,
                "as_configured": b["as_configured"].get(k),
                "best_trial": b["best_trial"],
                "n_trials": b["n_trials"],
                "train_objective_configured": b["configured_objective"],
                "train_objective_calibrated": b["best_objective"],
            }
            for (e, c), b in sorted(best.items())
            for k, v in b["parameters"].items()
        ]
    )
    write_csv(params, outputs["parameters"])
    if "turning" in outputs:
        separation = load_robot(urdf).track  # the controller's wheel_separation (geometric)
        table = turning_table(frame, best, float(turning["track"]), separation, turning["target"], statistics)
        write_csv(table, outputs["turning"])
        write_csv(
            target_table(frame, table, list(turning["engines"]), turning["target"], statistics), outputs["target"]
        )


# --- turning on held-out runs ---------------------------------------------------------------------------

TARGET_POOL = "target classes"  # turning.csv's pooled rows: the held-out runs of calibration.target.classes
TURNING_COLUMNS = [
    "terrain_class",
    "engine",
    "variant",
    "n_runs",
    "gain_real",
    "gain_sim",
    "gain_ratio",
    "within_tolerance",
    "gain_error",
    "gain_error_low",
    "gain_error_high",
    "gain_error_min",
    "gain_error_max",
    "error_yaw_rate",
    "separation_multiplier",
    "separation_multiplier_real",
    "parameters",
]
TARGET_COLUMNS = [
    "engine",
    "is_engine",
    "n_runs",
    "error_calibrated",
    "error_configured",
    "error_reference",
    "vs_configured",
    "vs_configured_low",
    "vs_configured_high",
    "p_vs_configured",
    "vs_reference",
    "vs_reference_low",
    "vs_reference_high",
    "p_vs_reference",
    "lower_than_configured",
    "lower_than_reference",
    "worst_gain_ratio",
    "classes_off_gain",
    "gain_within_tolerance",
    "meets",
    "best",
]


def _per_run(frame: pd.DataFrame, column: str) -> pd.Series:
    """A figure averaged within each real run first (a run's segments are not independent), keyed
    by class/run (run numbers repeat across classes)."""
    ok = frame[frame.status == "ok"].dropna(subset=[column])
    return ok.groupby(ok.terrain_class + "/" + ok.run.astype(str))[column].mean()


def turning_table(
    evals: pd.DataFrame,
    best: dict[tuple[str, str], dict],
    track: float,
    separation: float,
    target: dict,
    statistics: dict | None = None,
) -> pd.DataFrame:
    """Per terrain class, model and variant, on the held-out (test) runs that turn: the real and the
    simulated yaw-rate gain (each averaged within a run, then over runs), their ratio and whether it
    is within ``target['gain_tolerance']``, the gain error |sim - real| with its interval over runs
    (none below ``statistics.min_runs``; the range over runs always), the yaw-rate error, and the
    ``wheel_separation_multiplier`` a ROS diff_drive_controller user would set to turn this model
    (and the real robot) as commanded (simpick.coulomb.wheel_separation_multiplier). Then the same
    over the held-out runs of ``target['classes']`` together (``TARGET_POOL``)."""
    min_runs, level = _stats(statistics)
    test = evals[evals.set == "test"]
    if "gain_error" not in test:
        return pd.DataFrame(columns=TURNING_COLUMNS)
    tol = float(target["gain_tolerance"])
    classes = sorted(test.terrain_class.unique())
    pools = [(cls, test[test.terrain_class == cls]) for cls in classes]
    pools.append((TARGET_POOL, test[test.terrain_class.isin(target.get("classes") or classes)]))
    rows = []
    for cls, frame in pools:
        for (engine, variant), g in frame.groupby(["engine", "variant"], sort=True):
            gain_error, real, sim = (_per_run(g, c) for c in ("gain_error", "yaw_rate_gain_real", "yaw_rate_gain_sim"))
            if gain_error.empty:
                continue
            mean, low, high = _ci(gain_error.to_numpy(), list(gain_error.index), min_runs, level)
            g_real, g_sim = float(real.mean()), float(sim.mean())
            ratio = g_sim / g_real if g_real else math.nan
            params = best.get((engine, cls), {}) if variant == "calibrated" else {}
            rows.append(
                {
                    "terrain_class": cls,
                    "engine": engine,
                    "variant": variant,
                    "n_runs": int(gain_error.size),
                    "gain_real": g_real,
                    "gain_sim": g_sim,
                    "gain_ratio": ratio,
                    "within_tolerance": bool(abs(ratio - 1) <= tol) if cls != TARGET_POOL else math.nan,
                    "gain_error": mean,
                    "gain_error_low": low,
                    "gain_error_high": high,
                    "gain_error_min": float(gain_error.min()),
                    "gain_error_max": float(gain_error.max()),
                    "error_yaw_rate": float(_per_run(g, "error_yaw_rate").mean()),
                    "separation_multiplier": wheel_separation_multiplier(g_sim, track, separation),
                    "separation_multiplier_real": wheel_separation_multiplier(g_real, track, separation),
                    "parameters": "; ".join(f"{k}={v:.4g}" for k, v in (params.get("parameters") or {}).items()),
                }
            )
    return pd.DataFrame(rows, columns=TURNING_COLUMNS)


def target_table(
    evals: pd.DataFrame, turning: pd.DataFrame, engines: list[str], target: dict, statistics: dict | None = None
) -> pd.DataFrame:
    """The turning target (calibration.target), per calibrated model, on the held-out runs of ``target['classes']``
    together: its per-run yaw-rate error as calibrated against (a) its own as configured and (b) the
    ``target['reference']`` model as configured (rigid Coulomb mechanics), each by the paired
    sign-flip test over runs at ``statistics.level``; and per class whether its mean calibrated gain
    is within ``target['gain_tolerance']`` of the real robot's. ``meets`` when all three hold; ``best``
    marks the engine (a simulator, not a reference model) with the lowest mean calibrated error."""
    min_runs, level = _stats(statistics)
    classes = target.get("classes") or sorted(evals.terrain_class.unique())
    test = evals[(evals.set == "test") & evals.terrain_class.isin(classes)]
    if test.empty:
        return pd.DataFrame(columns=TARGET_COLUMNS)
    test = test.assign(
        key=test.terrain_class + "/" + test.unit.astype(str), runkey=test.terrain_class + "/" + test.run.astype(str)
    )
    ok = test[test.status == "ok"]
    wide = ok.pivot_table(index="key", columns=["engine", "variant"], values="error_yaw_rate")
    run_of = test.drop_duplicates("key").set_index("key").runkey
    reference = (target["reference"], "configured")
    rows = []
    for engine in sorted(test.engine.unique()):
        if (engine, "calibrated") not in wide:
            continue
        cal = wide[(engine, "calibrated")]
        row = {
            "engine": engine,
            "is_engine": engine in engines,
            "n_runs": int(run_of.reindex(cal.dropna().index).nunique()),
            "error_calibrated": float(
                _per_run(ok[(ok.engine == engine) & (ok.variant == "calibrated")], "error_yaw_rate").mean()
            ),
        }
        for name, col in (("configured", (engine, "configured")), ("reference", reference)):
            other = wide[col] if col in wide else pd.Series(math.nan, index=wide.index)
            row[f"error_{name}"] = float(
                _per_run(ok[(ok.engine == col[0]) & (ok.variant == col[1])], "error_yaw_rate").mean()
            )
            t = paired_test(cal.to_numpy(), other.to_numpy(), run_of.reindex(wide.index).to_numpy(), min_runs, level)
            row.update(
                {
                    f"vs_{name}": t["mean"],
                    f"vs_{name}_low": t["low"],
                    f"vs_{name}_high": t["high"],
                    f"p_vs_{name}": t["p_value"],
                    f"lower_than_{name}": t["verdict"] == "b",
                }
            )
        gains = turning[
            (turning.engine == engine) & (turning.variant == "calibrated") & turning.terrain_class.isin(classes)
        ]
        off = [
            c if c in set(gains.terrain_class) else f"{c} (no held-out turning run)"
            for c in classes
            if c not in set(gains.terrain_class)
            or not bool(gains.loc[gains.terrain_class == c, "within_tolerance"].iloc[0])
        ]
        row["worst_gain_ratio"] = (
            float(gains.gain_ratio.iloc[(gains.gain_ratio - 1).abs().argmax()]) if len(gains) else math.nan
        )
        row["classes_off_gain"] = "; ".join(off)
        row["gain_within_tolerance"] = not off
        row["meets"] = bool(row["lower_than_configured"] and row["lower_than_reference"] and not off)
        rows.append(row)
    out = pd.DataFrame(rows, columns=TARGET_COLUMNS)
    sims = out[out.is_engine & out.error_calibrated.notna()]
    out["best"] = False
    if len(sims):
        out.loc[sims.error_calibrated.idxmin(), "best"] = True
    return out
