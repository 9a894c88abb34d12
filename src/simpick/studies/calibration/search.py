"""The Optuna search: a seeded TPE study in a journal file (an interrupted job resumes it), trial 0
the as-configured engine; the job that runs it on the training units under the watchdog, and the job
that evaluates the best parameters found on the held-out units."""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from simpick.errors import InputError
from simpick.simulate.real_settings import RealCaseParams
from simpick.simulate.run import config_hash, stable_seed
from simpick.simulate.watchdog import DEFAULT_TIMEOUT_S, Watchdog, hung_reason
from simpick.studies.calibration.objective import FAILED_UNIT, Units, evaluate
from simpick.studies.calibration.parameters import apply_parameters, configured_values, parameter_space
from simpick.studies.calibration.settings import CalibrationBudget, EvaluateSettings, SearchSettings
from simpick.studies.calibration.split import read_split
from simpick.tables import write_csv


def _storage(path: Path):
    from optuna.storages import JournalStorage
    from optuna.storages.journal import JournalFileBackend

    path.parent.mkdir(parents=True, exist_ok=True)
    return JournalStorage(JournalFileBackend(str(path)))


def study_name(params: dict, settings: dict, train: list[str] | None = None) -> str:
    """Names the study by everything its trials depend on except the budget, so raising
    ``n_trials`` continues the same study and any other edit starts a new one: the parameters,
    the settings (with the job's code version, ``settings["code"]``: an edit to the objective or
    an engine) and the training units (a new split): a trial of other units or code is never reused.
    ``params``: a real-data case's (:class:`simpick.simulate.real_settings.RealCaseParams`), hashed as given."""
    case = RealCaseParams.model_validate(params)
    keyed = {"params": params, "settings": {k: v for k, v in settings.items() if k != "n_trials"}}
    if train is not None:
        keyed["train"] = sorted(str(u) for u in train)
    return f"{case.engine}-{case.terrain_class}-{config_hash(keyed)}"


def calibrate(
    units: Units, train: list[str], urdf: str, params: dict, settings: dict, journal: Path, evaluate_fn=evaluate
) -> tuple[dict, pd.DataFrame, dict]:
    """Run (or resume) the study until ``n_trials`` (of the settings) trials have finished.

    ``params`` and ``settings`` stay mappings here: the DRIVE calibration (simpick.studies.calibration.steps)
    calls this with settings of its own form, and the study's name is their hash (:func:`study_name`). The
    workflow's job (:func:`calibrate_job`) has checked them against its models first.

    Returns the best parameter values, the trial history and run facts (trials run now, wall s).
    """
    import optuna  # only a search imports it (the report reads this module's constants)
    from optuna.trial import TrialState

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    engine = RealCaseParams.model_validate(params).engine
    # the search's budget, typed: both callers' settings hold its fields beside their own (above)
    budget = CalibrationBudget.model_validate({k: settings[k] for k in CalibrationBudget.model_fields if k in settings})
    space = parameter_space(engine, budget.bounds.get(engine))
    if not space:
        raise InputError(f"engines.{engine}", "declares no calibratable parameters")
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
    while done(study) < budget.n_trials:
        sampler = optuna.samplers.TPESampler(
            seed=stable_seed(budget.seed, seed_key, done(study)),
            n_startup_trials=budget.startup_trials,
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
    history = history.sort_values("trial").head(budget.n_trials).reset_index(drop=True)
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
    # settings["code"], the job's code version (scripts/calibrate.py adds it), only names the Optuna study
    # (calibrate's study_name): no field of the job's own
    case = RealCaseParams.model_validate(params)
    s = SearchSettings.model_validate({k: v for k, v in settings.items() if k != "code"})
    split = read_split(inputs["split"], case.terrain_class)
    units = Units(s.source, inputs.get("segments"), inputs.get("logs"), case.terrain_class)
    train = [u for u in split[split.set == "train"].unit if u in units.ids]
    if not train:
        raise InputError(inputs["split"], f"class {case.terrain_class!r} has no training units")
    journal = Path(outputs["best"]).with_name("optuna.journal")
    as_configured = configured_values(params, parameter_space(case.engine, s.bounds.get(case.engine)))

    def write_best(status: str, reasons: list[str], values: dict, facts: dict) -> None:
        Path(outputs["best"]).write_text(
            yaml.safe_dump(
                {
                    "engine": case.engine,
                    "terrain_class": case.terrain_class,
                    "status": status,
                    "reasons": reasons,
                    "parameters": values,
                    "as_configured": as_configured,
                    "train_units": train,
                    "n_trials": s.n_trials,
                    "journal": str(journal),
                    **facts,
                },
                sort_keys=False,
            )
        )

    def hung() -> None:
        reason = hung_reason(timeout)
        print(f"simpick: calibrate {case.engine} {case.terrain_class}: {reason}", file=sys.stderr)
        write_csv(pd.DataFrame(columns=["trial", "as_configured", "objective"]), outputs["trials"])
        write_best("failed", [reason], {}, {"best_trial": None, "best_objective": None, "configured_objective": None})

    with Watchdog(timeout, hung):
        # calibrate() is shared with the DRIVE calibration (simpick.studies.calibration.steps), whose settings
        # are its own: it takes the mappings, and names the Optuna study by their hash
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
    case, s = RealCaseParams.model_validate(params), EvaluateSettings.model_validate(settings)
    split = read_split(inputs["split"], case.terrain_class)
    units = Units(s.source, inputs.get("segments"), inputs.get("logs"), case.terrain_class)
    best = yaml.safe_load(Path(inputs["best"]).read_text())
    sets = dict(zip(split.unit, split.set))
    ids = [u for u in split.unit if u in units.ids]
    rows: list[dict] = []
    key = {"engine": case.engine, "terrain_class": case.terrain_class}
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
            f"simpick: evaluate {case.engine} {case.terrain_class}: {len(left)} unit(s) not done: "
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
