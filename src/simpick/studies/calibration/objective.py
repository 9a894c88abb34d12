"""One unit's errors and the objective: a committed segment or a replayed run simulated as the study's
real-data jobs do, its yaw-rate and acceleration errors (and steady turning gain), their scaled sum,
and the training units an objective is the mean over."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from simpick.compare import realmetrics
from simpick.compare.real import compared_window, real_imu_at, trace_rate
from simpick.real.logs import read_canonical
from simpick.real.turning import turning_windows
from simpick.simulate.real import class_segments, replay_log, simulate_segment
from simpick.simulate.real_settings import RealCaseParams

FAILED_UNIT = 10.0  # objective counted for a unit the engine fails (10x the scale of either error)


def segment_errors(seg: pd.Series, urdf: str, params: dict, window: float | None) -> dict:
    """A committed segment: |mean sim - mean real| of yaw rate and longitudinal acceleration over
    the first ``window`` seconds of its compared window (all of it when None). ``params``: a real-data case's
    (:class:`simpick.simulate.real_settings.RealCaseParams`), handed on to the simulate stage as given."""
    track = RealCaseParams.model_validate(params).robot.track
    seg = seg.copy()
    if window is not None:
        seg["duration"] = min(float(seg.duration), float(window))
    frame, meta = simulate_segment(seg, urdf, params)
    out = {"status": meta["health"]["status"], "wall_time": float(meta["wall_time"]), "steps": int(meta["steps"])}
    if out["status"] == "ok":
        w = compared_window(pd.DataFrame(frame), meta)
        out["error_yaw_rate"] = abs(float(w.wz.mean()) - float(seg.angular_z_mean))
        out["error_accel_x"] = abs(float(w.ax.mean()) - float(seg.linear_x_mean))
        out["error_accel_x_offset_free"] = 0.0  # a window mean less its mean (module docstring)
        if np.isfinite(float(seg.yaw_rate_gain)):  # a turning segment: the gain under its constant command
            kinematic = (float(seg.v_right) - float(seg.v_left)) / track
            out.update(_gain_figures(float(w.wz.mean()) / kinematic, float(seg.yaw_rate_gain), 1))
    return out


def _gain_figures(sim_gain: float, real_gain: float, windows: int) -> dict:
    """A unit's steady yaw-rate gain, simulated and real (mean yaw rate over the kinematic one under a
    steady command), their absolute difference and the number of steady windows behind them."""
    return {
        "yaw_rate_gain_sim": sim_gain,
        "yaw_rate_gain_real": real_gain,
        "gain_error": abs(sim_gain - real_gain),
        "gain_windows": windows,
    }


def steady_windows(log, track: float, steady: dict) -> pd.DataFrame:
    """The log's steady-command turning windows (simpick.real.turning.turning_windows with the real
    turning analysis' ``steady`` settings: window, settle, tolerance, min_turn)."""
    return turning_windows(log, track, **{k: float(v) for k, v in steady.items()})


def replay_errors(log, urdf: str, params: dict, duration: float | None, steady: dict | None = None) -> dict:
    """A replayed run: RMS difference of the low-passed yaw rate and longitudinal acceleration
    (the replay metrics' rmse_yaw_rate and rmse_ax, over the first ``duration`` seconds), and the
    steady yaw-rate gain, simulated and real, in its steady-command turning windows. ``params``: as
    :func:`segment_errors`'."""
    track = RealCaseParams.model_validate(params).robot.track
    frame, meta = replay_log(log, urdf, params, duration=duration)
    out = {"status": meta["health"]["status"], "wall_time": float(meta["wall_time"]), "steps": int(meta["steps"])}
    if out["status"] == "ok":
        sim = pd.DataFrame(frame)
        rate = trace_rate(sim, meta)
        real = real_imu_at(log.imu, sim.time.to_numpy(), ("wz", "ax"))
        for col, key in (("wz", "error_yaw_rate"), ("ax", "error_accel_x")):
            out[key] = realmetrics.aligned_rmse(real[col], sim[col].to_numpy(), rate)
        out["error_accel_x_offset_free"] = realmetrics.aligned_rmse(
            real["ax"], sim["ax"].to_numpy(), rate, offset_free=True
        )
        # the steady yaw-rate gain: in the log's steady-command turning windows inside the
        # compared seconds (simpick.real.turning.turning_windows, the real turning figure's windows), the
        # mean yaw rate over the kinematic one, simulated and real, averaged over the run's windows.
        # Not a fit over every turning sample: the real yaw rate lags a changed command by ~0.3 s, which
        # would mix the response's lag into the gain of a run with many short turns
        windows = steady_windows(log, track, steady or {})
        windows = windows[windows.t_end <= float(sim.time.iloc[-1])]
        if len(windows):
            t, wz = sim.time.to_numpy(), sim.wz.to_numpy()
            sim_gains = [
                float(wz[(t >= w.t_start) & (t < w.t_end)].mean()) / w.w_kinematic for w in windows.itertuples()
            ]
            out.update(_gain_figures(float(np.mean(sim_gains)), float(windows.yaw_rate_gain.mean()), len(windows)))
    return out


def objective_terms(row: dict, scales: dict) -> float:
    """One unit's contribution to the objective (dimensionless): the yaw-rate error and the
    offset-free longitudinal-acceleration error (module docstring), each over its scale, plus, on a
    unit that turns under a steady command, the steady yaw-rate gain error over
    ``scales['yaw_rate_gain']`` (the gain gets a weight of its own, not only through the
    yaw rate, whose RMS over a whole run is dominated by transients)."""
    if row.get("status") != "ok" or not np.isfinite(row.get("error_yaw_rate", np.nan)):
        return FAILED_UNIT
    accel = row.get("error_accel_x_offset_free", row["error_accel_x"])
    total = row["error_yaw_rate"] / scales["yaw_rate"] + accel / scales["accel_x"]
    gain = row.get("gain_error", math.nan)
    if scales.get("yaw_rate_gain") and gain is not None and np.isfinite(gain):
        total += gain / scales["yaw_rate_gain"]
    return total


class Units:
    """The real units of one terrain class (segments or replayed runs), by unit id."""

    def __init__(
        self,
        source: str,
        segments_csv: str | None = None,
        logs: list[str] | None = None,
        terrain_class: str | None = None,
    ):
        self.source = source
        if source == "segments":
            self.segments = class_segments(segments_csv, terrain_class)
            self.ids = [str(s) for s in self.segments.index]
            self.runs = {str(s): str(self.segments.loc[s, "run"]) for s in self.segments.index}
        else:
            self.logs = {}
            for path in logs or []:
                log = read_canonical(path)
                self.logs[str(log.meta["run_id"])] = log
            self.ids = sorted(self.logs)
            self.runs = {r: r for r in self.ids}

    def errors(self, unit: str, urdf: str, params: dict, settings: dict) -> dict:
        if self.source == "segments":
            return segment_errors(self.segments.loc[unit], urdf, params, settings.get("segment_seconds"))
        return replay_errors(self.logs[unit], urdf, params, settings.get("replay_seconds"), settings.get("steady"))


def evaluate(units: Units, ids: list[str], urdf: str, params: dict, settings: dict) -> list[dict]:
    rows = []
    for unit in ids:
        row = {"unit": unit, "run": units.runs[unit], **units.errors(unit, urdf, params, settings)}
        row["objective"] = objective_terms(row, settings["scales"])
        rows.append(row)
    return rows
