"""How the real robot turns across the command space, beside the Coulomb reference and each engine.

DRIVE's steps sample the whole command space, and :mod:`simpick.real.steps` bins their yaw-rate gain
(gyro yaw rate over the kinematic rate of the measured wheels, ``w_kin = r (w_R - w_L) / B``) per terrain
against the commanded forward speed, turn radius and wheel-speed difference (:data:`simpick.real.steps.BINS`).
This module puts two models at the same commands:

* the quasi-static Coulomb gain for the robot's geometry and loads (:mod:`simpick.coulomb`), which depends
  on the command only through its turn radius (the dissipation is homogeneous in the rim speeds);
* each engine's steady gain on flat rigid ground with the terrain's friction, one short run per command,
  built and measured exactly as the validation's ``yaw_gain`` case (:func:`simpick.studies.validation.cases.run_case`).

The command of a bin (its *representative step*) is the bin's median step by the binned variable (the lower
of the two middle steps for an even count): the engine is driven at that step's measured steady wheel
speeds, the speeds the real gain is measured against, so the engine's gain and the real one share their
denominator. Only turning steps (``|w_kin| > MIN_TURN``) enter a bin: at equal wheel speeds the gain is
0 / 0 and undefined, so such a command is never in the grid.

An engine's gain is the mean over the run's second half, as in the validation; where an engine has no steady
turn on flat ground the number is that window's mean and no more. Measured on the Warthog at the 37 commands
of the shared sessions, 3-6 s against 5-10 s: MuJoCo and ODE within 0.001, PhysX within 0.003 at most
commands but up to 0.26 at a few, PyBullet up to 0.28 (its gain changes as the robot's heading turns
against the world axes, as the validation's heading cases show on the Husky).

All gains here are against DRIVE's kinematic yaw rate (``r`` and ``B`` of the dataset's geometry). An
engine's or the Coulomb model's rate against the config's ``robot.track`` is converted with the same wheel
speeds, so a config whose track differs from DRIVE's baseline still compares like with like.
"""

from __future__ import annotations

import math
import sys
import time
import traceback
from typing import Any

import numpy as np
import pandas as pd
from pydantic import Field

from simpick.coulomb import ContactLayout, contact_layout, yaw_rate_gain
from simpick.engines import get_engine
from simpick.errors import InputError
from simpick.inputs.robot import RobotSpec
from simpick.inputs.robot.settings import RobotParams
from simpick.params import JobParams, PhysicsStep, Positive
from simpick.real.settings import Ground
from simpick.real.steps import BINS, MIN_TURN, gain_bins
from simpick.tables import write_csv

# s simulated per command; the gain is the mean yaw rate over its second half, as the validation's yaw_gain
# case, whose default length this is. Shorter runs were measured on the Warthog over the 37 commands of the
# shared DRIVE sessions against 6 s: at 3 s the gain differed by up to 0.010 (MuJoCo) and 0.041 (ODE), at
# 4 s by 0.003 and 0.014, the largest at the fast turns (lateral acceleration 2.5-3.5 m/s^2), which settle
# slowest; at 6 s and 10 s MuJoCo's and ODE's gains agreed within 0.001.
DURATION = 6.0

GRID_COLUMNS = [
    "terrain_class",
    "variable",
    "bin",
    "steps",
    "gain_median",
    "gain_q25",
    "gain_q75",
    "session",
    "step",
    "value",
    "wheel_left",
    "wheel_right",
    "v_kin",
    "w_kin",
    "real_gain",
    "friction",
]
COULOMB_COLUMNS = ["coulomb_gain", "coulomb_front_load", "coulomb_back_load"]
ENGINE_COLUMNS = [
    "engine",
    "engine_version",
    "terrain_class",
    "session",
    "step",
    "wheel_left",
    "wheel_right",
    "friction",
    "duration",
    "v",
    "w",
    "engine_gain",
    "status",
    "reason",
    "wall_time",
]


def _representative(group: pd.DataFrame, variable: str) -> pd.Series:
    """The bin's median step by |variable| (the lower middle one for an even count; ties by session, step)."""
    ordered = group.assign(_key=group[variable].abs()).sort_values(["_key", "session", "step"], kind="stable")
    return ordered.iloc[(len(ordered) - 1) // 2]


def command_grid(steps: pd.DataFrame, friction: dict[str, float], bins: dict | None = None) -> pd.DataFrame:
    """One row per terrain x binned variable x bin of the real turning steps: the real gain (steps,
    median, quartiles, as :func:`simpick.real.steps.gain_bins`), the bin's representative step (module doc)
    with its measured wheel speeds (rad/s), kinematic twist and own gain, and the terrain's friction
    (``friction``: terrain class -> its Coulomb coefficient, from the config's ``real_data.classes``)."""
    bins = BINS if bins is None else bins
    turning = steps[steps.turning.astype(bool) & steps.gain.notna() & (steps.w_kin.abs() > MIN_TURN)].copy()
    rows = []
    for variable, edges in bins.items():
        real = gain_bins(turning, variable, edges).set_index(["terrain_class", "bin"])
        t = turning.assign(bin=pd.cut(turning[variable].abs(), edges, include_lowest=True).astype(str))
        for (terrain, label), group in t.groupby(["terrain_class", "bin"], sort=False):
            if terrain not in friction:
                raise InputError(
                    f"real_data.classes.{terrain}",
                    f"the DRIVE terrain {terrain!r} has no ground model, so its friction is unknown",
                    f"add it: real_data: {{classes: {{{terrain}: {{friction: 0.6, source: ...}}}}}}",
                )
            pick = _representative(group, variable)
            stats = real.loc[(terrain, label)]
            rows.append(
                {
                    "terrain_class": terrain,
                    "variable": variable,
                    "bin": label,
                    "steps": int(stats["steps"]),
                    "gain_median": stats["gain_median"],
                    "gain_q25": stats["gain_q25"],
                    "gain_q75": stats["gain_q75"],
                    "session": pick["session"],
                    "step": int(pick["step"]),
                    "value": abs(float(pick[variable])),
                    "wheel_left": float(pick["wheel_left"]),
                    "wheel_right": float(pick["wheel_right"]),
                    "v_kin": float(pick["v_kin"]),
                    "w_kin": float(pick["w_kin"]),
                    "real_gain": float(pick["gain"]),
                    "friction": float(friction[terrain]),
                }
            )
    grid = pd.DataFrame(rows, columns=GRID_COLUMNS)
    order = {v: i for i, v in enumerate(bins)}
    return grid.sort_values(
        ["terrain_class", "variable", "value"], key=lambda c: c.map(order) if c.name == "variable" else c
    ).reset_index(drop=True)


def coulomb_layout(robot: RobotSpec, points_per_wheel: int | None = None) -> ContactLayout:
    """The robot's contact layout and static wheel loads for the Coulomb reference (``points_per_wheel``:
    as :func:`simpick.coulomb.contact_layout`; None, the line contact across each wheel's width).

    This is where a suspended robot's loads enter. :func:`simpick.coulomb.contact_layout` shares the weight
    as a rigid body on equally stiff contacts (loads linear in position). For a robot symmetric about its
    x axis on four wheels, whole-body balance of force and pitch moment already fixes the front and back
    loads, so that rigid share is also the balance of the coupled rockers: for the Warthog (pivots 0.04 m
    ahead of the chassis origin, wheels at x +0.50 / -0.42, centre of mass 0.0246 m ahead) front 616 N and
    back 659 N per wheel, which tests/test_turnmap.py checks against the lever balance done by hand. A
    model of loads that departs from the rigid share (an asymmetric or uncoupled suspension) replaces this
    function's body."""
    return contact_layout(robot, points_per_wheel)


def _wheel_twist(robot: RobotSpec, track: float, left: float, right: float) -> tuple[float, float]:
    """(v, w) that the config's controller (``robot.track``) maps back to these wheel speeds (rad/s)."""
    r = robot.wheel_radius
    return r * (left + right) / 2, r * (right - left) / track


def coulomb_gains(
    grid: pd.DataFrame, robot: RobotSpec, track: float, points_per_wheel: int | None = None
) -> pd.DataFrame:
    """The grid with the Coulomb gain at each representative command (against DRIVE's w_kin) and the
    layout's front / back wheel loads (N, mean over the wheels ahead of / behind the centre of mass)."""
    layout = coulomb_layout(robot, points_per_wheel)
    per_wheel = np.bincount(layout.wheel, weights=layout.loads)
    x = np.array([w.position[0] for w in robot.wheels])
    front, back = per_wheel[: len(x)][x > layout.com[0]], per_wheel[: len(x)][x <= layout.com[0]]
    gains = []
    for row in grid.itertuples():
        v, w = _wheel_twist(robot, track, row.wheel_left, row.wheel_right)
        gains.append(yaw_rate_gain(layout, v, w, track) * w / row.w_kin)
    return grid.assign(
        coulomb_gain=gains,
        coulomb_front_load=float(front.mean()) if len(front) else math.nan,
        coulomb_back_load=float(back.mean()) if len(back) else math.nan,
    )


def unique_commands(grid: pd.DataFrame) -> pd.DataFrame:
    """The grid's distinct runs: one per terrain and representative step (a step can represent a bin of
    several variables)."""
    keys = ["terrain_class", "session", "step", "wheel_left", "wheel_right", "w_kin", "friction"]
    return grid[keys].drop_duplicates(["terrain_class", "session", "step"]).reset_index(drop=True)


def engine_gains(grid: pd.DataFrame, setup, duration: float = DURATION) -> pd.DataFrame:
    """Each distinct command of ``grid`` run on ``setup``'s engine (a
    :class:`simpick.studies.validation.cases.Setup`) as the validation's yaw_gain case at the terrain's friction:
    the steady gain against DRIVE's w_kin, the run's status and wall time (s). An engine that refuses the
    robot (e.g. a suspension it does not simulate) gives every row status "refused" with its reason; a run
    that raises is "failed" with the error, and the others still run."""
    from simpick.engines.base import Scenario
    from simpick.engines.runner import check_layout
    from simpick.studies.validation.cases import FLAT, run_case

    engine = get_engine(setup.engine)
    version = engine.version()
    refusal = None
    try:
        world = Scenario(
            robot=setup.robot,
            terrain=dict(FLAT),
            ground_friction=0.0,
            timestep=setup.timestep,
            max_wheel_torque=setup.max_wheel_torque,
            starts=((0.0, 0.0, 0.0),),
        )
        check_layout(engine, world)
    except InputError as exc:
        refusal = str(exc)
    rows = []
    for c in unique_commands(grid).itertuples():
        v, w = _wheel_twist(setup.robot, setup.track, c.wheel_left, c.wheel_right)
        row = {
            "engine": setup.engine,
            "engine_version": version,
            "terrain_class": c.terrain_class,
            "session": c.session,
            "step": c.step,
            "wheel_left": c.wheel_left,
            "wheel_right": c.wheel_right,
            "friction": c.friction,
            "duration": float(duration),
            "v": v,
            "w": w,
            "engine_gain": math.nan,
            "status": "refused",
            "reason": refusal or "",
            "wall_time": 0.0,
        }
        if refusal is None:
            start = time.perf_counter()
            params = {"kind": "yaw_gain", "v": v, "w": w, "mu": float(c.friction), "duration": float(duration)}
            try:
                result = run_case(setup, f"turnmap_{c.terrain_class}_{c.session}_{c.step}", params)
                gain = result["checks"][0]["engine_value"] if result["checks"] else math.nan
                row.update(
                    engine_gain=gain * w / c.w_kin,
                    status=result["status"],
                    reason="; ".join(result["reasons"]),
                    wall_time=result["wall_time"],
                )
            except Exception as exc:  # noqa: BLE001 - recorded as this command's failure; the others run on
                traceback.print_exc()
                row.update(
                    status="failed",
                    reason=f"crashed: {type(exc).__name__}: {exc}",
                    wall_time=time.perf_counter() - start,
                )
        rows.append(row)
    return pd.DataFrame(rows, columns=ENGINE_COLUMNS)


def combined_table(grid: pd.DataFrame, engines: list[pd.DataFrame]) -> pd.DataFrame:
    """The grid (real gain per bin, representative command, Coulomb gain) beside each engine's gain: one row
    per terrain x variable x bin x engine (engine "" where no engine table is given)."""
    keys = ["terrain_class", "session", "step"]
    frames = [
        grid.merge(e[keys + ["engine", "engine_gain", "status", "reason", "wall_time"]], on=keys, how="left")
        for e in engines
        if len(e)
    ]
    if not frames:
        return grid.assign(engine="", engine_gain=math.nan, status="", reason="", wall_time=math.nan)
    return pd.concat(frames, ignore_index=True)


def wall_times(engines: list[pd.DataFrame]) -> pd.DataFrame:
    """Per engine: runs, runs ok, simulated s, and the map's wall time (s, the sum over its runs)."""
    rows = [
        {
            "engine": e.engine.iloc[0],
            "runs": len(e),
            "ok": int((e.status == "ok").sum()),
            "simulated_s": float(e.duration[e.status == "ok"].sum()),
            "wall_time": float(e.wall_time.sum()),
        }
        for e in engines
        if len(e)
    ]
    return pd.DataFrame(rows, columns=["engine", "runs", "ok", "simulated_s", "wall_time"])


# --- the workflow's jobs (rules/turnmap.smk) ---


class TurnmapGridParams(JobParams):
    """What rule turnmap_grid reads: the robot (the Coulomb reference's geometry and loads) and each terrain
    class's ground (its friction). Not the IMU model, the health limits or the validation's cases, so editing
    those reruns nothing here."""

    robot: RobotParams
    classes: dict[str, Ground] = Field(description="terrain class -> its ground (the config's real_data.classes)")


class TurnmapEngineParams(TurnmapGridParams):
    """What rule turnmap_engine reads: the grid's settings, and the engine, its settings and the timestep."""

    engine: str
    engine_settings: dict[str, Any] = Field(
        description="the engine's settings as the config gives them; its adapter's own settings model checks them "
        "(the config's engines block at planning time, the adapter in the job)"
    )
    physics: PhysicsStep
    duration: Positive = Field(DURATION, description="s simulated per command")


def grid_job(steps_csv, urdf, params: dict, output) -> pd.DataFrame:
    """Rule turnmap_grid: the real steps' bins, their representative commands and the Coulomb gain."""
    p = TurnmapGridParams.model_validate(params)
    steps = pd.read_csv(steps_csv)
    grid = command_grid(steps, {name: ground.friction for name, ground in p.classes.items()})
    grid = coulomb_gains(grid, p.robot.spec(urdf), p.robot.track)
    write_csv(grid, output)
    return grid


def engine_job(grid_csv, urdf, params: dict, output) -> pd.DataFrame:
    """Rule turnmap_engine: one engine's gain at every distinct command of the grid."""
    from simpick.studies.validation.cases import Setup

    p = TurnmapEngineParams.model_validate(params)
    setup = Setup(
        engine=p.engine,
        robot=p.robot.spec(urdf),
        timestep=p.physics.timestep,
        max_wheel_torque=p.robot.max_wheel_torque,
        track=p.robot.track,
        settings=p.engine_settings,
    )
    table = engine_gains(pd.read_csv(grid_csv), setup, p.duration)
    for line in wall_times([table]).itertuples():
        print(
            f"simpick: turnmap {line.engine}: {line.ok}/{line.runs} runs ok in {line.wall_time:.1f} s", file=sys.stderr
        )
    write_csv(table, output)
    return table


def table_job(grid_csv, engine_csvs, outputs: dict) -> pd.DataFrame:
    """Rule turnmap_table: the combined table and the per-engine wall times."""
    engines = [pd.read_csv(p, keep_default_na=False, na_values=[""]) for p in engine_csvs]
    table = combined_table(pd.read_csv(grid_csv), engines)
    write_csv(table, outputs["table"])
    write_csv(wall_times(engines), outputs["wall"])
    return table


__all__ = [
    "DURATION",
    "TurnmapEngineParams",
    "TurnmapGridParams",
    "coulomb_gains",
    "coulomb_layout",
    "combined_table",
    "command_grid",
    "engine_gains",
    "unique_commands",
    "wall_times",
]
