"""What an evaluation of the fit runs on the engine, as :class:`~.fit.Units`: what the held-out figure of the fit's
source replays, on the training runs: the committed segments' turning segments (:func:`segment_units`), the full
replay's turning windows (:func:`window_units`) or DRIVE's turning steps (:func:`step_units`)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from simpick.studies.simulator_calibration.fit import Units
from simpick.studies.simulator_calibration.params import CalibrateParams
from simpick.studies.simulator_calibration.runs import representative_units, turning_segments, turning_windows


def segment_units(p: CalibrateParams, inputs: dict, runs: list[str], classes: list[str]) -> Units:
    """The turning segments of ``runs`` in ``classes`` (the committed table), each replayed as the calibrated
    profile's segments simulate job replays it (simpick.simulate.real.prepare_segment with the job's params, the
    trial's settings merged over them as simpick.simulate.calibrated merges the fit's) and its simulated gain
    taken as the comparison takes it (simpick.compare.real.segment_row, in the segment's compared window)."""
    from simpick.compare.real import segment_row
    from simpick.simulate.calibrated import merge_settings
    from simpick.simulate.real import prepare_segment, table_segment

    if p.segments_case is None:
        raise ValueError("kind segments fits on the calibrated profile's segments case: the params give none")

    seg = turning_segments(inputs["segments"], runs, classes)
    names = list(seg.segment)
    rows = [table_segment(inputs["segments"], name) for name in names]
    track = p.robot.track

    def simulate(settings: dict) -> np.ndarray:
        params = merge_settings(p.segments_case, settings)  # the trial's over the job's, as a fit's are merged
        out = []
        for name, row in zip(names, rows):
            _, run = prepare_segment(inputs["urdf"], inputs, params, name)
            frame, meta = run()
            compared = segment_row(pd.DataFrame(frame), meta, row, track)
            out.append(float(compared.get("yaw_rate_gain_sim", math.nan)) if compared["status"] == "ok" else math.nan)
        return np.array(out)

    describe = {"segments": names, "window": "each segment's compared window in full (settle, then its duration)"}
    return Units(
        [f"{c}/{r}" for c, r in zip(seg.terrain_class, seg.run)],
        seg.yaw_rate_gain.to_numpy(float),
        names,
        simulate,
        describe,
    )


# s replayed past a run's last fitted window: the trace's last samples reach the window's end as the full replay's do
END_MARGIN = 0.05


def window_units(p: CalibrateParams, inputs: dict, runs: list[str], classes: list[str]) -> Units:
    """Kind replay: per run of ``runs`` in ``classes``, its first ``p.replay_windows`` turning windows of the
    held-out comparison's grid (:func:`~.runs.turning_windows`), each replayed as the calibrated profile's replay
    simulate job replays its run (simpick.simulate.real.replay_log with the job's params of the run's class, the
    trial's settings merged over them: from rest at t = 0, by the recorded wheel speeds) up to the end of the run's
    last such window, and each window's simulated gain taken as simpick.compare.real.replay_compare takes it (the
    gain over the trace's samples in the window, against the recorded wheel speeds held at them). The first
    windows: a later window is only reached by replaying the whole run before it, as the held-out replay does."""
    from simpick.compare import realmetrics
    from simpick.real.logs import read_canonical
    from simpick.simulate.calibrated import merge_settings
    from simpick.simulate.real import replay_log

    logs = {}
    for path in [inputs["logs"]] if isinstance(inputs["logs"], str) else inputs["logs"]:
        log = read_canonical(path)
        logs[f"{str(log.meta['terrain_class']).lower()}/{log.meta['run_id']}"] = log
    track, window = p.robot.track, p.replay_window
    picked = turning_windows(logs, runs, classes, track, window, p.replay_windows)
    ends = picked.groupby("key").t_end.max().to_dict()
    order = list(ends)

    def simulate(settings: dict) -> np.ndarray:
        gains: dict[tuple[str, float], float] = {}
        for key in order:
            cls = key.split("/")[0]
            params = merge_settings(p.replay_cases[cls], settings)
            frame, meta = replay_log(logs[key], inputs["urdf"], params, duration=float(ends[key]) + END_MARGIN)
            if meta["health"]["status"] != "ok":
                continue  # a failed replay: its windows' gains NaN (the fit's FAILED_RESIDUAL)
            sim = pd.DataFrame(frame)
            cmd = logs[key].wheel_commands(track)
            held = np.clip(np.searchsorted(cmd.time.to_numpy(), sim.time.to_numpy(), side="right") - 1, 0, len(cmd) - 1)
            left, right = cmd.v_left.to_numpy()[held], cmd.v_right.to_numpy()[held]
            for w0 in picked[picked.key == key].t_start:
                sel = ((sim.time > w0) & (sim.time <= w0 + window)).to_numpy()
                gains[(key, w0)] = realmetrics.yaw_rate_gain(sim.wz[sel], left[sel], right[sel], track)
        return np.array([gains.get((k, w0), math.nan) for k, w0 in zip(picked.key, picked.t_start)], float)

    describe = {
        "windows": [f"{k} [{a:g}, {a + window:g}] s" for k, a in zip(picked.key, picked.t_start)],
        "window": f"the held-out comparison's {window:g} s windows from each run's start; per run its first "
        f"{p.replay_windows} that turn (real gain defined), the run replayed from rest up to the last one's end",
        "replayed_seconds": round(float(sum(ends.values())) + END_MARGIN * len(ends), 3),
    }
    return Units(list(picked.key), picked.gain.to_numpy(float), describe["windows"], simulate, describe)


def step_units(p: CalibrateParams, inputs: dict, turns: pd.DataFrame) -> Units:
    """Kind drive: at most ``p.drive_commands`` training steps (:func:`~.runs.representative_units`: the median
    step by |w| of each of as many equal bins), each replayed as DRIVE's replay replays it
    (simpick.simulate.steps.drive_step: the warm-up from rest at the wheel speeds the real robot measured before
    the step, then the step's measured wheel speeds, on its class's ground, the trial's settings merged over the
    calibrated profile's replay params) and its gain taken as simpick.compare.steps.step_errors takes it (the
    steady part's mean simulated yaw rate over the step's kinematic one)."""
    from simpick.simulate.calibrated import merge_settings
    from simpick.simulate.step_rows import step_row
    from simpick.simulate.steps import StepsParams, drive_step, ground, read_wheels, step_samples
    from simpick.studies.simulator_calibration.runs import steps_key

    picked = representative_units(turns, p.drive_commands)
    cases = pd.read_csv(inputs["cases"])
    cases = cases.assign(key=cases.terrain_class + "/" + steps_key(cases)).set_index("key")
    keys = [f"{c}/{r}" for c, r in zip(picked.terrain_class, picked.run)]
    chosen = [cases.loc[k] for k in keys]
    wheels = read_wheels(inputs["wheels"])
    samples = [step_samples(wheels, c.session, int(c.step), inputs["wheels"]) for c in chosen]
    w_kin = picked.w.to_numpy(float)

    def simulate(settings: dict) -> np.ndarray:
        sp = StepsParams.model_validate(merge_settings(p.steps_case, settings))
        out = []
        for case, sample, w in zip(chosen, samples, w_kin):
            frame, meta = drive_step(
                sample, case, inputs["urdf"], ground(sp, case.terrain_class, "a step"), sp.replay.warmup
            )
            row = step_row(frame, meta, case)
            out.append(float(row["sim_yaw_rate"]) / w if row["status"] == "ok" else math.nan)
        return np.array(out)

    describe = {
        "steps": keys,
        "commands": [[float(v), float(w)] for v, w in zip(picked.v, picked.w)],
        "from": "each step replayed from its warm-up at the real robot's wheel speeds before it, then its measured "
        "wheel speeds; its gain over its steady part, against its real gain",
    }
    return Units(keys, picked.gain.to_numpy(float), keys, simulate, describe)


def _units(p: CalibrateParams, inputs: dict, robot, runs: list[str], classes: list[str], turns) -> Units:
    """The fitted units, what the held-out figure replays on the training runs: their turning segments (kind
    segments), their turning windows of the full replay (kind replay) or their turning steps (kind drive)."""
    if p.kind == "replay":
        return window_units(p, inputs, runs, classes)
    if p.kind == "drive":
        return step_units(p, inputs, turns)
    return segment_units(p, inputs, runs, classes)
