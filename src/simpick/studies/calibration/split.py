"""The calibration's split: per terrain class, whole real runs shuffled by a seeded generator into
training and test sets, written as a result file and read back per class."""

from __future__ import annotations

import numpy as np
import pandas as pd
from pydantic import Field

from simpick.params import JobParams, Positive
from simpick.real.logs import read_canonical
from simpick.real.settings import SteadyRules
from simpick.simulate.run import stable_seed
from simpick.studies.calibration.objective import steady_windows
from simpick.tables import write_csv

SPLIT_COLUMNS = ("terrain_class", "run", "unit", "set")


class SplitStrata(JobParams):
    """How rule calibration_split's job tells a replayed run that turns (the plan's calibration_strata): the
    controller's track, the steady-command rules of the turning windows, and the compared seconds."""

    track: Positive = Field(description="m, the controller's track (the config's robot.track)")
    steady: SteadyRules
    duration: Positive | None = Field(description="s compared of each run (None: all of it)")


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
        s = SplitStrata.model_validate(strata)
        turns = {}
        for path in logs:
            log = read_canonical(path)
            key = (str(log.meta["terrain_class"]).lower(), str(log.meta["run_id"]))
            turns[key] = run_turns(log, s.track, s.steady.model_dump(), s.duration)
        frame["turns"] = [turns.get((c, r), False) for c, r in zip(frame.terrain_class, frame.run)]
    write_csv(split_runs(frame, test_fraction, seed), output)


def read_split(path: str, terrain_class: str) -> pd.DataFrame:
    split = pd.read_csv(path, dtype={"run": str, "unit": str})
    return split[split.terrain_class == terrain_class]
