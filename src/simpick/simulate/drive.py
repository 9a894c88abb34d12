"""DRIVE steps replayed in an engine: each step on flat ground with its session's terrain friction, from the
state the real robot was in at the step's start, then driven by the step's measured wheel speeds.

How a step starts. The engines have no common way to set a body velocity, and a body velocity set by hand
would start without the contact forces and slip that go with it (every engine would then spend the first
part of the step settling from an inconsistent state, each in its own way). So each step starts with a
warm-up: the robot, at rest on the ground, is driven for ``warmup`` seconds (the first :data:`RAMP_S` a ramp
from rest) at the wheel speeds the real
robot measured just before the step (the previous step's last :data:`~simpick.real.logs.drive.START_SECONDS`,
the cases' ``start_wheel_left/right``). That is long enough for each engine to reach its own steady state
for those wheels (the Warthog's steps settle in well under 1 s in the engines), a physically consistent
start (contact forces, slip) reached in every engine alike. Where that engine state differs from the real
robot's (the ICP body speed and the gyro yaw rate at the step's start), the difference is the engine's own
error on the previous command, and it is reported per step (``start_dv``, ``start_dwz``), not hidden.

What drives the step. The measured wheel speeds (DRIVE holds each reading about 0.25 s; the replay
interpolates linearly between the instants they change, the continuous wheel motion they sample, where
holding them would jerk the wheels four times a second), not the commands:
DRIVE's commands exceed what the Warthog's wheels reach (commanded up to 16.6 rad/s, measured at most 14),
and every engine's velocity servo follows a command it is given almost exactly, so replaying the command
would drive the simulated wheels faster than the real ones turned and charge the engine with the motor
controller's shortfall. With the measured speeds the comparison is of what the ground does with the wheels'
motion, the part an engine models (as the BorealTC replay does).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.errors import InputError
from simpick.simulate.real import flat_terrain, start_heading
from simpick.simulate.run import Recording, run_commands, scenario_from, stable_seed

WARMUP_S = 3.0  # s of the previous step's measured wheel speeds before a step (module doc)
RAMP_S = 1.0  # s of the warm-up over which the wheels speed up from rest (no jump that the servos cannot follow)
START_WINDOW_S = 0.5  # s at the end of the warm-up averaged for the simulated start state (as the real one)
TRACE_COLUMNS = ["step", "t_step", "v_forward", "yaw_rate", "wz", "x", "y", "yaw", "roll", "pitch", "z", "cmd_left"]
STEP_COLUMNS = [
    "case",
    "session",
    "terrain_class",
    "step",
    "engine",
    "status",
    "reasons",
    "warmup",
    "start_heading_deg",
    "sim_start_vx",
    "sim_start_wz",
    "sim_v",
    "sim_yaw_rate",
    "sim_heading",
    "wall_time",
    "sim_time",
]


def select_steps(cases: pd.DataFrame, every: int = 1, max_steps_per_session: int | None = None) -> pd.DataFrame:
    """A deterministic subset of the replay cases: per session, every ``every``-th step counted from step 1
    (step 0 is DRIVE's zero command), then at most ``max_steps_per_session`` of those, the earliest. The same
    table and settings always give the same steps."""
    if every < 1:
        raise ValueError(f"every must be 1 or more, not {every}")
    kept = []
    for _, g in cases.sort_values(["session", "step"]).groupby("session", sort=True):
        g = g[g.step >= 1]
        g = g[((g.step - 1) % every) == 0]
        kept.append(g if max_steps_per_session is None else g.head(int(max_steps_per_session)))
    return pd.concat(kept) if kept else cases.iloc[:0]


def _interpolated(times: np.ndarray, held: np.ndarray, t: np.ndarray) -> np.ndarray:
    """A sample-and-hold series (DRIVE's wheel speeds change about every 0.25 s and are held in between)
    read as the continuous speed it samples: linear between the instants it changes, held after the last."""
    changes = np.flatnonzero(np.diff(held) != 0) + 1
    at = np.concatenate(([0], changes))
    return np.interp(t, times[at], held[at])


def step_wheels(session, case: pd.Series, warmup: float, dt: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Rim speeds (m/s) of the left and right wheels at every physics step (time ``-warmup`` .. the step's
    end): the warm-up, from rest, ramped over :data:`RAMP_S` to the start speeds and held there; then the
    step's measured speeds (:func:`_interpolated`); and the step's end (s from its start)."""
    samples = session.wheel_commands(int(case.step))
    r = session.meta["geometry"]["wheel_radius"]
    end = float(case.steady_end)
    n = int(round((warmup + end) / dt))
    t = dt * np.arange(1, n + 1) - warmup
    ramp = np.clip((t + warmup) / min(RAMP_S, warmup), 0.0, 1.0)
    times = samples.time.to_numpy(float)
    out = []
    for side, start in (("v_left", case.start_wheel_left), ("v_right", case.start_wheel_right)):
        measured = _interpolated(times, samples[side].to_numpy(float), t)
        out.append(np.where(t < 0, ramp * r * float(start), measured))
    return out[0], out[1], end


def _mean(frame: dict, column: str, start: float, end: float) -> float:
    t = np.asarray(frame["time"])
    inside = (t > start) & (t <= end)
    return float(np.mean(np.asarray(frame[column])[inside])) if inside.any() else float("nan")


def replay_step(session, case: pd.Series, urdf: str, params: dict, warmup: float = WARMUP_S) -> tuple[dict, dict]:
    """One step on ``params["engine"]``: its trace (time from the step's start) and its summary row
    (``STEP_COLUMNS``: the simulated start state, steady means and heading change, health, wall time)."""
    dt = params["physics"]["timestep"]
    left, right, end = step_wheels(session, case, warmup, dt)
    friction = params["class"]["friction"]
    heading = start_heading(params["seed"], case.dataset, case.terrain_class, case.session, case.case)
    scenario = scenario_from(
        params, urdf, flat_terrain(case.terrain_class, friction), ((0.0, 0.0, heading),), ground_friction=friction
    )
    wheels = scenario.robot.joint_speeds(left, right)
    recording = Recording.from_params(params)
    began = time.perf_counter()
    frame, meta = run_commands(
        params["engine"], wheels, scenario, recording, stable_seed(params["seed"], params["engine"], case.case)
    )
    wall = time.perf_counter() - began
    a, b = warmup + float(case.steady_start), warmup + end
    sim_wz = _mean(frame, "yaw_rate", a, b)
    yaw = np.asarray(frame["yaw"])
    t = np.asarray(frame["time"])
    inside = (t > a) & (t <= b)
    row = {
        "case": case.case,
        "session": case.session,
        "terrain_class": case.terrain_class,
        "step": int(case.step),
        "engine": params["engine"],
        "status": meta["health"]["status"],
        "reasons": "; ".join(meta["health"]["reasons"]),
        "warmup": warmup,
        "start_heading_deg": float(np.degrees(heading)),
        "sim_start_vx": _mean(frame, "v_forward", warmup - START_WINDOW_S, warmup),
        "sim_start_wz": _mean(frame, "yaw_rate", warmup - START_WINDOW_S, warmup),
        "sim_v": _mean(frame, "v_forward", a, b),
        "sim_yaw_rate": sim_wz,
        "sim_heading": float(yaw[inside][-1] - yaw[inside][0]) if inside.sum() > 1 else float("nan"),
        "wall_time": wall,
        "sim_time": meta["sim_time"],
    }
    trace = {c: np.asarray(frame[c]) for c in TRACE_COLUMNS[2:]}
    trace["t_step"] = t - warmup
    trace["step"] = np.full(len(t), int(case.step))
    return trace, row | {"_meta": meta}


def session_cases(cases: pd.DataFrame, session: str, cases_csv: str = "cases.csv") -> pd.DataFrame:
    chosen = cases[cases.session == session]
    if chosen.empty:
        known = ", ".join(sorted(cases.session.unique())) or "none"
        raise InputError(
            cases_csv,
            f"has no session {session!r} to replay",
            f"name one of its sessions ({known}), or rerun the drive_tables rule over the folder that holds it",
        )
    return chosen


def replay_session(session, cases: pd.DataFrame, urdf: str, params: dict, warmup: float = WARMUP_S):
    """Every chosen step of one session on one engine: the traces (``TRACE_COLUMNS``) and the step table
    (``STEP_COLUMNS``). A step whose engine diverges is kept with its health status and reasons (the
    project's health check), so the comparison reports it instead of averaging it."""
    traces, rows = [], []
    for _, case in cases.sort_values("step").iterrows():
        trace, row = replay_step(session, case, urdf, params, warmup)
        row.pop("_meta")
        traces.append(pd.DataFrame(trace)[TRACE_COLUMNS])
        rows.append(row)
    trace = pd.concat(traces, ignore_index=True) if traces else pd.DataFrame(columns=TRACE_COLUMNS)
    return trace, pd.DataFrame(rows, columns=STEP_COLUMNS)


def open_session(folder: str, declared: dict, name: str):
    """The one DRIVE session under ``folder`` (a session folder the user named), read with the config's
    declaration of the dataset (its per-session overrides)."""
    from simpick.real.drive import open_drive

    dataset = open_drive(folder, declared=declared, name=name)
    if len(dataset.sessions) != 1:
        raise InputError(folder, f"holds {len(dataset.sessions)} sessions, not one", "name one session folder")
    return dataset.sessions[0]


def hung_rows(cases: pd.DataFrame, engine: str, reason: str) -> pd.DataFrame:
    rows = [
        {
            "case": c.case,
            "session": c.session,
            "terrain_class": c.terrain_class,
            "step": int(c.step),
            "engine": engine,
            "status": "failed",
            "reasons": reason,
        }
        for c in cases.itertuples()
    ]
    return pd.DataFrame(rows, columns=STEP_COLUMNS)


def replay_job(inputs: dict, params: dict, outputs: dict, timeout: float) -> None:
    """Rule drive_replay: one engine x one session. Reads the session folder (a pickle: only the folder the
    user named), replays its chosen steps (``params["replay"]``: every, max_steps_per_session, warmup) and
    writes the traces (``outputs["trace"]``, Parquet) and the step table (``outputs["steps"]``, CSV). Under
    the watchdog: a job still running after ``timeout`` s writes every step as failed ("hung") and ends."""
    from simpick.simulate.watchdog import Watchdog, hung_reason
    from simpick.tables import write_csv

    replay = params["replay"]
    cases = session_cases(pd.read_csv(inputs["cases"]), params["session"], inputs["cases"])
    chosen = select_steps(cases, replay["every"], replay["max_steps_per_session"])
    session = open_session(params["folder"], params["declared"], params["dataset"])
    terrain = session.terrain_class
    if terrain not in params["classes"]:
        raise InputError(
            "real_data.classes in the config",
            f"has no terrain class {terrain!r} (session {session.name})",
            f"add {terrain}: {{friction: ..., source: ...}} under real_data.classes",
        )
    case_params = dict(params, terrain_class=terrain, **{"class": params["classes"][terrain]})

    def hung() -> None:
        write_csv(hung_rows(chosen, params["engine"], hung_reason(timeout)), outputs["steps"])
        pd.DataFrame(columns=TRACE_COLUMNS).to_parquet(outputs["trace"])

    Path(outputs["trace"]).parent.mkdir(parents=True, exist_ok=True)
    with Watchdog(timeout, hung):
        trace, rows = replay_session(session, chosen, inputs["urdf"], case_params, float(replay["warmup"]))
    trace.to_parquet(outputs["trace"])
    write_csv(rows, outputs["steps"])


def replay_models(chosen: list[str] | None, configured: list[str], unavailable: dict | None = None) -> list[str]:
    """The models that replay the DRIVE steps: ``drive_replay.models`` (None: every configured one), in the
    configured order. A model that is not configured is one clear error; one configured but not installed
    here is left out (the study says so at planning time)."""
    unavailable = unavailable or {}
    if chosen is None:
        return list(configured)
    unknown = [m for m in chosen if m not in configured and m not in unavailable]
    if unknown:
        raise InputError(
            "drive_replay.models in the config",
            f"names {unknown}, which the study does not configure",
            f"choose among {configured} (engines and baselines), or null for all",
        )
    return [m for m in configured if m in chosen]
