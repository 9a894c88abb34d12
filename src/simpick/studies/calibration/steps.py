"""Calibration on step units (:mod:`simpick.real.steps`, DRIVE's steps): each engine's turning parameters
fitted on some steps, judged on held-out ones.

Everything but the units is the project's calibration (:mod:`simpick.studies.calibration`): the seeded split
(:func:`~simpick.studies.calibration.split.split_runs`, stratified into turning and straight), each adapter's
declared parameters and bounds, the Optuna search with its journal
(:func:`~simpick.studies.calibration.search.calibrate`, trial 0 the as-configured engine) and the one
statistics rule of its summary (:func:`~simpick.studies.calibration.summary.summarise`: BCa intervals over
independent units, paired sign-flip tests, none below ``statistics.min_runs``).

The units are steps (the chosen subset, ``drive_replay.every`` / ``max_steps_per_session``), each its
own replicate as in the verdict (:mod:`simpick.score.steps`: DRIVE draws every step's command
independently), split within each terrain class, each replayed from the reader's wheels table as the
replay jobs do (:func:`simpick.simulate.steps.replay_step`). A step's objective: its steady yaw-rate error over
``calibration.scales.yaw_rate`` plus its steady speed error against the measured (lidar-ICP) speed over
:data:`SPEED_SCALE` (the longitudinal acceleration of the BorealTC objective is zero in a steady step: DRIVE
measures the speed itself). ``error_yaw_rate`` is reported as such; ``error_accel_x`` holds the speed error
(m/s) so the project's summary carries it (its column name is the project's; the unit is m/s here).

Each engine's calibrated gain on the held-out turning steps gives the equivalent ROS
``wheel_separation_multiplier`` for the robot (:func:`simpick.coulomb.wheel_separation_multiplier`: DRIVE's
kinematic baseline as the track, the robot description's wheel separation), beside the real robot's.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import yaml
from pydantic import Field

from simpick.coulomb import wheel_separation_multiplier
from simpick.errors import InputError
from simpick.inputs.robot import load_robot
from simpick.params import JobParams
from simpick.real.settings import StepReplay, TerrainClass
from simpick.real.steps import MIN_TURN
from simpick.score.settings import Statistics
from simpick.simulate.settings import SimulationParams
from simpick.simulate.steps import read_wheels, replay_step, select_steps, step_samples
from simpick.simulate.watchdog import Watchdog, hung_reason
from simpick.studies.calibration.objective import FAILED_UNIT
from simpick.studies.calibration.parameters import apply_parameters, configured_values, parameter_space
from simpick.studies.calibration.search import calibrate
from simpick.studies.calibration.settings import CalibrationBudget, CalibrationScales, CalibrationSplit
from simpick.studies.calibration.split import split_runs
from simpick.studies.calibration.summary import summarise
from simpick.tables import write_csv

SPEED_SCALE = 0.2  # m/s: about the as-configured engines' median steady speed error on the Warthog's steps
# (fixed-rocker Warthog, asphalt: 0.28-0.42 m/s), so the speed and the yaw-rate terms count alike


class StepSearchSettings(CalibrationBudget, CalibrationSplit):
    """What the step calibration reads of the calibration section: the search's budget, seed and this model's
    bounds, the held-out share, and the objective's scales (its yaw-rate term's; the speed's is
    :data:`SPEED_SCALE`)."""

    source: str = Field(description="the units' source kind (step units)")
    scales: CalibrationScales = Field(description="the objective's scales")


class StepCalibrateParams(JobParams):
    """What rule drive_calibrate's job reads: the model and the terrain class, the model's simulation settings,
    every class's ground (a step's own class is the case table's), how the steps are replayed, and the
    search's settings."""

    engine: str
    terrain_class: str
    case: SimulationParams
    classes: dict[str, TerrainClass]
    replay: StepReplay
    calibration: StepSearchSettings


class StepUnits:
    """The steps of one terrain class (every session of it), by case id, with the wheels table they are
    driven by: what :func:`simpick.studies.calibration.search.calibrate` evaluates."""

    def __init__(self, wheels: pd.DataFrame, cases: pd.DataFrame, warmup: float):
        self.wheels = wheels
        self.cases = cases.set_index("case")
        self.ids = list(self.cases.index)
        self.runs = {c: c for c in self.ids}  # every step its own replicate (module doc)
        self.warmup = warmup

    def errors(self, unit: str, urdf: str, params: dict, settings: dict) -> dict:
        case = self.cases.loc[unit].copy()
        case["case"] = unit
        samples = step_samples(self.wheels, case.session, int(case.step))
        _, row = replay_step(samples, case, urdf, params, self.warmup)
        ok = row["status"] == "ok"
        wz, v = row["sim_yaw_rate"], row["sim_v"]
        return {
            "status": row["status"],
            "reasons": "; ".join(row["_meta"]["health"]["reasons"]),
            "sim_yaw_rate": wz,
            "sim_v": v,
            "error_yaw_rate": abs(wz - case.yaw_rate) if ok else math.nan,
            "error_accel_x": abs(v - case.v_icp) if ok else math.nan,
        }


def evaluate(units: StepUnits, ids: list[str], urdf: str, params: dict, settings: dict) -> list[dict]:
    """Each step's errors and objective (module doc); a failed step counts
    :data:`simpick.studies.calibration.objective.FAILED_UNIT`."""
    rows = []
    for unit in ids:
        row = {"unit": unit, "run": units.runs[unit], **units.errors(unit, urdf, params, settings)}
        row["objective"] = (
            row["error_yaw_rate"] / settings["scales"]["yaw_rate"] + row["error_accel_x"] / SPEED_SCALE
            if row["status"] == "ok"
            else FAILED_UNIT
        )
        rows.append(row)
    return rows


def class_units(cases: pd.DataFrame, steps: pd.DataFrame, terrain: str, replay: StepReplay) -> pd.DataFrame:
    """The chosen steps of one terrain class with their turning flag (the split's strata)."""
    chosen = select_steps(cases[cases.terrain_class == terrain], replay.every, replay.max_steps_per_session)
    kin = steps.set_index(["session", "step"]).w_kin
    turns = [abs(kin.get((s, k), 0.0)) > MIN_TURN for s, k in zip(chosen.session, chosen.step)]
    return chosen.assign(turns=turns)


def split(units: pd.DataFrame, test_fraction: float, seed: int) -> pd.DataFrame:
    table = units.assign(run=units.case, unit=units.case)[["terrain_class", "run", "unit", "turns"]]
    return split_runs(table, test_fraction, seed)


def calibrate_job(inputs: dict, params: dict, outputs: dict, timeout: float) -> None:
    """One engine x one terrain class. Splits the class's chosen steps, calibrates on
    the training steps and evaluates the as-configured and the calibrated engine on every step; writes the
    split, best.yaml, the trials and the evaluated units (CSV). ``params``: :class:`StepCalibrateParams`."""
    p = StepCalibrateParams.model_validate(params)
    terrain, engine = p.terrain_class, p.engine
    # The search's settings and the real-data case stay the mappings the rule passed (canonical: numbers as
    # floats): calibrate() names the Optuna study, and seeds its sampler, by their hash, so a typed dump (an int
    # seed) would start another study with other trials. What this job reads itself is read from ``p``.
    settings = dict(params["calibration"])  # as given: hashed (above)
    cases, steps = pd.read_csv(inputs["cases"]), pd.read_csv(inputs["steps"])
    units_table = class_units(cases, steps, terrain, p.replay)
    if units_table.empty:
        raise InputError(inputs["cases"], f"has no chosen steps on {terrain!r}", "choose drive_replay.every smaller")
    wheels = read_wheels(inputs["wheels"])
    parts = split(units_table, p.calibration.test_fraction, p.calibration.seed)
    write_csv(parts, outputs["split"])
    wheels = wheels[wheels.session.isin(set(units_table.session))]
    units = StepUnits(wheels, units_table, p.replay.warmup)
    train = list(parts[parts.set == "train"].unit)
    test = list(parts[parts.set == "test"].unit)
    # a real-data case's params (simpick.simulate.real_settings.RealCaseParams), as given: hashed (above)
    case_params = dict(params["case"], terrain_class=terrain, **{"class": params["classes"][terrain]})  # as given
    journal = Path(outputs["best"]).with_name("optuna.journal")
    Path(outputs["best"]).parent.mkdir(parents=True, exist_ok=True)

    def hung() -> None:
        reason = hung_reason(timeout)
        Path(outputs["best"]).write_text(
            yaml.safe_dump(
                {
                    "engine": engine,
                    "terrain_class": terrain,
                    "status": "failed",
                    "reasons": [reason],
                    "parameters": {},
                }
            )
        )
        write_csv(pd.DataFrame(columns=["trial", "objective"]), outputs["trials"])
        write_csv(pd.DataFrame(columns=["unit", "status"]), outputs["evals"])

    with Watchdog(timeout, hung):
        values, history, facts = calibrate(units, train, inputs["urdf"], case_params, settings, journal, evaluate)
        space = parameter_space(engine, p.calibration.bounds.get(engine))
        configured = configured_values(case_params, space)
        rows = []
        for variant, chosen in (("configured", configured), ("calibrated", values)):
            for set_, ids in (("train", train), ("test", test)):
                for row in evaluate(units, ids, inputs["urdf"], apply_parameters(case_params, chosen), settings):
                    rows.append({"terrain_class": terrain, "engine": engine, "variant": variant, "set": set_, **row})
    best = {
        "engine": engine,
        "terrain_class": terrain,
        "status": "ok",
        "reasons": [],
        "parameters": values,
        "as_configured": configured,
        "train_units": train,
        "n_trials": p.calibration.n_trials,
        **facts,
    }
    Path(outputs["best"]).write_text(yaml.safe_dump(best, sort_keys=False))
    write_csv(history, outputs["trials"])
    write_csv(pd.DataFrame(rows), outputs["evals"])


class StepSummaryParams(JobParams):
    """What rule drive_calibration's job reads: the statistics of its summary (intervals, verdicts)."""

    statistics: Statistics


TURNING_COLUMNS = [
    "terrain_class",
    "engine",
    "variant",
    "held_out_turning_steps",
    "gain_real",
    "gain_sim",
    "multiplier_real",
    "multiplier_sim",
]


def turning_table(
    evals: pd.DataFrame, cases: pd.DataFrame, steps: pd.DataFrame, track: float, separation: float
) -> pd.DataFrame:
    """Per class, engine and variant, on the held-out turning steps: the median real and simulated gain and
    the equivalent wheel_separation_multiplier of each (``track``: the kinematic baseline the commands use;
    ``separation``: the wheels' geometric separation)."""
    kin = steps.set_index(["session", "step"]).w_kin
    real = cases.set_index("case")
    rows = []
    test = evals[(evals.set == "test") & (evals.status == "ok")]
    for (cls, engine, variant), g in test.groupby(["terrain_class", "engine", "variant"], sort=True):
        c = real.loc[g.unit]
        w = np.array([kin.get((s, k), np.nan) for s, k in zip(c.session, c.step)])
        turning = np.abs(w) > MIN_TURN
        if not turning.any():
            continue
        gain_real = float(np.median(c.yaw_rate.to_numpy()[turning] / w[turning]))
        gain_sim = float(np.median(g.sim_yaw_rate.to_numpy()[turning] / w[turning]))
        rows.append(
            {
                "terrain_class": cls,
                "engine": engine,
                "variant": variant,
                "held_out_turning_steps": int(turning.sum()),
                "gain_real": gain_real,
                "gain_sim": gain_sim,
                "multiplier_real": wheel_separation_multiplier(gain_real, track, separation),
                "multiplier_sim": wheel_separation_multiplier(gain_sim, track, separation),
            }
        )
    return pd.DataFrame(rows, columns=TURNING_COLUMNS)


def summary_job(inputs: dict, params: dict, outputs: dict) -> None:
    """Rule drive_calibration_summary: the project's calibration summary of every engine x class, the
    parameters found, and the held-out turning table with the multipliers. ``params``: :class:`StepSummaryParams`."""
    p = StepSummaryParams.model_validate(params)
    evals = pd.concat([pd.read_csv(p, dtype={"run": str, "unit": str}) for p in inputs["evals"]], ignore_index=True)
    best = {}
    for path in inputs["bests"]:
        b = yaml.safe_load(Path(path).read_text())
        best[(b["engine"], b["terrain_class"])] = b
    write_csv(summarise(evals, best, p.statistics.model_dump()), outputs["summary"])
    separation = load_robot(inputs["urdf"]).track
    sessions = pd.read_csv(inputs["sessions"])
    track = float(sessions[sessions.kept.astype(bool)].wheel_baseline.median())  # the baseline DRIVE's gains use
    table = turning_table(evals, pd.read_csv(inputs["cases"]), pd.read_csv(inputs["steps"]), track, separation)
    write_csv(table, outputs["turning"])
