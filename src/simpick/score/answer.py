"""The answer a roboticist acts on: one row per engine and one sentence per need.

``answer.csv`` (one row per engine): whether it passes the analytic mechanics (the failed cases
counted by kind), each real-data metric's outcome against the best with the interval of the
difference and the margin (simpick.score.equivalence), how it turns as configured against the
real robot (simulated / real yaw-rate gain; after calibration where it ran), real-time factor, CPU
load, and the paper's weighted total and rank, flagged for every engine that fails mechanics (the
paper's table itself stays exactly the paper's), and the real runs it failed that another engine
completed, with the health reasons. ``answer.yaml``: a sentence per need (closest, the runs an engine
failed, fastest, settings, avoid), each with the figures it rests on (written by
simpick.score.sentences). Every engine is compared on the
runs every compared engine completed (simpick.score.equivalence), and an engine that failed runs the
others completed is never named closest without that said in the same sentence.

:func:`answer_job` writes them, beside the paper's weighted ranking with its interval over runs, the
separation table and the headline, as the first step of the report job (simpick.report.weighing): the work a
weight edit reruns, kept small (no test of the verdict is redone; those are rule ``verdict``'s, which reads no
weight).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import numpy as np
import pandas as pd
import yaml
from pydantic import Field

from simpick.errors import InputError
from simpick.params import JobParams, NonNegative
from simpick.score.equivalence import FAILED_SEPARATOR, pooled
from simpick.score.sentences import (
    RUNS,
    AnswerBasis,
    basis_sentence,
    failed_runs,
    headline,
    sentences,
    units,
)
from simpick.score.settings import Statistics
from simpick.score.verdict import (
    DISCRIMINATION_COLUMNS,
    METRICS,
    SEPARATION_COLUMNS,
    paper_rows,
    ranking,
    read_per_test,
    run_key,
    separation_rows,
)
from simpick.tables import write_csv

ANSWER_COLUMNS = [
    "engine",
    "mechanics",
    "mechanics_failed",
    "mechanics_cases",
    "mechanics_note",
    *[f"{m}_{k}" for m in METRICS for k in ("outcome", "diff", "low", "high", "margin")],
    "gain_ratio",
    "gain_ratio_calibrated",
    "rtf",
    "cpu_average",
    "cpu_intense",
    "paper_total",
    "paper_rank",
    "paper_flag",
    "runs_failed",
    "failed_runs",
]
CALIBRATED_POOL = "target classes"  # simpick.studies.calibration.turning.TARGET_POOL: the held-out runs judged together


def gain_ratios(per_test: pd.DataFrame, engines: list[str]) -> dict[str, float]:
    """engine -> simulated / real yaw-rate gain as configured: each over the engine's healthy
    turning tests, averaged within a run, then over runs (the same runs for both)."""
    need = {"yaw_rate_gain_sim", "yaw_rate_gain_real"}
    if not need <= set(per_test.columns) or per_test.empty:
        return {}
    frame = per_test[per_test.status == "ok"].assign(
        sim=lambda f: pd.to_numeric(f.yaw_rate_gain_sim, errors="coerce"),
        real=lambda f: pd.to_numeric(f.yaw_rate_gain_real, errors="coerce"),
    )
    frame = frame[np.isfinite(frame.sim) & np.isfinite(frame.real)]
    out = {}
    for engine in engines:
        g = frame[frame.engine == engine]
        if g.empty:
            continue
        runs = g.assign(_run=run_key(g)).groupby("_run")[["sim", "real"]].mean()
        real = float(runs.real.mean())
        out[engine] = float(runs.sim.mean()) / real if real else float("nan")
    return out


def calibrated(turning: str | None) -> pd.DataFrame:
    """The calibration's held-out turning rows as calibrated, per engine (empty where it did not run)."""
    if not turning or not Path(turning).is_file():
        return pd.DataFrame(columns=["engine", "gain_ratio", "parameters", "n_runs"])
    frame = pd.read_csv(turning, dtype={"parameters": str}, keep_default_na=False, na_values=[""])
    frame = frame[(frame.terrain_class == CALIBRATED_POOL) & (frame.variant == "calibrated")]
    return frame[["engine", "gain_ratio", "parameters", "n_runs"]].reset_index(drop=True)


def machine_figures(rtf: str, cpu_files: list[str]) -> tuple[dict, dict]:
    """engine -> real-time factor (the lab runs, one robot), and engine -> (CPU load % with one
    robot, with several), from a CPU run that passed its health check (NaN otherwise)."""
    rtf_frame = pd.read_csv(rtf)
    rtfs = dict(zip(rtf_frame.engine, rtf_frame.real_time_factor.astype(float)))
    cpu = {}
    for path in cpu_files:
        c = json.loads(Path(path).read_text())
        ok = (c.get("health") or {}).get("status", "ok") == "ok"
        cpu[c["engine"]] = (
            (float(c["average"]["load_percent"]), float(c["intense"]["load_percent"]))
            if ok
            else (float("nan"), float("nan"))
        )
    return rtfs, cpu


def answer_table(
    outcomes: pd.DataFrame,
    mechanics: pd.DataFrame,
    weighted: pd.DataFrame,
    engines: list[str],
    ratios: dict,
    calibration: pd.DataFrame,
    rtfs: dict,
    cpu: dict,
) -> pd.DataFrame:
    """One row per engine (``ANSWER_COLUMNS``), in the order of the study's engines."""
    mech = mechanics.set_index("engine")
    cal = calibration.set_index("engine").gain_ratio.to_dict() if len(calibration) else {}
    rows = []
    for engine in engines:
        m = mech.loc[engine]
        row = {
            "engine": engine,
            "mechanics": m.mechanics,
            "mechanics_failed": int(m.mechanics_failed),
            "mechanics_cases": int(m.mechanics_cases),
            "mechanics_note": m.mechanics_note,
        }
        for metric in METRICS:
            o = outcomes[(outcomes.metric == metric) & (outcomes.engine == engine)]
            o = o.iloc[0] if len(o) else {}
            row.update(
                {
                    f"{metric}_outcome": o.get("outcome", "not measurable"),
                    f"{metric}_diff": o.get("diff_to_best", float("nan")),
                    f"{metric}_low": o.get("diff_low", float("nan")),
                    f"{metric}_high": o.get("diff_high", float("nan")),
                    f"{metric}_margin": o.get("margin", float("nan")),
                }
            )
        flag = ""
        if m.mechanics == "fail":
            flag = (
                f"fails mechanics ({int(m.mechanics_failed)} of {int(m.mechanics_cases)} cases)"
                if int(m.mechanics_failed)
                else f"fails mechanics ({m.mechanics_note})"
            )
        average, intense = cpu.get(engine, (float("nan"), float("nan")))
        in_table = engine in weighted.index
        row.update(
            {
                "gain_ratio": ratios.get(engine, float("nan")),
                "gain_ratio_calibrated": cal.get(engine, float("nan")),
                "rtf": rtfs.get(engine, float("nan")),
                "cpu_average": average,
                "cpu_intense": intense,
                "paper_total": float(weighted.loc[engine, "total"]) if in_table else float("nan"),
                "paper_rank": int(weighted.loc[engine, "rank"]) if in_table else None,
                "paper_flag": flag,
            }
        )
        lost = failed_runs(outcomes, engine)
        row.update(
            {
                "runs_failed": len(lost),
                "failed_runs": FAILED_SEPARATOR.join(f"{r}: {why}" for r, why in lost),
            }
        )
        rows.append(row)
    return pd.DataFrame(rows, columns=ANSWER_COLUMNS)


def read_outcomes(path: str) -> pd.DataFrame:
    """Every engine against the best per real-data metric, from the comparison the answer rests on: the
    verdict's outcomes.csv or the DRIVE comparison's (its rows over every terrain:
    simpick.score.equivalence.pooled). A table that is neither stops here, naming what it lacks."""
    frame = pooled(pd.read_csv(path))
    missing = [c for c in ("metric", "engine", "outcome", "is_best", "mean", "n_runs") if c not in frame]
    if missing:
        raise InputError(path, f"not an outcomes table: columns {missing} are missing", "rerun the rule that writes it")
    if frame.duplicated(["metric", "engine"]).any():
        raise InputError(path, "more than one row per metric and engine", "rerun the rule that writes it")
    return frame


class AnswerParams(JobParams):
    """What rule answer's job reads: the study's engines, the statistics, the weights (the answer is what a
    weight edit reruns), the seed, the real data's source and title, the robot's name and the basis."""

    engines: list[str]
    statistics: Statistics
    weights: dict[str, NonNegative]
    seed: Annotated[int, Field(ge=0, lt=2**32)]
    source: str = Field(description="the real data's source (a source's name, or the DRIVE dataset)")
    source_title: str = Field(description="how the headline names the real data")
    robot: str = Field(description="the robot's name in the sentences")
    basis: AnswerBasis | None = Field(None, description="the real data the answer rests on; None: not named")


def answer_job(inputs: dict, params: dict, outputs: dict) -> None:
    """Rule ``answer``: the paper's weighted ranking with its interval over real runs (ranking.csv),
    the separation table, answer.csv, answer.yaml and the headline, from the scores (weighted.csv, or
    with ``inputs["scores"]`` the per-metric scores, weighed here at the params' weights into
    ``outputs["weighted"]``, ``["contributions"]`` and ``["drivers"]``; provenance.yaml), the real-data
    comparison's tables (outcomes, mechanics, table, per_test: the verdict's,
    with its discrimination table, where the study has one, else the DRIVE comparison's, which writes the
    same tables beside its outcomes; simpick.plan answer_tables), the lab's real-time factor, the CPU runs
    and, where it ran, the calibration's turning table. ``params.basis``: the dataset the comparison rests
    on, its unit ("step", "run") and the study's other real data, for the sentence that names them
    (``params``: :class:`AnswerParams`)."""
    p = AnswerParams.model_validate(params)
    # simpick.score.verdict's ranking reads the statistics as a mapping
    statistics, weights = p.statistics.model_dump(mode="json"), dict(p.weights)
    engines, seed = list(p.engines), p.seed
    if inputs.get("scores"):
        # the workflow weighs the scores here (rule answer writes weighted.csv, contributions.csv and
        # drivers.csv): one job less before the answer on a weight edit
        from simpick.score.jobs import weigh

        weigh(pd.read_csv(inputs["scores"], index_col="engine"), weights, outputs)
    weighted = pd.read_csv(outputs["weighted"] if inputs.get("scores") else inputs["weighted"], index_col=0)
    prov = yaml.safe_load(Path(inputs["provenance"]).read_text()) or {}
    acc = prov.get("accuracy") or {}
    acc_per_test = None
    if acc.get("set") not in (None, "lab") and Path(inputs["accuracy_tests"]).is_file():
        acc_per_test = read_per_test(inputs["accuracy_tests"])
    scored = [e for e in engines if e in weighted.index]
    rank = ranking(weighted.loc[scored], acc_per_test, acc.get("tests") or None, weights, statistics, seed=seed)
    write_csv(rank, outputs["ranking"])
    table = pd.read_csv(inputs["table"])
    # what the paper's accuracy scores separate: the verdict's, where the scores rest on its real runs; none
    # beside DRIVE's outcomes (the scores never rest on DRIVE's steps)
    disc = (
        pd.read_csv(inputs["discrimination"])
        if inputs.get("discrimination")
        else pd.DataFrame(columns=DISCRIMINATION_COLUMNS)
    )
    separation = separation_rows(table, p.statistics.min_runs) + paper_rows(rank, disc, weights)
    write_csv(pd.DataFrame(separation, columns=SEPARATION_COLUMNS), outputs["separation"])

    outcomes = read_outcomes(inputs["outcomes"])
    # the engines the comparison judged: a DRIVE replay may leave some of the study's out (drive_replay.models);
    # the answer names them rather than giving them a row without real data
    judged = set(outcomes.engine)
    left_out = [e for e in engines if e not in judged]
    engines = [e for e in engines if e in judged]
    mechanics = pd.read_csv(inputs["mechanics"])
    tests = read_per_test(inputs["per_test"])
    rtfs, cpu = machine_figures(inputs["rtf"], list(inputs["cpu"]))
    cal = calibrated(inputs.get("calibration_turning"))
    answer = answer_table(outcomes, mechanics, weighted, engines, gain_ratios(tests, engines), cal, rtfs, cpu)
    write_csv(answer, outputs["answer"])
    robot = p.robot or "real robot"
    noun = (p.basis.noun if p.basis else None) or RUNS
    said = sentences(outcomes, answer, cal, robot, noun)
    Path(outputs["answer_yaml"]).write_text(
        yaml.safe_dump({"robot": robot, "sentences": said}, sort_keys=False, allow_unicode=True, width=10_000)
    )
    n_runs = int(run_key(tests[tests.status == "ok"]).nunique()) if len(tests) else 0
    source = p.source_title or p.source or "real data"
    Path(outputs["headline"]).write_text(
        yaml.safe_dump(
            {
                "source": p.source,
                "source_title": source,
                "n_runs": n_runs,
                "min_runs": p.statistics.min_runs,
                "units": units(noun),
                "basis": basis_sentence(p.basis, n_runs, left_out),
                "level": p.statistics.level,
                "paragraph": headline(said, separation, rank),
            },
            sort_keys=False,
            allow_unicode=True,
        )
    )
