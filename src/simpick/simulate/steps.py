"""Step units replayed in an engine (:mod:`simpick.real.steps`: what a reader of DRIVE's sessions, or of any
dataset told to hold one command per step, hands on): each step on flat ground with its terrain's
friction, from the state the real robot was in at the step's start, then driven by the step's measured
wheel speeds (the reader's wheels table). One step is a case of the ``steps`` kind
(:data:`simpick.simulate.jobs.PREPARE`: :func:`prepare_step`); a job replays one session's chosen steps
(:func:`replay_job`), and the calibration replays them in-process (:func:`replay_step`).

How a step starts. The engines have no common way to set a body velocity, and a body velocity set by hand
would start without the contact forces and slip that go with it (every engine would then spend the first
part of the step settling from an inconsistent state, each in its own way). So each step starts with a
warm-up: the robot, at rest on the ground, is driven for ``warmup`` seconds (the first :data:`RAMP_S` a ramp
from rest) at the wheel speeds the real
robot measured just before the step (for DRIVE, the previous step's last 0.5 s: the cases'
``start_wheel_left/right``). That is long enough for each engine to reach its own steady state
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
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pandas as pd
from pydantic import Field

from simpick.errors import InputError
from simpick.real.settings import StepReplay, TerrainClass
from simpick.simulate.real import flat_terrain, noise_seed_of, real_case, start_heading
from simpick.simulate.real_settings import RealCaseParams
from simpick.simulate.run import Recording, Unit, run_commands, scenario_from
from simpick.simulate.settings import SimulationParams
from simpick.simulate.step_rows import STEP_COLUMNS, hung_rows, step_row

# s of the previous step's measured wheel speeds before a step (module doc): the replay section's default
WARMUP_S = StepReplay.model_fields["warmup"].default
RAMP_S = 1.0  # s of the warm-up over which the wheels speed up from rest (no jump that the servos cannot follow)
TRACE_COLUMNS = ["step", "t_step", "v_forward", "yaw_rate", "wz", "x", "y", "yaw", "roll", "pitch", "z", "cmd_left"]


class StepsParams(SimulationParams):
    """What a replay of step units on one model reads: the model's simulation settings, every terrain class's
    ground (a step's is its case's) and how the steps are replayed."""

    classes: dict[str, TerrainClass] = Field(description="real_data.classes: each terrain class's ground")
    replay: StepReplay


class SessionReplayParams(StepsParams):
    """What rule drive_replay's job (:func:`replay_job`) reads (the plan's simpick.sources.drive.case_params):
    the steps' settings and the session replayed."""

    session: str = Field(description="the session whose chosen steps the job replays")


class StepUnitParams(StepsParams, Unit):
    """What a simulate job of the ``steps`` kind (:func:`prepare_step`) reads: the steps' settings and which
    unit of step cases it is."""


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


def read_wheels(path: str) -> pd.DataFrame:
    """The wheels table a reader wrote (simpick.real.steps.WHEEL_COLUMNS)."""
    return pd.read_parquet(path)


def step_samples(wheels: pd.DataFrame, session: str, step: int, where: str = "the wheels table") -> pd.DataFrame:
    """One step's measured wheel speeds (time from the step's start, v_left, v_right in m/s, the wheel
    radius) from the wheels table; a step it lacks is one clear error naming the table."""
    s = wheels[(wheels.session == session) & (wheels.step == step)]
    if s.empty:
        raise InputError(
            where,
            f"has no wheel speeds of session {session!r} step {step}",
            "rerun the import step (its tables job) over the folder that holds the session",
        )
    return s


def step_wheels(samples: pd.DataFrame, case, warmup: float, dt: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Rim speeds (m/s) of the left and right wheels at every physics step (time ``-warmup`` .. the step's
    end): the warm-up, from rest, ramped over :data:`RAMP_S` to the start speeds and held there; then the
    step's measured speeds (:func:`_interpolated`); and the step's end (s from its start)."""
    r = float(samples.wheel_radius.iloc[0])
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


def drive_step(samples: pd.DataFrame, case, urdf: str, params: RealCaseParams | Mapping, warmup: float = WARMUP_S):
    """One step on the params' model (:class:`RealCaseParams`: its ``class``, the terrain's ground): the engine's
    frame (time from the warm-up's start), its metadata and the start heading (rad)."""
    p = real_case(params)
    dt = p.physics.timestep
    left, right, _ = step_wheels(samples, case, warmup, dt)
    friction = p.ground.friction
    heading = start_heading(p.seed, case.dataset, case.terrain_class, case.session, case.case)
    scenario = scenario_from(
        p, urdf, flat_terrain(case.terrain_class, friction), ((0.0, 0.0, heading),), ground_friction=friction
    )
    wheels = scenario.robot.joint_speeds(left, right)
    recording = Recording.from_params(p)
    began = time.perf_counter()
    frame, meta = run_commands(p.engine, wheels, scenario, recording, noise_seed_of(p, p.engine, case.case))
    meta = meta | {"wall_time_step": time.perf_counter() - began, "start_heading": float(heading), "warmup": warmup}
    return frame, meta


def replay_step(
    samples: pd.DataFrame, case, urdf: str, params: RealCaseParams | Mapping, warmup: float = WARMUP_S
) -> tuple[dict, dict]:
    """One step on the params' model (its measured wheel speeds: :func:`step_samples`): its trace (time
    from the step's start) and its summary row (:func:`step_row`)."""
    frame, meta = drive_step(samples, case, urdf, params, warmup)
    row = step_row(frame, meta, case)
    t = np.asarray(frame["time"])
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


def replay_session(
    wheels: pd.DataFrame,
    cases: pd.DataFrame,
    urdf: str,
    params: RealCaseParams | Mapping,
    warmup: float = WARMUP_S,
    where: str = "",
):
    """Every chosen step of one session on one engine: the traces (``TRACE_COLUMNS``) and the step table
    (``STEP_COLUMNS``). A step whose engine diverges is kept with its health status and reasons (the
    project's health check), so the comparison reports it instead of averaging it."""
    p = real_case(params)
    traces, rows = [], []
    for _, case in cases.sort_values("step").iterrows():
        samples = step_samples(wheels, case.session, int(case.step), where or "the wheels table")
        trace, row = replay_step(samples, case, urdf, p, warmup)
        row.pop("_meta")
        traces.append(pd.DataFrame(trace)[TRACE_COLUMNS])
        rows.append(row)
    trace = pd.concat(traces, ignore_index=True) if traces else pd.DataFrame(columns=TRACE_COLUMNS)
    return trace, pd.DataFrame(rows, columns=STEP_COLUMNS)


def ground(p: StepsParams, terrain: str, unit: str) -> RealCaseParams:
    """A real-data case's params on the unit's model: its settings with terrain class ``terrain``'s ground
    (``classes``: real_data.classes)."""
    if terrain not in p.classes:
        raise InputError(
            "real_data.classes in the config",
            f"has no terrain class {terrain!r} ({unit})",
            f"add {terrain}: {{friction: ..., source: ...}} under real_data.classes",
        )
    simulation = {name: getattr(p, name) for name in SimulationParams.model_fields}
    return RealCaseParams(**simulation, terrain_class=terrain, ground=p.classes[terrain])


def prepare_step(urdf: str, inputs: dict, params: Mapping, name: str):
    """One step unit (the ``steps`` kind, :data:`simpick.simulate.jobs.PREPARE`): case ``name`` of the case
    table ``inputs["cases"]``, driven by its measured wheel speeds (``inputs["wheels"]``) after the warm-up
    (:class:`StepUnitParams`: ``replay.warmup``). Its trace keeps the warm-up (time from the warm-up's start);
    its ``window`` is the steady part compared."""
    p = StepUnitParams.model_validate(params)
    cases = pd.read_csv(inputs["cases"])
    found = cases[cases.case == name]
    if found.empty:
        raise InputError(inputs["cases"], f"has no case {name!r}", "rerun the import step over the dataset folder")
    case = found.iloc[0]
    warmup = p.replay.warmup
    samples = step_samples(read_wheels(inputs["wheels"]), case.session, int(case.step), inputs["wheels"])
    which = {
        "terrain": case.terrain_class,
        "motion": f"step-{int(case.step):03d}",
        "test": case.case,
        "dataset": case.dataset,
        "run": case.session,
        "segment": f"{int(case.step):03d}",
        "window": [warmup + float(case.steady_start), warmup + float(case.steady_end)],
    }
    unit_params = ground(p, case.terrain_class, f"session {case.session}")
    return which, lambda: drive_step(samples, case, urdf, unit_params, warmup)


def replay_job(inputs: dict, params: Mapping, outputs: dict, timeout: float) -> None:
    """One engine x one session (:class:`SessionReplayParams`): its chosen steps (``replay``: every,
    max_steps_per_session, warmup), driven by the wheels table (``inputs["wheels"]``, written by the reader's
    import step), into the traces (``outputs["trace"]``, Parquet) and the step table (``outputs["steps"]``,
    CSV). Under the watchdog: a job still running after ``timeout`` s writes every step as failed ("hung") and
    ends."""
    from simpick.simulate.calibrated import with_calibrated
    from simpick.simulate.watchdog import Watchdog, hung_reason
    from simpick.tables import write_csv

    # a calibrated profile's fitted settings (its fit's file, an input) over its plan-time (tuned) settings
    params, _ = with_calibrated(params, inputs.get("calibrated"))
    p = SessionReplayParams.model_validate(params)
    replay = p.replay
    cases = session_cases(pd.read_csv(inputs["cases"]), p.session, inputs["cases"])
    chosen = select_steps(cases, replay.every, replay.max_steps_per_session)
    terrains = sorted(set(cases.terrain_class))
    if len(terrains) != 1:
        raise InputError(inputs["cases"], f"gives session {p.session!r} terrains {terrains}", "one a session")
    case_params = ground(p, terrains[0], f"session {p.session}")

    def hung() -> None:
        write_csv(hung_rows(chosen, p.engine, hung_reason(timeout)), outputs["steps"])
        pd.DataFrame(columns=TRACE_COLUMNS).to_parquet(outputs["trace"])

    Path(outputs["trace"]).parent.mkdir(parents=True, exist_ok=True)
    wheels = read_wheels(inputs["wheels"])
    with Watchdog(timeout, hung):
        trace, rows = replay_session(wheels, chosen, inputs["urdf"], case_params, replay.warmup, inputs["wheels"])
    trace.to_parquet(outputs["trace"])
    write_csv(rows, outputs["steps"])
