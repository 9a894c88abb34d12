"""The real runs a calibration fits: the split (rule simulator_split), the training runs' turning units and
their real gains, and the representative units the steady-turn kinds run."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pandas as pd

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
