"""What an evaluation of the fit runs on the engine: the training runs' turning segments replayed, or
steady-turn cases at representative commands, as :class:`~.fit.Units`."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from simpick.studies.simulator_calibration.fit import Units
from simpick.studies.simulator_calibration.params import CalibrateParams
from simpick.studies.simulator_calibration.runs import representative_units, turning_segments


def segment_units(p: CalibrateParams, inputs: dict, runs: list[str], classes: list[str]) -> Units:
    """The turning segments of ``runs`` in ``classes`` (the committed table), each replayed as the calibrated
    profile's segments simulate job replays it (simpick.simulate.real.prepare_segment with the job's params, the
    trial's settings merged over them as simpick.simulate.calibrated merges the fit's) and its simulated gain
    taken as the comparison takes it (simpick.compare.real.segment_row, in the segment's compared window)."""
    from simpick.compare.real import segment_row
    from simpick.simulate.calibrated import merge_settings
    from simpick.simulate.real import prepare_segment, table_segment

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


def _steady_turns(p: CalibrateParams, robot, commands: list, grounds: list[float]):
    """The function of a trial's settings that gives the engine's steady yaw-rate gain at each of ``commands``
    from rest on flat ground of the matching friction in ``grounds`` (the validation's steady-turn case)."""
    from simpick.studies.validation.cases import Setup, run_case

    def simulate(settings: dict) -> np.ndarray:
        setup = Setup(
            engine=p.engine,
            robot=robot,
            timestep=p.physics.timestep,
            max_wheel_torque=p.robot.max_wheel_torque,
            track=p.robot.track,
            settings={**p.engine_settings, **settings},
        )
        ratio = float(settings.get("friction_ratio", p.engine_settings.get("friction_ratio", 1.0)))
        return np.array(
            [_engine_gain(run_case, setup, ratio, v, w, mu, p.duration) for (v, w), mu in zip(commands, grounds)]
        )

    return simulate


def _units(p: CalibrateParams, inputs: dict, robot, runs: list[str], classes: list[str], turns) -> Units:
    """The fitted units: the training runs' turning segments (kind segments), else each run (or DRIVE step) a
    steady turn at its own representative command on its class's ground against its own real gain
    (:func:`representative_units`, :func:`run_units`)."""
    if p.kind == "segments" and p.segments_case is not None:
        return segment_units(p, inputs, runs, classes)
    return run_units(p, robot, representative_units(turns, p.drive_commands))


def run_units(p: CalibrateParams, robot, picked: pd.DataFrame) -> Units:
    """The engine's steady turn from rest at each picked unit's command on its class's ground (the validation's
    steady-turn case), against that unit's own real gain: the per-run gain residuals the held-out figure takes,
    at each run's representative command (a replay of every DRIVE step or full-replay window per evaluation costs
    more than these kinds' fits are given)."""
    commands = list(zip(picked.v.astype(float), picked.w.astype(float)))
    grounds = [float(p.grounds[str(c)]) for c in picked.terrain_class]
    simulate = _steady_turns(p, robot, commands, grounds)

    runs = [f"{c}/{r}" for c, r in zip(picked.terrain_class, picked.run)]
    describe = {
        "units": runs,
        "commands": [[v, w] for v, w in commands],
        "grounds": grounds,
        "duration": p.duration,
        "from": "each unit's turning window of median |w| (a steady turn from rest on its class's ground), against "
        "its windows' mean real gain",
    }
    return Units(runs, picked.gain.to_numpy(float), runs, simulate, describe)


def _engine_gain(run_case, setup, ratio: float, v: float, w: float, mu: float, duration: float) -> float:
    """The engine's steady yaw-rate gain on the validation's steady-turn case at ``ratio`` (NaN if it failed)."""
    case = {"kind": "yaw_gain", "v": v, "w": w, "mu": mu, "duration": duration, "friction_ratio": ratio}
    record = run_case(setup, f"calibrate_r{ratio:.4f}", case)
    checks = [c for c in record["checks"] if c["quantity"] == "yaw_rate_gain"]
    if record["status"] != "ok" or not checks:
        return math.nan
    return float(checks[0]["engine_value"])
