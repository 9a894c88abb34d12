"""The simulators' results: each simulator as shipped and as tuned, against mechanics and the real robot, beside
the engines; and the subjects of the simulators' decision tree and weighted table.

The job reads what the study wrote for every model (the validation summary and gains, the verdict source's
per-test table, the lab's real-time factor and the CPU load) and re-labels it by simulator: a profile's model
is ``<simulator>-<variant>`` or, where its settings are its engine's, the engine (``profile_results``).
Nothing is simulated here and no weight is read.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
import pandas as pd
import yaml
from pydantic import Field

from simpick.engines.catalog import load_catalog
from simpick.engines.simulators import VARIANTS, model_name
from simpick.params import JobParams, NonNegative
from simpick.score.equivalence import outcomes_table
from simpick.score.mechanics import mechanics_table
from simpick.score.scoring import FACT_KEYS
from simpick.score.settings import Statistics, Verdict
from simpick.score.simulator_classes import per_class_table
from simpick.score.simulator_settings import fit_parts, fitted_parameters, read_fits
from simpick.score.split import read_split
from simpick.score.verdict import METRICS, NO_SPEED, per_run_values, read_per_test
from simpick.tables import write_csv

TABLE_COLUMNS = [
    "simulator",
    "label",
    "variant",
    "model",
    "engine",
    "status",
    "mechanics",
    "mechanics_failed",
    "mechanics_cases",
    "mechanics_note",
    "gain_flat",
    "gain_flat_min",
    "gain_flat_max",
    "gain_coulomb",
    "gain_error",
    "gain_error_low",
    "gain_error_high",
    "gain_outcome",
    "gain_diff_to_best",
    "heading_error",
    "heading_outcome",
    "speed_error",
    "speed_outcome",
    "n_runs",
    "runs_failed",
    "settings_file",
    # the model that opens as it is (rule simulator_models), where the profile's simulator has a model writer, and
    # what the report says beside its link where no loader of the simulator runs here ("fields checked; ...")
    "model_file",
    "model_note",
    # judged on the held-out runs only (the calibration's split: no run of them reached any fit), every row alike
    "heldout_gain_error",
    "heldout_gain_error_low",
    "heldout_gain_error_high",
    "heldout_runs",
    "real_spread",
    "within_spread",
    "heldout_heading_error",
    "heldout_speed_error",  # DRIVE: against the lidar-measured speed (the committed segments measure none)
    # the same gain error on the training runs of the classes the calibration fits (the runs its objective
    # covers): beside the held-out one it tells a fit that missed the runs it was fitted on from one that does
    # not carry over; a calibrated row is never above its tuned row here (a fit that gains nothing is not kept)
    "train_gain_error",
    "calibrated_settings",
    # the calibrated row's fitted settings with their 95 % intervals (or why the runs cannot fix one), and the
    # contact's and the actuator's share of what the fit gained on its training runs
    "fitted_parameters",
    "fit_parts",
    "turning_settable",
    "mechanics_own",
]


def _gains(gains: pd.DataFrame, model: str) -> tuple[float, float, float]:
    """Mean, min and max isotropic yaw-rate gain of a model's validation turns on flat ground."""
    own = gains[gains.engine == model] if "engine" in gains else gains.iloc[0:0]
    means = pd.to_numeric(own[["left_mean", "right_mean"]].stack(), errors="coerce").dropna()
    lows = pd.to_numeric(own[["left_min", "right_min"]].stack(), errors="coerce").dropna()
    highs = pd.to_numeric(own[["left_max", "right_max"]].stack(), errors="coerce").dropna()
    if means.empty:
        return (math.nan, math.nan, math.nan)
    return float(means.mean()), float(lows.min()), float(highs.max())


def _first(frame: pd.DataFrame, **where) -> pd.Series | None:
    mask = np.ones(len(frame), bool)
    for k, v in where.items():
        mask &= (frame[k] == v).to_numpy()
    rows = frame[mask]
    return rows.iloc[0] if len(rows) else None


class DriveJudging(JobParams):
    """How DRIVE's steps are judged where the profiles replayed them (simpick.sources.drive.compare_settings)."""

    tolerance: float = Field(description="the repeatability margin of DRIVE's steps")
    unit: Literal["step", "session"] = Field(description="the verdict's unit of pairing")


class SimulatorsParams(JobParams):
    """What rule simulators' job reads: which profiles ran and what each reads, the engines beside them, the
    statistics and the verdict's margins (no weight); DRIVE's judging where the study replays DRIVE."""

    profile_results: dict[str, str] = Field(description="profile -> the model whose results it reads")
    engines: list[str]
    simulators: list[str] = Field(description="the simulators whose profiles ran")
    left_out: dict[str, str] = Field(description="simulator -> why its profiles did not run")
    settings_files: dict[str, str] = Field(description="profile -> its settings files' stem")
    model_files: dict[str, str] = Field(
        description="profile -> the path of its model that opens as it is (rule simulator_models), where it has one"
    )
    model_notes: dict[str, str] = Field(
        default_factory=dict,
        description="profile -> the words beside its model's link where the simulator's own loader does not run here",
    )
    statistics: Statistics
    seed: Annotated[int, Field(ge=0, lt=2**32)]
    verdict: Verdict
    drive: DriveJudging | None = Field(None, description="DRIVE's judging; None: the study has no DRIVE folder")
    calibrated_left_out: str = Field("", description="why the study runs no calibrated profile (empty: it does)")


class SimulatorScoresParams(JobParams):
    """What rule simulator_scores' job reads: the run simulators and the weights of the paper's table."""

    simulators: list[str]
    weights: dict[str, NonNegative]


class SimulatorTreeParams(JobParams):
    """What rule simulator_tree's job reads: the run simulators, and whether the study has a verdict."""

    simulators: list[str]
    verdict: bool = Field(description="the study has real data of its robot: the leaves carry its outcomes")


def simulators_job(inputs: dict, params: dict, outputs: dict) -> None:
    """results/simulators/: table.csv (a row per simulator and profile), outcomes.csv and mechanics.csv (every
    engine and profile on the verdict's real data, relabelled), and the tree's subjects (tree/): one per
    simulator with its tuned row's physics and its 2026 facts."""
    p = SimulatorsParams.model_validate(params)
    catalog = load_catalog(inputs["catalog"])
    results, engines, run = dict(p.profile_results), list(p.engines), list(p.simulators)
    left_out, files = dict(p.left_out), dict(p.settings_files)
    # simpick.score.equivalence and simpick.score.steps read these as mappings
    verdict, statistics = p.verdict.model_dump(mode="json"), p.statistics.model_dump(mode="json")
    summary = pd.read_csv(inputs["validation"])
    gains = pd.read_csv(inputs["gains"])

    # every model the real data compare: the engines and the profiles that simulate (aliases read their engine)
    models = engines + [m for m in dict.fromkeys(results.values()) if m not in engines]
    mechanics = mechanics_table(summary, models)
    outcomes, tests = pd.DataFrame(), None
    if inputs.get("per_test") and Path(inputs["per_test"]).is_file():
        tests = read_per_test(inputs["per_test"])
        walls = {metric: per_run_values(tests, metric) for metric in METRICS}
        outcomes = outcomes_table(
            walls,
            tests,
            models,
            METRICS,
            mechanics,
            verdict,
            statistics,
            p.seed,
            {"speed_error": NO_SPEED},
        )
    elif inputs.get("drive_errors") and Path(inputs["drive_errors"]).is_file() and p.drive is not None:
        # DRIVE's steps, judged as rule drive_compare judges the engines (its repeatability margin, paired by
        # step), engines and profiles together; every terrain pooled
        from simpick.score import steps as step_units
        from simpick.score.equivalence import pooled

        errors = pd.read_csv(inputs["drive_errors"])
        table = step_units.outcomes(
            errors,
            pd.read_csv(inputs["drive_steps"]),
            [m for m in models if m in set(errors.engine)],
            verdict,
            p.drive.tolerance,
            summary,
            p.drive.unit,
            statistics,
            p.seed,
        )
        outcomes = pooled(table).drop(columns=["paired_by"], errors="ignore")
    write_csv(mechanics, outputs["mechanics"])
    write_csv(outcomes, outputs["outcomes"])

    fits = read_fits(inputs)
    # the classes the calibration fits (its target): the training column is each row's error on the runs the fit
    # was fitted on, so that a calibrated row's training error is the fit's objective and the tuned row's beside it
    # is on the same runs
    fitted = sorted({str(c) for f in fits.values() for c in ((f.get("fit") or {}).get("classes") or [])})
    if tests is None and len(outcomes) and p.drive is not None:
        spread = drive_spread(inputs, p.verdict, p.drive.tolerance)
        heldout = _heldout_steps(inputs, spread, statistics, p.seed, fitted)
    else:
        heldout = _heldout(inputs, tests if len(outcomes) else None, verdict, statistics, p.seed, fitted)
    rows = []
    for name, sim in catalog.simulators.items():
        for variant in VARIANTS:
            profile = model_name(name, variant)
            base = {"simulator": name, "label": sim.label, "variant": variant, "engine": sim.engine or ""}
            if name not in run:
                rows.append(dict(base, model="", status=f"not run: {left_out.get(name, 'not selected')}"))
                continue
            if profile not in results:
                why = p.calibrated_left_out if variant == "calibrated" and p.calibrated_left_out else ""
                rows.append(
                    dict(base, model="", status=f"not run: {why or 'variant not selected (simulators.variants)'}")
                )
                continue
            model = results[profile]
            m = _first(mechanics, engine=model)
            row = dict(base, model=model, status="run" if model == profile else f"run (the {model} engine's results)")
            if m is not None:
                row.update({k: m[k] for k in ("mechanics", "mechanics_failed", "mechanics_cases", "mechanics_note")})
            row["gain_flat"], row["gain_flat_min"], row["gain_flat_max"] = _gains(gains, model)
            analytic = pd.to_numeric(
                gains[gains.engine == model].get("analytic", pd.Series(dtype=float)), errors="coerce"
            )
            row["gain_coulomb"] = float(analytic.dropna().iloc[0]) if analytic.notna().any() else math.nan
            for metric, prefix in (("gain_error", "gain"), ("heading_error", "heading"), ("speed_error", "speed")):
                o = _first(outcomes, metric=metric, engine=model) if len(outcomes) else None
                if o is None:
                    continue
                if prefix == "gain":
                    row.update(
                        gain_error=o["mean"],
                        gain_error_low=o["low"],
                        gain_error_high=o["high"],
                        gain_outcome=o["outcome"],
                        gain_diff_to_best=o["diff_to_best"],
                        n_runs=o["n_runs"],
                        runs_failed=o["runs_failed"],
                    )
                else:
                    row[f"{prefix}_error"], row[f"{prefix}_outcome"] = o["mean"], o["outcome"]
            row["settings_file"] = files.get(profile, "")
            row["model_file"] = p.model_files.get(profile, "")
            row["model_note"] = p.model_notes.get(profile, "")
            row.update(heldout(model))
            row.update(_calibration_columns(fits.get(name), variant, row, summary, results, name))
            rows.append(row)
    write_csv(pd.DataFrame(rows, columns=TABLE_COLUMNS), outputs["table"])
    if outputs.get("per_class"):
        write_csv(per_class_table(fits, catalog, p.model_files, p.model_notes), outputs["per_class"])
    _tree_subjects(catalog, run, results, mechanics, outcomes, inputs, outputs)


# a row's held-out columns where nothing was held out (no split, or no real data judged)
NOT_HELD_OUT = dict.fromkeys(
    ("heldout_gain_error", "heldout_gain_error_low", "heldout_gain_error_high", "real_spread"), math.nan
) | {
    "heldout_runs": 0,
    "within_spread": "",
    "heldout_heading_error": math.nan,
    "heldout_speed_error": math.nan,
    "train_gain_error": math.nan,
}


def _heldout(inputs: dict, tests: pd.DataFrame | None, verdict: dict, statistics: dict, seed: int, classes=()):
    """model -> its held-out columns over the verdict's runs (:func:`_judge_heldout`), beside the real robot's
    run-to-run spread of its gain (the verdict's gain margin, over every run)."""
    from simpick.score.equivalence import margin
    from simpick.score.verdict.runs import run_key

    if tests is None or not inputs.get("split") or not Path(inputs["split"]).is_file():
        return lambda model: dict(NOT_HELD_OUT)
    spread, _ = margin(tests, "gain_error", verdict["margins"]["gain_error"])
    ok = tests[tests.status.astype(str) == "ok"] if "status" in tests else tests
    return _judge_heldout(ok, run_key(ok), inputs["split"], spread, statistics, seed, classes)


def drive_spread(inputs: dict, verdict: Verdict, tolerance: float) -> float:
    """The gain error's margin on DRIVE's steps, as rule drive_compare sets it (simpick.score.steps): where the
    verdict bases it on the real robot's spread, the robot's step-to-step repeatability of its gain between
    steps of similar command (``tolerance``); NaN where the margin is not an absolute gain."""
    from simpick.score.steps import gain_margin_spec

    spec, _ = gain_margin_spec(verdict.margins.gain_error, pd.read_csv(inputs["drive_steps"]), tolerance)
    return float(spec["value"]) if spec.get("basis") == "absolute" else math.nan


def _heldout_steps(inputs: dict, spread: float, statistics: dict, seed: int, classes=()):
    """model -> its held-out columns on DRIVE's steps (:func:`_judge_heldout`, each step a unit: DRIVE draws each
    step's command independently), beside the robot's step-to-step repeatability of its gain (``spread``)."""
    if not inputs.get("split") or not Path(inputs["split"]).is_file():
        return lambda model: dict(NOT_HELD_OUT)
    errors = pd.read_csv(inputs["drive_errors"])
    ok = errors[errors.status.astype(str) == "ok"]
    key = ok.terrain_class.astype(str) + "/" + ok.case.astype(str)
    return _judge_heldout(ok, key, inputs["split"], spread, statistics, seed, classes)


def _judge_heldout(
    rows: pd.DataFrame, units: pd.Series, split: str, spread: float, statistics: dict, seed: int, classes=()
):
    """model -> its columns over ``rows`` (a model's errors per real unit, ``units`` their ``class/run`` key): the
    gain error over the split's test units with its BCa interval (NaN below statistics.min_runs units), their
    number, ``spread`` and whether the error is within it, the heading and speed errors over the same units
    (NaN where the data measure none), and the gain error over the training units of ``classes`` (the classes the
    calibration fits; every class where none is given)."""
    from simpick.compare.realmetrics import mean_ci, statistics_settings

    train_runs, test_runs = read_split(split)
    if classes:
        train_runs = [r for r in train_runs if r.split("/", 1)[0] in set(classes)]
    min_runs, level = statistics_settings(statistics)
    rows = rows.assign(unit_key=units.to_numpy(object))
    test, train = rows[rows.unit_key.isin(set(test_runs))], rows[rows.unit_key.isin(set(train_runs))]

    def values(frame: pd.DataFrame, metric: str) -> np.ndarray:
        return pd.to_numeric(frame.get(metric, pd.Series(math.nan, index=frame.index)), errors="coerce").to_numpy(float)

    def mean(frame: pd.DataFrame, metric: str) -> float:
        return mean_ci(values(frame, metric), frame.unit_key.to_numpy(object), 10**9, level, seed)[0]

    def columns(model: str) -> dict:
        own, fitted = test[test.engine == model], train[train.engine == model]
        gain, low, high, n = mean_ci(values(own, "gain_error"), own.unit_key.to_numpy(object), min_runs, level, seed)
        return {
            "heldout_gain_error": gain,
            "heldout_gain_error_low": low,
            "heldout_gain_error_high": high,
            "heldout_runs": n,
            "real_spread": spread,
            "within_spread": bool(gain <= spread) if np.isfinite(gain) and np.isfinite(spread) else "",
            "heldout_heading_error": mean(own, "heading_error"),
            "heldout_speed_error": mean(own, "speed_error"),
            "train_gain_error": mean(fitted, "gain_error"),
        }

    return columns


def _failed_cases(summary: pd.DataFrame, model: str) -> tuple[set[str], int]:
    """(the analytic cases a model fails, how many it ran) in the validation summary."""
    own = summary[
        (summary.engine == model) & (summary.status.astype(str) != "skipped") & (summary.kind != "invariance")
    ]
    from simpick.score.mechanics import _bool

    return set(own.case[~_bool(own.passed)].astype(str)), int(own.case.nunique())


def _calibration_columns(fit: dict | None, variant: str, row: dict, summary, results, simulator) -> dict:
    """A row's calibrated_settings, turning_settable and mechanics_own: for the calibrated row, its validation
    against the mechanics of its own parameters (the yaw-gain cases against the Coulomb gain of its fitted ratio)
    and, where it fails a case its tuned profile passes, that it fits by breaking mechanics."""
    out = {
        "calibrated_settings": "",
        "fitted_parameters": "",
        "fit_parts": "",
        "turning_settable": "",
        "mechanics_own": "",
    }
    if fit is not None:
        out["turning_settable"] = "yes" if fit.get("searchable") else f"no: {fit.get('why_not') or 'not searched'}"
        if variant == "calibrated":
            out["calibrated_settings"] = "; ".join(f"{k}={v}" for k, v in (fit.get("settings") or {}).items())
            out["fitted_parameters"] = fitted_parameters(fit)
            out["fit_parts"] = fit_parts(fit)
    model = row.get("model")
    if not model:
        return out
    failed, n = _failed_cases(summary, model)
    if not n:
        out["mechanics_own"] = "not validated"
        return out
    out["mechanics_own"] = f"passes {n - len(failed)}/{n}"
    tuned = results.get(model_name(simulator, "tuned"))
    if variant == "calibrated" and tuned and tuned != model:
        broken = sorted(failed - _failed_cases(summary, tuned)[0])
        if broken:
            out["mechanics_own"] += f"; breaks mechanics its tuned profile keeps: {', '.join(broken)}"
    return out


def _tree_subjects(catalog, run, results, mechanics, outcomes, inputs, outputs) -> None:
    """The simulators as the decision tree's subjects, each with its tuned row's evidence: the 2026 facts
    (qualitative.yaml), the mechanics gate and the real-data outcomes of that row, and its engine's real-time
    factor and CPU load (the simulator's own overhead is not reproduced). A simulator not run keeps its facts
    and has no physics evidence: the tree's mechanics question finds it not validated."""
    out = Path(outputs["tree_dir"])
    (out / "cpu").mkdir(parents=True, exist_ok=True)
    facts = {}
    for name, sim in catalog.simulators.items():
        q = sim.qualitative.model_dump()
        facts[name] = {k: q[k] for k in FACT_KEYS}  # the facts the paper's rules score
        facts[name]["sources"] = q["sources"]
        facts[name]["label"] = sim.label
    (out / "qualitative.yaml").write_text(yaml.safe_dump(facts, sort_keys=False, allow_unicode=True))

    tuned = {name: results[model_name(name, "tuned")] for name in run if model_name(name, "tuned") in results}
    mech = mechanics[mechanics.engine.isin(tuned.values())].copy()
    mech["engine"] = mech.engine.map({m: s for s, m in tuned.items()})
    write_csv(mech, out / "mechanics.csv")
    validation = pd.read_csv(inputs["validation"])
    validation = validation[validation.engine.isin(tuned.values())].copy()
    validation["engine"] = validation.engine.map({m: s for s, m in tuned.items()})
    write_csv(validation, out / "validation.csv")
    if len(outcomes):
        o = outcomes[outcomes.engine.isin(tuned.values())].copy()
        o["engine"] = o.engine.map({m: s for s, m in tuned.items()})
        o["best"] = o.best.map(lambda b: {m: s for s, m in tuned.items()}.get(b, b))
        o["is_best"] = o.engine == o.best
    else:
        o = outcomes
    write_csv(o, out / "outcomes.csv")

    if inputs.get("imu_errors") and Path(inputs["imu_errors"]).is_file():
        errors = pd.read_csv(inputs["imu_errors"])
        errors = errors[errors.engine.isin(tuned.values())].copy()
        errors["engine"] = errors.engine.map({m: s for s, m in tuned.items()})
        write_csv(errors, out / "imu_errors.csv")
    else:  # no real IMU errors for these simulators (DRIVE measures no IMU statistics): their accuracy unscored
        write_csv(pd.DataFrame(columns=["engine", "quantity", "error"]), out / "imu_errors.csv")
    rtf = pd.read_csv(inputs["rtf"])
    rows = []
    for name in run:
        engine = catalog.simulators[name].engine
        r = rtf[rtf.engine == engine]
        if len(r):
            rows.append(r.iloc[0].to_dict() | {"engine": name})
        cpu = next((Path(f) for f in inputs.get("cpu") or [] if Path(f).stem == engine), None)
        if cpu is not None and cpu.is_file():
            record = json.loads(cpu.read_text())
            record["engine"] = name
            (out / "cpu" / f"{name}.json").write_text(json.dumps(record, indent=1))
    write_csv(pd.DataFrame(rows, columns=rtf.columns), out / "rtf.csv")


def simulator_scores_job(subjects: str, params: dict, outputs: dict) -> None:
    """The paper's scores and weighted table with simulators as rows (simpick.score.jobs.scores_job over the
    subjects' facts, their tuned rows' Eq. 7 errors and their engines' speed and CPU)."""
    from simpick.score.jobs import scores_job

    p = SimulatorScoresParams.model_validate(params)
    folder = Path(subjects)
    scores_job(
        list(p.simulators),
        str(folder / "imu_errors.csv"),
        str(folder / "rtf.csv"),
        sorted(str(p) for p in (folder / "cpu").glob("*.json")),
        str(folder / "qualitative.yaml"),
        dict(p.weights),
        outputs,
    )


def simulator_tree_job(subjects: str, params: dict, table: str, settings: str | None, output: str) -> None:
    """Rule simulator_tree: the decision tree with the run simulators as its leaves (:func:`leaves_tree_job`),
    each leaf naming the profile its answers ask for (simpick.score.profiles.name_profiles, from the simulators'
    table and its settings folder)."""
    import json

    from simpick.score.profiles import name_profiles
    from simpick.score.tree import _read_csv, read_tree

    leaves_tree_job(subjects, params, output)
    frame = _read_csv(table, ("simulator", "label", "variant", "status"), "the simulators' table")
    tree = name_profiles(read_tree(output), frame, settings)
    Path(output).write_text(json.dumps(tree, indent=1, allow_nan=False) + "\n")


def leaves_tree_job(subjects: str, params: dict, output: str) -> None:
    """The decision tree with the run simulators as its leaves (simpick.score.tree over the subjects)."""
    from simpick.score.tree import decision_tree_job

    p = SimulatorTreeParams.model_validate(params)
    folder = Path(subjects)
    inputs = {
        "qualitative": str(folder / "qualitative.yaml"),
        "validation": str(folder / "validation.csv"),
        "rtf": str(folder / "rtf.csv"),
        "cpu": sorted(str(p) for p in (folder / "cpu").glob("*.json")),
    }
    if p.verdict:
        inputs |= {"outcomes": str(folder / "outcomes.csv"), "mechanics": str(folder / "mechanics.csv")}
    decision_tree_job(list(p.simulators), inputs, output)
