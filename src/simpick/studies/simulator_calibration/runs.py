"""The real runs a calibration fits: the split (rule simulator_split), the training runs' turning units and
their real gains, the full replay's turning windows of its held-out grid, and DRIVE's representative steps."""

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
    if "windows" in inputs:
        # the user's own logs: every run (its canonical log, results/real/own/logs/<class>/<run>.parquet), a unit
        # of its own, turning where it has a steady turning window (rule real_turning)
        win = pd.read_csv(inputs["windows"], dtype={"run": str})
        turning = set(zip(win.terrain_class.astype(str).str.lower(), win.run.astype(str)))
        logs = [inputs["logs"]] if isinstance(inputs["logs"], str) else list(inputs["logs"])
        rows = [
            [Path(f).parent.name, Path(f).stem, Path(f).stem, (Path(f).parent.name, Path(f).stem) in turning]
            for f in logs
        ]
        units = pd.DataFrame(rows, columns=["terrain_class", "run", "unit", "turns"]).astype({"run": str})
        write_csv(split_runs(units, test_fraction, seed), output)
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
    """Kind drive: the training steps the fit replays, at most ``n``, each with its command, class and real gain.
    Per unit (a run; a DRIVE step is one) its turning window of median |w| gives the command and the mean of its
    windows' gains the real gain; where there are more than ``n`` units, the median unit by |w| of each of ``n``
    equal bins of them (terrain_class, run, v, w, gain): deterministic, stratified by how fast they turn."""
    rows = []
    for (cls, run), g in turns.groupby(["terrain_class", "run"], sort=True):
        g = g.assign(aw=g.w.abs()).sort_values(["aw"], kind="stable").reset_index(drop=True)
        mid = g.iloc[len(g) // 2]
        rows.append({"terrain_class": cls, "run": run, "v": float(mid.v), "w": float(mid.w)})
        rows[-1]["gain"] = float(g.gain.mean())
    if not rows:
        return pd.DataFrame(columns=["terrain_class", "run", "v", "w", "gain"])
    order = pd.DataFrame(rows)
    order = order.assign(aw=order.w.abs()).sort_values(["aw", "terrain_class", "run"]).reset_index(drop=True)
    bins = np.array_split(np.arange(len(order)), min(n, len(order)))
    return order.iloc[[int(b[len(b) // 2]) for b in bins]].drop(columns="aw").reset_index(drop=True)


WINDOW_UNIT_COLUMNS = ["key", "terrain_class", "run", "t_start", "t_end", "gain"]


def turning_windows(logs: dict, runs: list[str], classes: list[str], track: float, window: float, n: int):
    """Per run of ``runs`` (``class/run``) in ``classes`` with a canonical log in ``logs`` (``class/run`` -> log),
    its first ``n`` windows that turn on the full replay's held-out grid (simpick.compare.real.replay_compare:
    ``window`` s windows from t = 0, a tail shorter than half a window left out), each with its real gain over the
    real IMU's samples in it against the recorded wheel speeds held at them (NaN where the wheels do not turn it:
    not a turning window) (``WINDOW_UNIT_COLUMNS``)."""
    from simpick.compare import realmetrics

    rows = []
    for key in sorted(set(runs)):
        cls, run = key.split("/", 1)
        if cls not in classes or key not in logs:
            continue
        log = logs[key]
        cmd, imu = log.wheel_commands(track), log.imu
        t = imu.time.to_numpy(float)
        end = float(min(t[-1], cmd.time.iloc[-1]))
        rate = 1.0 / float(np.median(np.diff(t)))
        held = np.clip(np.searchsorted(cmd.time.to_numpy(), t, side="right") - 1, 0, len(cmd) - 1)
        left, right, wz = cmd.v_left.to_numpy()[held], cmd.v_right.to_numpy()[held], imu.wz.to_numpy(float)
        found = 0
        for w0 in np.arange(0.0, end + 1e-9, window):
            sel = (t > w0) & (t <= min(w0 + window, end))
            if sel.sum() < 0.5 * window * rate or found >= n:
                continue
            gain = realmetrics.yaw_rate_gain(wz[sel], left[sel], right[sel], track)
            if np.isfinite(gain):
                t_end = round(min(float(w0 + window), end), 6)
                rows.append([key, cls, run, float(w0), t_end, float(gain)])
                found += 1
    return pd.DataFrame(rows, columns=WINDOW_UNIT_COLUMNS)
