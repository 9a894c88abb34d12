"""The verdict's job: reads the real-data per-test table and the validation summary, and writes
every table of ``results/verdict/`` (per-run metrics, the metric x model table, outcomes against
the best behind the mechanics gate, the heading spread, the paper's score discrimination).

Reading and writing files stays here so that the statistics modules take and return frames only."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Literal

import pandas as pd
from pydantic import Field

from simpick.params import JobParams
from simpick.score.equivalence import outcomes_table
from simpick.score.mechanics import mechanics_table
from simpick.score.settings import Statistics, Verdict
from simpick.score.verdict.headings import heading_spread
from simpick.score.verdict.paper import DISCRIMINATION_COLUMNS, score_discrimination
from simpick.score.verdict.runs import METRICS, NO_SPEED, metric_table, per_run_long, per_run_values
from simpick.tables import write_csv


def scored_tests(imu_errors: str, engines: list[str]) -> list[str] | None:
    """The tests the accuracy scores rest on, as the Eq. 7 totals file lists them (the scores
    record the same list in their provenance)."""
    errors = pd.read_csv(imu_errors, dtype=str, keep_default_na=False)
    errors = errors[errors.engine.isin(engines)]
    tests = sorted({t for cell in errors.get("tests", []) for t in str(cell).split(";") if t.strip() and t != "nan"})
    return tests or None


def read_per_test(path: str) -> pd.DataFrame:
    tests = pd.read_csv(path, dtype={"run": str, "test": str, "segment": str})
    for col in ("engine", "terrain_class", "run", "status", "test"):
        if col not in tests:
            tests[col] = pd.Series(dtype=str)
    return tests


class VerdictParams(JobParams):
    """What rule verdict's job reads: the engines judged, the reference models that floor the paper's scores,
    the statistics, the seed, the accuracy scores' set and the verdict's margins and mechanics (no weight)."""

    engines: list[str]
    baselines: list[str] = Field([], description="the reference models (a floor under the paper's scores)")
    statistics: Statistics
    seed: Annotated[int, Field(ge=0, lt=2**32)]
    accuracy_set: Literal["lab", "segments", "replay", "own"] = Field(
        description="the set of tests the accuracy scores rest on (lab: the paper's, no discrimination)"
    )
    verdict: Verdict


def verdict_job(inputs: dict, params: dict, outputs: dict) -> None:
    """results/verdict/: per-run metrics, the metric x model table (each engine against the next),
    each engine against the best (outcomes.csv: simpick.score.equivalence) with the mechanics gate
    it rests on (mechanics.csv: simpick.score.mechanics), the heading spread and what the paper's
    accuracy scores separate (discrimination). Nothing here reads the weights: a weight edit does
    not rerun these tests (the weighted ranking and the answer are rule ``answer``'s).

    ``inputs``: ``per_test`` (the verdict's real data), ``validation`` (the validation summary),
    ``accuracy_tests`` and ``accuracy_errors`` (the accuracy scores' per-test table and Eq. 7
    totals); ``params``: :class:`VerdictParams`."""
    p = VerdictParams.model_validate(params)
    # the statistics modules (simpick.score.equivalence, .verdict) read these as mappings
    statistics, verdict = p.statistics.model_dump(mode="json"), p.verdict.model_dump(mode="json")
    engines, floor_models, seed = list(p.engines), list(p.baselines), p.seed
    tests = read_per_test(inputs["per_test"])
    walls = {metric: per_run_values(tests, metric) for metric in METRICS}
    write_csv(per_run_long(walls), outputs["metrics"])
    write_csv(metric_table(tests, engines, statistics, seed), outputs["table"])
    if outputs.get("headings"):
        write_csv(heading_spread(tests), outputs["headings"])

    mechanics = mechanics_table(pd.read_csv(inputs["validation"]), engines)
    write_csv(mechanics, outputs["mechanics"])
    absent = {"speed_error": NO_SPEED}
    outcomes = outcomes_table(walls, tests, engines, METRICS, mechanics, verdict, statistics, seed, absent)
    write_csv(outcomes, outputs["outcomes"])

    disc = pd.DataFrame(columns=DISCRIMINATION_COLUMNS)
    if p.accuracy_set != "lab" and Path(inputs["accuracy_tests"]).is_file():
        acc_per_test = read_per_test(inputs["accuracy_tests"])
        scored = [e for e in engines if e in set(acc_per_test.engine)]
        if len(acc_per_test) and scored:
            disc = score_discrimination(
                acc_per_test,
                scored,
                floor_models,
                scored_tests(inputs["accuracy_errors"], scored),
                statistics,
                seed=seed,
            )
    write_csv(disc, outputs["discrimination"])
