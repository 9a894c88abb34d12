"""Engines against analytic mechanics: cases with known answers, run before any comparison
with the real robot (METHOD.md section 6).

Every case runs the study's own robot, timestep, wheel-torque bound and engine settings on
flat rigid ground with one Coulomb coefficient, and measures one or more *checks*: the
engine's value beside the value mechanics predicts. Pass or fail is decided later, by
:func:`summarise` with the tolerances of the config, so editing a tolerance re-judges the
stored runs without stepping an engine again.

Case kinds (their parameters come from ``validation.cases`` in the config):

``yaw_gain``  (v, w, mu, heading) skid-steer turning from start heading ``heading`` (degrees);
    steady yaw rate / commanded w over the second half of the run against
    :mod:`simpick.coulomb`'s quasi-static solution for this robot's contact layout and loads
    (the same for w and -w: mirroring a turn mirrors the COM offset, and the gain does not
    depend on the offset's side). With ``friction_ratio`` r the engine's own
    ``friction_ratio`` setting is set to r and the analytic value is the anisotropic (elliptic)
    Coulomb gain at r; an engine without that setting skips the case, saying so. Such cases stay
    out of the invariance checks and the gains table (which compare isotropic turning).
``straight``  (v, mu, heading) forward speed against measured wheel speed x radius (rolling
    without slip), and the heading drift (none expected).
``slide``     (v, mu, heading) cruise from start heading ``heading``, then every wheel commanded
    to stop (locked by its servo): the robot slides to rest with deceleration mu g.
``incline``   (mu, angle_factor, heading) parked with locked wheels on a slope of angle_factor x
    atan(mu) (gravity tilted, same mechanics as a tilted plane), downhill at ``heading`` degrees
    from the robot's back (0: along -x; 45: across the world axes): below atan(mu) it stays
    (creep speed 0), above it slides down with g (sin a - mu cos a) and does not yaw.
``rest``      (mu) parked on level ground: accelerometer z = g, gyro 0, no creep.

Cases for a robot on a passive suspension (rockers; skipped, saying so, on a robot without one):

``rest_pose`` (mu) parked on level ground: the mechanism balances the weight with every joint at
    zero (:func:`simpick.coulomb.contact_layout` refuses a description where it cannot), so the
    chassis rests level (pitch 0, roll 0) at the description's resting height ``base_height``.
    Pitch and roll are judged by their worst sample over the measured part (the second half), the
    height by its mean: a chassis that rocks or is still settling fails.
    Uncoupled rockers have no such pose: the chassis tips onto the joint limits (the Warthog's
    public description: 0.15 rad), which this case catches.
``articulation`` (h, mu, v) two coupled rockers twisted against each other: the robot drives at
    ``v`` onto two blocks of height ``h``, one under the leading rocker's front wheel, one under
    the other rocker's back wheel (diagonally opposite), stops on them and is held. The blocks are
    stairs of 1 cm layers 4 cm apart, so that no engine's climbing traction is what is tested. Each rocker
    then pitches by theta = -asin(dz / L) (dz its front wheel's rise over its back wheel's, L the
    axle distance), and the coupling q(follower) = m q(leader) sets the chassis' pitch to
    (theta_f - m theta_l) / (1 - m): for a differential (m = -1) the mean of the two, 0 for equal
    arms. The pivots rise by the blocks' height shared by the lever arms, which gives the chassis'
    roll and height. A rigid robot rests on three of the four wheels instead, and uncoupled rockers
    drop onto their limits: both show as pitch or roll.

Invariance checks. Flat isotropic ground has no preferred direction, and the
mirror image of a turn is a turn the other way: an engine's gain must not depend on the
start heading nor on the turn's direction. :func:`summarise` adds, from the yaw_gain cases
themselves (no extra engine runs), per group of cases with the same (v, |w|, mu):

``turn_asymmetry``  the largest |gain(w) / analytic - gain(-w) / analytic| over the headings
    at which both directions ran;
``heading_spread``  per turn direction, max - min of gain / analytic over the headings.

:func:`gain_table` gives each engine's gain per group with its spread (left, right, over
headings): results/validation/gains.csv, which the report and its gain figure read.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
import traceback
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from simpick.coulomb import braking_deceleration as coulomb_braking
from simpick.coulomb import contact_layout, yaw_rate_gain
from simpick.engines import get_engine
from simpick.engines.base import GRAVITY, PhysicsRecord, Scenario
from simpick.engines.kinematics import euler_rpy, rotation_matrices
from simpick.errors import InputError
from simpick.inputs.motions import side_speeds
from simpick.inputs.robot import RobotSpec, load_from_config
from simpick.simulate.imu import block_average
from simpick.simulate.watchdog import DEFAULT_TIMEOUT_S, Watchdog, hung_reason
from simpick.tables import write_csv

KINDS = ("yaw_gain", "straight", "slide", "incline", "rest", "rest_pose", "articulation")
# deg: a case's start heading (the downhill direction of an incline) when it names none
DEFAULT_HEADING = 0.0
# s: a parked case (incline, rest) measures after the spawn drop and the servos' lock-up settle
SETTLE_S = 1.0
# s: the least it then measures (100 samples at 1 kHz: a slope fit and a creep speed need some)
MIN_MEASURED_S = 0.1
FLAT = {"schema": "simpick.inputs.terrain/1", "name": "flat", "boxes": [], "spheres": [], "friction": 0.0}

# Quantity -> (unit, how its error is measured): "relative" |e - a| / |a|, or "absolute" |e - a|.
QUANTITIES = {
    "yaw_rate_gain": ("1", "relative"),
    "speed_over_wheel_speed": ("1", "relative"),
    "heading_drift": ("rad", "absolute"),
    "slide_yaw": ("rad", "absolute"),
    "deceleration": ("m/s^2", "relative"),
    "creep_speed": ("m/s", "absolute"),
    "slide_acceleration": ("m/s^2", "relative"),
    "accel_z": ("m/s^2", "absolute"),
    "gyro_max": ("rad/s", "absolute"),
    "creep_distance": ("m", "absolute"),
    "turn_asymmetry": ("1", "absolute"),
    "heading_spread": ("1", "absolute"),
    "chassis_pitch": ("rad", "absolute"),
    "chassis_roll": ("rad", "absolute"),
    "chassis_height": ("m", "absolute"),
}


@dataclass(frozen=True)
class Setup:
    """What every case shares with the study: the robot and the engine's settings."""

    engine: str
    robot: RobotSpec
    timestep: float
    max_wheel_torque: float
    track: float
    settings: dict


def _scenario(
    setup: Setup, mu: float, gravity=(0.0, 0.0, -GRAVITY), heading: float = DEFAULT_HEADING, boxes=()
) -> Scenario:
    """``heading``: the robot's start yaw in degrees; ``boxes``: blocks on the ground (x, y, z, yaw,
    size x, y, z), of the ground's friction."""
    return Scenario(
        robot=setup.robot,
        terrain=dict(FLAT, friction=mu, boxes=[list(map(float, b)) for b in boxes]),
        ground_friction=mu,
        timestep=setup.timestep,
        max_wheel_torque=setup.max_wheel_torque,
        starts=((0.0, 0.0, math.radians(heading)),),
        settings=dict(setup.settings),
        gravity=tuple(gravity),
    )


def _commands(setup: Setup, segments: list[tuple[float, float, float]]) -> np.ndarray:
    """(steps, 1, driven wheels) joint speeds for consecutive (duration, v, w) pieces."""
    rows = []
    for duration, v, w in segments:
        left, right = side_speeds(v, w, setup.track)
        steps = int(round(duration / setup.timestep))
        rows.append(np.tile(setup.robot.joint_speeds(left, right), (steps, 1)))
    return np.concatenate(rows)[:, None, :]


def _check(quantity: str, engine_value: float, analytic: float, **extra) -> dict:
    unit, measure = QUANTITIES[quantity]
    return {
        "quantity": quantity,
        "unit": unit,
        "error_kind": measure,
        "engine_value": float(engine_value),
        "analytic_value": float(analytic),
        **extra,
    }


def _finite(record: PhysicsRecord) -> bool:
    return all(
        np.isfinite(getattr(record, k)).all()
        for k in ("position", "linear_velocity", "angular_velocity", "imu_specific_force")
    )


def body_velocity(record: PhysicsRecord) -> np.ndarray:
    """(n, 3) base_link velocity in the body frame."""
    return np.einsum("nji,nj->ni", rotation_matrices(record.quaternion), record.linear_velocity)


def braking_deceleration(speed: np.ndarray, timestep: float) -> float:
    """Deceleration fitted to a forward ``speed`` trace that starts at the brake command: while
    it falls from 80 % to 20 % of its first value, away from the servo's lock-up and from the
    stop, where static friction takes over. NaN when it never falls through that window."""
    v0 = speed[0]
    window = np.flatnonzero((speed <= 0.8 * v0) & (speed >= 0.2 * v0))
    if v0 <= 0 or window.size < 5:
        return math.nan
    return float(-np.polyfit(window * timestep, speed[window], 1)[0])


def _yaw_gain(setup: Setup, p: dict):
    v, w, mu, duration, heading = p["v"], p["w"], p["mu"], p.get("duration", 6.0), p.get("heading", DEFAULT_HEADING)
    ratio = p.get("friction_ratio")
    if ratio is not None:  # the engine's anisotropic friction at this ratio (run_case checked it has one)
        setup = replace(setup, settings={**dict(setup.settings), "friction_ratio": float(ratio)})
    record = get_engine(setup.engine).simulate(
        _scenario(setup, mu, heading=heading), _commands(setup, [(duration, v, w)])
    )
    half = record.steps // 2
    # body yaw rate: the angular velocity's component on the body z axis
    rate = np.einsum("nji,nj->ni", rotation_matrices(record.quaternion), record.angular_velocity)[:, 2]
    gain = rate[half:].mean() / w
    layout = contact_layout(setup.robot, friction_ratio=1.0 if ratio is None else float(ratio))
    analytic = yaw_rate_gain(layout, v, w, setup.track)
    extra = {} if ratio is None else {"friction_ratio": float(ratio)}
    return record, [_check("yaw_rate_gain", gain, analytic, v=v, w=w, mu=mu, heading=heading, **extra)]


def _straight(setup: Setup, p: dict):
    v, mu, duration = p["v"], p["mu"], p.get("duration", 6.0)
    record = get_engine(setup.engine).simulate(
        _scenario(setup, mu, heading=p.get("heading", DEFAULT_HEADING)), _commands(setup, [(duration, v, 0.0)])
    )
    half = record.steps // 2
    speed = body_velocity(record)[half:, 0].mean()
    signs = np.array([w.axis_sign for w in setup.robot.driven], dtype=float)  # mirrored joints: forward-signed
    rolling = (record.wheel_speed[half:] * signs).mean() * setup.robot.wheel_radius
    yaw = np.unwrap(euler_rpy(record.quaternion)[:, 2])
    return record, [
        _check("speed_over_wheel_speed", speed / rolling, 1.0, v=v, mu=mu),
        _check("heading_drift", yaw[-1] - yaw[half], 0.0, v=v, mu=mu),
    ]


def _slide(setup: Setup, p: dict):
    v, mu, cruise, heading = p["v"], p["mu"], p.get("cruise", 2.0), p.get("heading", DEFAULT_HEADING)
    record = get_engine(setup.engine).simulate(
        _scenario(setup, mu, heading=heading), _commands(setup, [(cruise, v, 0.0), (2.0, 0.0, 0.0)])
    )
    brake = int(round(cruise / setup.timestep))
    deceleration = braking_deceleration(body_velocity(record)[brake:, 0], setup.timestep)
    analytic, _ = braking_deceleration_of(setup.robot, mu)  # mu g unless casters roll free
    return record, [_check("deceleration", deceleration, analytic, v=v, mu=mu, heading=heading)]


def _incline(setup: Setup, p: dict):
    mu, factor, duration = p["mu"], p["angle_factor"], p.get("duration", 4.0)
    angle = factor * math.atan(mu)
    # downhill points along -(cos h, sin h); h = 0: along -x, the robot's back. h = 45 deg puts the
    # slope across the world axes, where an engine with world-aligned friction directions holds
    # up to sqrt(2) mu N (ODE's default pyramid did: parked at 1.2 atan(mu))
    heading = math.radians(p.get("heading", DEFAULT_HEADING))
    down = np.array([-math.cos(heading), -math.sin(heading)])
    horizontal = GRAVITY * math.sin(angle) * down
    gravity = (horizontal[0], horizontal[1], -GRAVITY * math.cos(angle))
    record = get_engine(setup.engine).simulate(_scenario(setup, mu, gravity), _commands(setup, [(duration, 0.0, 0.0)]))
    settle = int(round(SETTLE_S / setup.timestep))
    s = record.position[:, :2] @ down  # distance travelled downhill
    if factor < 1:
        creep = abs(s[-1] - s[settle]) / ((record.steps - 1 - settle) * setup.timestep)
        return record, [_check("creep_speed", creep, 0.0, mu=mu, angle=angle)]
    t = np.arange(settle, record.steps) * setup.timestep
    accel = 2 * np.polyfit(t, s[settle:], 2)[0]  # s = s0 + v0 t + a t^2 / 2
    analytic = GRAVITY * (math.sin(angle) - mu * math.cos(angle))
    # all contacts slide the same way, so Coulomb friction has no yaw moment about the centre of
    # mass and damps any yaw rate: the robot slides without turning
    yaw = np.unwrap(euler_rpy(record.quaternion)[:, 2])
    return record, [
        _check("slide_acceleration", accel, analytic, mu=mu, angle=angle),
        _check("slide_yaw", yaw[-1] - yaw[settle], 0.0, mu=mu, angle=angle),
    ]


def _rest(setup: Setup, p: dict):
    mu, duration = p["mu"], p.get("duration", 10.0)
    record = get_engine(setup.engine).simulate(_scenario(setup, mu), _commands(setup, [(duration, 0.0, 0.0)]))
    block = max(1, int(round(0.01 / setup.timestep)))  # the IMU's 100 Hz
    settle = int(round(SETTLE_S / setup.timestep))
    accel = block_average(record.imu_specific_force[settle:], block)
    gyro = block_average(record.imu_gyro[settle:], block)
    creep = float(np.linalg.norm(record.position[-1, :2] - record.position[settle, :2]))
    return record, [
        _check("accel_z", accel[:, 2].mean(), GRAVITY, mu=mu),
        _check("gyro_max", np.abs(gyro).max(), 0.0, mu=mu),
        _check("creep_distance", creep, 0.0, mu=mu),
    ]


def _chassis_pose(
    record: PhysicsRecord, start: int, pitch: float = 0.0, roll: float = 0.0
) -> tuple[float, float, float]:
    """Chassis pitch and roll (rad) from step ``start`` on, each the sample farthest from the predicted
    ``pitch`` / ``roll`` (a chassis that rocks or settles late shows its worst, not its mean), and the
    mean base height (m)."""
    rpy = euler_rpy(record.quaternion[start:])

    def worst(values: np.ndarray, predicted: float) -> float:
        return float(values[np.argmax(np.abs(values - predicted))])

    return worst(rpy[:, 1], pitch), worst(rpy[:, 0], roll), float(record.position[start:, 2].mean())


def _rest_pose(setup: Setup, p: dict):
    mu, duration = p["mu"], p.get("duration", 4.0)
    record = get_engine(setup.engine).simulate(_scenario(setup, mu), _commands(setup, [(duration, 0.0, 0.0)]))
    # the rockers' damping slows the settling: the last half of the run, at least the parked cases' settle
    start = max(int(round(SETTLE_S / setup.timestep)), record.steps // 2)
    pitch, roll, height = _chassis_pose(record, start)
    return record, [
        _check("chassis_pitch", pitch, 0.0, mu=mu),
        _check("chassis_roll", roll, 0.0, mu=mu),
        _check("chassis_height", height, setup.robot.base_height, mu=mu),
    ]


@dataclass(frozen=True)
class Articulation:
    """Where an articulation case puts its blocks, how far the robot drives onto them, and the
    chassis pose mechanics predicts once it stands on them (see the module docstring)."""

    boxes: tuple[tuple[float, ...], ...]  # x, y, z, yaw, size x, y, z
    travel: float  # m driven forward from the start
    pitch: float  # rad
    roll: float  # rad
    height: float  # m, base frame origin above the ground


def articulation(robot: RobotSpec, h: float) -> Articulation:
    """The articulation case's layout and prediction for ``robot`` and blocks ``h`` high (raises
    InputError when it does not apply: see :func:`not_applicable`)."""
    reason = _articulation_reason(robot, h)
    if reason is not None:
        raise InputError("validation.cases (articulation)", reason)
    coupling = robot.couplings[0]
    by_joint = {s.joint: s for s in robot.suspension}
    lead, follow = by_joint[coupling.leader], by_joint[coupling.joint]

    def axles(sus):
        wheels = sorted((w for w in robot.driven if w.joint in sus.wheels), key=lambda w: -w.position[0])
        return wheels[0], wheels[1]  # front, back

    (lf, lb), (ff, fb) = axles(lead), axles(follow)
    plan = _blocks(robot, h, lf, fb, ff)
    if isinstance(plan, str):
        raise InputError("validation.cases (articulation)", plan)
    boxes, travel = plan

    def rocker(sus, front_rise, back_rise, front, back):
        """Its pitch and its pivot's rise for wheel-centre rises at its front and back axles."""
        arm = front.position[0] - back.position[0]
        share = (sus.position[0] - back.position[0]) / arm  # the pivot's place between the axles
        return -math.asin((front_rise - back_rise) / arm), back_rise + share * (front_rise - back_rise)

    lead_pitch, lead_rise = rocker(lead, h, 0.0, lf, lb)
    follow_pitch, follow_rise = rocker(follow, 0.0, h, ff, fb)
    m = coupling.multiplier
    pitch = (follow_pitch - m * lead_pitch) / (1 - m)
    # each rocker is rigid in roll with the chassis: the chassis rolls as the line across the two
    # rockers' wheels, and its origin (at y 0, x 0) rises as that line there, the pitch turning it
    # about the pivots' line
    span = lf.position[1] - ff.position[1]
    roll = math.asin((lead_rise - follow_rise) / span)
    rise = follow_rise + (lead_rise - follow_rise) * (0.0 - ff.position[1]) / span
    rise += 0.5 * (lead.position[0] + follow.position[0]) * math.sin(pitch)
    return Articulation(boxes=boxes, travel=travel, pitch=pitch, roll=roll, height=robot.base_height + rise)


# m: the blocks are stairs of layers at most this high, each this far behind the one below it, so
# that a wheel climbs them as it would a 14-degree ramp. One 5 cm step is climbed only where the climbing
# wheel's friction exceeds tan(a), a the angle of the contact at the edge (0.66 for the Warthog's 0.30 m
# wheel): MuJoCo's Warthog stalled at mu 0.8 in front of one, spinning its wheels, as a case of the
# coupling it should not test traction
STAIR_RISE = 0.01
STAIR_RUN = 0.04


def _reach(radius: float, rise: float) -> float:
    """How far ahead of its centre a wheel meets a step ``rise`` high."""
    return math.sqrt(radius**2 - (radius - rise) ** 2)


def _blocks(robot: RobotSpec, h: float, lead_front, follow_back, follow_front):
    """The stairs under the leading rocker's front wheel and the other's back wheel, and how far the
    robot drives: (boxes, travel), or why the robot is too short for blocks ``h`` high."""
    radius = robot.wheel_radius
    layers = max(1, math.ceil(h / STAIR_RISE - 1e-9))
    rise = h / layers
    climb = (layers - 1) * STAIR_RUN  # from the first layer's edge to the top layer's
    first = _reach(radius, rise) + 0.05  # the first edge 5 cm beyond where the wheel would touch it
    # the back stairs end (at full height) before the wheel ahead of them on that side would touch them
    back_start = follow_back.position[0] + first
    back_end = follow_front.position[0] - _reach(radius, h) - 0.05
    top = back_start + climb  # where the top layer begins
    if back_end - top < 0.1:
        return (
            f"blocks {h} m high leave no room between the back and front axles of rocker "
            f"(the top of the stairs would be {back_end - top:.3f} m long): give a lower h"
        )
    travel = 0.5 * (top + back_end) - follow_back.position[0]  # the back wheel stops mid-top
    front_start = lead_front.position[0] + first
    length = travel + 1.0  # beyond where the front wheel stops
    width = max(w.width for w in robot.driven) + 0.1
    boxes = []
    for k in range(layers):
        for start, end, y in (
            (front_start, front_start + length, lead_front.position[1]),
            (back_start, back_end, follow_back.position[1]),
        ):
            x0 = start + k * STAIR_RUN
            boxes.append((0.5 * (x0 + end), y, (k + 0.5) * rise, 0.0, end - x0, width, rise))
    return tuple(boxes), travel


def _articulation_reason(robot: RobotSpec, h: float | None = None) -> str | None:
    if not robot.suspension:
        return "the robot has no suspension"
    if len(robot.suspension) != 2 or len(robot.couplings) != 1:
        return (
            "the case twists one coupled pair of rockers against each other; the robot's suspension is "
            f"{len(robot.suspension)} joints with {len(robot.couplings)} couplings"
        )
    coupling = robot.couplings[0]
    if coupling.multiplier == 1:
        return "a coupling with multiplier 1 moves both rockers alike: the chassis cannot pitch between them"
    for sus in robot.suspension:
        own = [w for w in robot.driven if w.joint in sus.wheels]
        if (
            len(own) != 2
            or len({round(w.position[1], 3) for w in own}) != 1
            or own[0].position[0] == own[1].position[0]
        ):
            return f"rocker {sus.joint!r} does not carry one front and one back driven wheel on one side"
        if sus.parent != robot.base_link:
            return f"rocker {sus.joint!r} hangs on {sus.parent!r}, not on the chassis"
    if h is not None and not 0 < h < robot.wheel_radius / 2:
        return f"blocks {h} m high: give 0 < h < half the wheel radius ({robot.wheel_radius / 2:.3f} m)"
    if h is not None:
        by_joint = {s.joint: s for s in robot.suspension}
        follow = by_joint[coupling.joint]
        lead = by_joint[coupling.leader]
        front = max((w for w in robot.driven if w.joint in lead.wheels), key=lambda w: w.position[0])
        own = sorted((w for w in robot.driven if w.joint in follow.wheels), key=lambda w: w.position[0])
        plan = _blocks(robot, h, front, own[0], own[1])
        if isinstance(plan, str):
            return plan
    return None


def _articulation(setup: Setup, p: dict):
    h, mu, v = p["h"], p["mu"], p.get("v", 0.2)
    plan = articulation(setup.robot, h)
    hold = p.get("duration", 3.0)
    record = get_engine(setup.engine).simulate(
        _scenario(setup, mu, boxes=plan.boxes), _commands(setup, [(plan.travel / v, v, 0.0), (hold, 0.0, 0.0)])
    )
    start = record.steps - int(round(min(1.0, hold / 2) / setup.timestep))  # the held pose's last second
    pitch, roll, height = _chassis_pose(record, start, plan.pitch, plan.roll)
    return record, [
        _check("chassis_pitch", pitch, plan.pitch, mu=mu, v=v),
        _check("chassis_roll", roll, plan.roll, mu=mu, v=v),
        _check("chassis_height", height, plan.height, mu=mu, v=v),
    ]


# --- robot-generic: where a case's analytic value does not apply to the robot studied ---------


def braking_deceleration_of(robot: RobotSpec, mu: float) -> tuple[float, str | None]:
    return coulomb_braking(robot, mu)


def not_applicable(robot: RobotSpec, kind: str, params: dict) -> str | None:
    """Why a case's analytic value does not describe ``robot`` (None: it does)."""
    if kind == "slide":
        return braking_deceleration_of(robot, params["mu"])[1]
    if kind == "rest_pose" and not robot.suspension:
        return "the robot has no suspension (its rest is the rest case's)"
    if kind == "articulation":
        return _articulation_reason(robot, params.get("h"))
    if kind == "incline" and robot.casters:
        return (
            "the robot's casters roll freely, so only its driven wheels hold it on the slope, and the "
            "analytic values (every wheel locked: parked below atan(mu), sliding above it) do not apply"
        )
    return None


RUNNERS = {
    "yaw_gain": _yaw_gain,
    "straight": _straight,
    "slide": _slide,
    "incline": _incline,
    "rest": _rest,
    "rest_pose": _rest_pose,
    "articulation": _articulation,
}


def run_case(setup: Setup, name: str, params: dict) -> dict:
    """Run one case on one engine; returns its record (checks, cost, health)."""
    params = dict(params)
    kind = params.pop("kind")
    if kind not in RUNNERS:
        raise InputError(f"validation.cases.{name}.kind", f"{kind!r} is not a case kind", f"use one of {list(KINDS)}")
    engine = get_engine(setup.engine)
    reason = not_applicable(setup.robot, kind, params)
    if (
        reason is None
        and params.get("friction_ratio") is not None
        and "friction_ratio" not in engine.settings_model.model_fields
    ):
        reason = (
            f"{setup.engine} has no anisotropic wheel friction here (no friction_ratio setting: "
            "see docs/engines.md, 'Turning like the real Husky')"
        )
    elif reason is None and params.get("friction_ratio") is not None:
        # a set-up (a simulator's profile) whose other settings exclude the ratio: the adapter says why
        try:
            engine.settings_model.of(
                {**dict(setup.settings), "friction_ratio": float(params["friction_ratio"])}, setup.engine
            )
        except InputError as exc:
            reason = f"this set-up takes no friction_ratio ({exc})"
    if reason is not None:  # skipped, with the reason in the summary and the report
        return {
            "engine": setup.engine,
            "engine_version": engine.version(),
            "case": name,
            "kind": kind,
            "params": params,
            "checks": [],
            "status": "skipped",
            "reasons": [f"not applicable: {reason}"],
            "steps": 0,
            "sim_time": 0.0,
            "steps_per_s": None,
            "wall_time": 0.0,
        }
    start = time.perf_counter()
    record, checks = RUNNERS[kind](setup, params)
    wall = time.perf_counter() - start
    status, reasons = "ok", []
    if not _finite(record):
        status, reasons = "failed", ["diverged: non-finite state"]
        for c in checks:
            c["engine_value"] = math.nan
    return {
        "engine": setup.engine,
        "engine_version": engine.version(),
        "case": name,
        "kind": kind,
        "params": params,
        "checks": checks,
        "status": status,
        "reasons": reasons,
        "steps": record.steps,
        "sim_time": record.steps * setup.timestep,
        "steps_per_s": record.steps / record.wall_time if record.wall_time > 0 else None,
        "wall_time": wall,
    }


def failed_record(setup: Setup, version: str, name: str, params: dict, reason: str, wall: float = 0.0) -> dict:
    """The record of a case that ended before it measured anything (hung, crashed, or not run
    because a case before it hung): failed, no checks, the reason; the summary lists it as a
    failed row of the case's first quantity (:data:`CASE_QUANTITY`)."""
    return {
        "engine": setup.engine,
        "engine_version": version,
        "case": name,
        "kind": params["kind"],
        "params": {k: v for k, v in params.items() if k != "kind"},
        "checks": [],
        "status": "failed",
        "reasons": [reason],
        "steps": 0,
        "sim_time": 0.0,
        "steps_per_s": None,
        "wall_time": float(wall),
    }


def validate_job(outputs: list[str], urdf: str | Path, params: dict, timeout: float = DEFAULT_TIMEOUT_S) -> list[dict]:
    """The workflow's per-engine job: every case of ``params["cases"]`` on one engine in one process
    (the robot and the engine's module are loaded once), one JSON record per case in ``outputs``
    (``.../{case}.json``), in the order of ``params["cases"]``.

    ``timeout``: the job's hang limit in s of wall time (simpick.simulate.watchdog.runtime_timeout of the rule's
    runtime), shared evenly by its cases: each case runs under the watchdog with ``timeout / cases``. A
    case still running then is recorded as failed (hung) and the cases after it, which cannot run in the
    stopped process, as failed (not run), so the summary lists every case. A case whose engine raises is
    recorded as failed with the error (the traceback goes to the job's log) and the next case runs; a bad
    case kind (InputError) still stops the job."""
    cases = params["cases"]
    paths = {Path(p).stem: Path(p) for p in outputs}
    if sorted(paths) != sorted(cases):
        raise ValueError(f"validate_job: outputs for {sorted(paths)}, cases {sorted(cases)}")
    setup = Setup(
        engine=params["engine"],
        robot=load_from_config({**params["robot"], "urdf": urdf}),
        timestep=params["physics"]["timestep"],
        max_wheel_torque=params["robot"]["max_wheel_torque"],
        track=params["robot"]["track"],
        settings=params["engine_settings"],
    )
    version = get_engine(setup.engine).version()  # before any case: the watchdog's records need it
    limit = float(timeout) / len(cases)
    names = list(cases)

    def failed(name: str, reason: str, wall: float = 0.0) -> dict:
        print(f"simpick: validate {setup.engine} {name}: {reason}", file=sys.stderr)
        return failed_record(setup, version, name, cases[name], reason, wall)

    results = []
    for i, name in enumerate(names):

        def hung(i: int = i) -> None:
            _write_record(paths[names[i]], failed(names[i], hung_reason(limit), limit))
            for later in names[i + 1 :]:
                _write_record(paths[later], failed(later, f"not run: {names[i]} hung before it"))

        start = time.perf_counter()
        with Watchdog(limit, hung):
            try:
                result = run_case(setup, name, cases[name])
            except InputError:
                raise
            except Exception as exc:  # noqa: BLE001 - recorded as the case's failure; the others run on
                traceback.print_exc()
                result = failed(name, f"crashed: {type(exc).__name__}: {exc}", time.perf_counter() - start)
        _write_record(paths[name], result)
        results.append(result)
    return results


def _write_record(path: Path, result: dict) -> None:
    """Atomically: a killed job leaves a temp file, never a truncated record."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".partial")
    tmp.write_text(json.dumps(result, indent=1, sort_keys=True, allow_nan=True))
    tmp.replace(path)


def _row(
    engine: str,
    case: str,
    kind: str,
    quantity: str,
    value: float,
    analytic: float,
    tolerances: dict,
    status: str,
    reasons: str,
    **extra,
) -> dict:
    if quantity not in tolerances:
        raise InputError(
            f"validation.tolerances.{quantity}",
            "no tolerance given",
            f"add `{quantity}: <tolerance>` under validation.tolerances in the config",
        )
    unit, measure = QUANTITIES[quantity]
    error = abs(value - analytic) / abs(analytic) if measure == "relative" else abs(value - analytic)
    passed = bool(status == "ok" and np.isfinite(error) and error <= tolerances[quantity])
    return {
        "engine": engine,
        "case": case,
        "kind": kind,
        "quantity": quantity,
        "unit": unit,
        "engine_value": value,
        "analytic_value": analytic,
        "error": error,
        "error_kind": measure,
        "tolerance": float(tolerances[quantity]),
        "passed": passed,
        "status": status,
        "reasons": reasons,
        "v": extra.get("v"),
        "w": extra.get("w"),
        "mu": extra.get("mu"),
        "heading": extra.get("heading"),
        "steps_per_s": extra.get("steps_per_s"),
        "covers": extra.get("covers", ""),
        "friction_ratio": extra.get("friction_ratio"),
    }


def _label(x: float) -> str:
    return f"{float(x):g}"


def invariance_rows(rows: list[dict], tolerances: dict) -> list[dict]:
    """The turn_asymmetry and heading_spread checks of every engine, from its yaw_rate_gain rows
    (see the module docstring). A group's check fails when any of its cases failed."""
    gains = pd.DataFrame(
        [
            r
            for r in rows
            if r["quantity"] == "yaw_rate_gain"
            and r["w"] is not None
            and r["status"] != "skipped"
            and r.get("friction_ratio") is None
        ]
    )
    if gains.empty:
        return []
    gains = gains.astype({"v": float, "w": float, "mu": float})
    gains = gains.assign(
        ratio=gains.engine_value / gains.analytic_value,
        turn=np.sign(gains.w),
        speed=gains.w.abs(),
        heading=gains.heading.fillna(DEFAULT_HEADING),
    )
    out = []

    def status(cases) -> str:
        return "ok" if (cases.status == "ok").all() else "failed"

    for (engine, v, speed, mu), g in gains.groupby(["engine", "v", "speed", "mu"], sort=False):
        name = f"v{_label(v)}_w{_label(speed)}_mu{_label(mu)}"
        both = g.groupby("heading").filter(lambda h: set(h.turn) == {-1.0, 1.0})
        if len(both):
            differences = both.groupby("heading").apply(
                lambda h: abs(h.ratio[h.turn > 0].mean() - h.ratio[h.turn < 0].mean()), include_groups=False
            )
            out.append(
                _row(
                    engine,
                    f"left_right_{name}",
                    "invariance",
                    "turn_asymmetry",
                    float(differences.max()),
                    0.0,
                    tolerances,
                    status(both),
                    "",
                    v=v,
                    w=speed,
                    mu=mu,
                    covers=" ".join(both.case),
                )
            )
        for turn, t in g.groupby("turn", sort=False):
            if t.heading.nunique() > 1:
                w = float(turn * speed)
                out.append(
                    _row(
                        engine,
                        f"headings_v{_label(v)}_w{_label(w)}_mu{_label(mu)}",
                        "invariance",
                        "heading_spread",
                        float(t.ratio.max() - t.ratio.min()),
                        0.0,
                        tolerances,
                        status(t),
                        "",
                        v=v,
                        w=w,
                        mu=mu,
                        covers=" ".join(t.case),
                    )
                )
    return out


def summarise(results: list[dict], tolerances: dict[str, float]):
    """One row per (engine, case, quantity): values, error and pass/fail under ``tolerances``;
    then the invariance checks (:func:`invariance_rows`)."""
    rows = []
    for result in results:
        if not result["checks"]:  # skipped (not applicable), or failed before it measured: one row, the reason
            quantity = CASE_QUANTITY[result["kind"]]
            rows.append(
                {
                    "engine": result["engine"],
                    "case": result["case"],
                    "kind": result["kind"],
                    "quantity": quantity,
                    "unit": QUANTITIES[quantity][0],
                    "engine_value": math.nan,
                    "analytic_value": math.nan,
                    "error": math.nan,
                    "error_kind": QUANTITIES[quantity][1],
                    "tolerance": math.nan,
                    "passed": False,
                    "status": result["status"],
                    "reasons": "; ".join(result["reasons"]),
                    "v": result["params"].get("v"),
                    "w": result["params"].get("w"),
                    "mu": result["params"].get("mu"),
                    "heading": result["params"].get("heading"),
                    "steps_per_s": None,
                    "covers": "",
                    "friction_ratio": result["params"].get("friction_ratio"),
                }
            )
            continue
        for c in result["checks"]:
            rows.append(
                _row(
                    result["engine"],
                    result["case"],
                    result["kind"],
                    c["quantity"],
                    c["engine_value"],
                    c["analytic_value"],
                    tolerances,
                    result["status"],
                    "; ".join(result["reasons"]),
                    v=c.get("v"),
                    w=c.get("w"),
                    mu=c.get("mu"),
                    heading=c.get("heading"),
                    steps_per_s=result["steps_per_s"],
                    friction_ratio=c.get("friction_ratio"),
                )
            )
    return pd.DataFrame(rows + invariance_rows(rows, tolerances))


GAIN_COLUMNS = (
    "engine",
    "v",
    "w",
    "mu",
    "analytic",
    "n_left",
    "left_mean",
    "left_min",
    "left_max",
    "n_right",
    "right_mean",
    "right_min",
    "right_max",
    "min",
    "max",
    "spread",
    "headings",
)


def gain_table(summary):
    """Per engine and (v, |w|, mu): the Coulomb gain and the engine's gain turning left (w > 0)
    and right (w < 0): mean, min and max over the start headings; over both, min, max and the
    spread max - min relative to the Coulomb gain."""
    gains = summary[(summary.quantity == "yaw_rate_gain") & summary.w.notna() & (summary.status != "skipped")]
    if "friction_ratio" in gains:  # anisotropic cases: not the isotropic turning this table compares
        gains = gains[gains.friction_ratio.isna()]
    rows = []
    if gains.empty:
        return pd.DataFrame(columns=list(GAIN_COLUMNS))
    gains = gains.assign(speed=gains.w.abs(), heading=gains.heading.fillna(DEFAULT_HEADING))
    for (engine, v, speed, mu), g in gains.groupby(["engine", "v", "speed", "mu"], sort=False):
        left, right = g[g.w > 0].engine_value, g[g.w < 0].engine_value
        analytic = float(g.analytic_value.mean())
        rows.append(
            {
                "engine": engine,
                "v": v,
                "w": speed,
                "mu": mu,
                "analytic": analytic,
                "n_left": len(left),
                "left_mean": left.mean(),
                "left_min": left.min(),
                "left_max": left.max(),
                "n_right": len(right),
                "right_mean": right.mean(),
                "right_min": right.min(),
                "right_max": right.max(),
                "min": g.engine_value.min(),
                "max": g.engine_value.max(),
                "spread": (g.engine_value.max() - g.engine_value.min()) / analytic,
                "headings": " ".join(_label(h) for h in sorted(g.heading.unique())),
            }
        )
    return pd.DataFrame(rows, columns=list(GAIN_COLUMNS))


# the quantity under which a case without checks (skipped, or hung, crashed or not run) is listed
CASE_QUANTITY = {
    "yaw_gain": "yaw_rate_gain",
    "straight": "speed_over_wheel_speed",
    "slide": "deceleration",
    "incline": "slide_acceleration",
    "rest": "accel_z",
    "rest_pose": "chassis_pitch",
    "articulation": "chassis_pitch",
}


def summarise_job(inputs: list[str], outputs: dict, tolerances: dict) -> None:
    results = [json.loads(Path(p).read_text()) for p in inputs]
    summary = summarise(results, tolerances)
    write_csv(summary, outputs["summary"])
    write_csv(gain_table(summary), outputs["gains"])


def main(argv: list[str] | None = None) -> None:
    """``python -m simpick.studies.validation ENGINE [CASE ...]``: run the config's cases and print them."""
    parser = argparse.ArgumentParser(description=main.__doc__)
    parser.add_argument("engine")
    parser.add_argument("cases", nargs="*")
    parser.add_argument("--config", default="config.yaml")
    parser.add_argument("--set", action="append", default=[], help="engine setting key=value (JSON value)")
    args = parser.parse_args(argv)
    config = yaml.safe_load(Path(args.config).read_text())
    settings = dict(config["engines"].get(args.engine) or {})
    for item in args.set:
        key, value = item.split("=", 1)
        try:
            settings[key] = json.loads(value)
        except json.JSONDecodeError:
            settings[key] = value
    setup = Setup(
        engine=args.engine,
        robot=load_from_config(config["robot"]),
        timestep=config["physics"]["timestep"],
        max_wheel_torque=config["robot"]["max_wheel_torque"],
        track=config["robot"]["track"],
        settings=settings,
    )
    cases = config["validation"]["cases"]
    results = [run_case(setup, name, cases[name]) for name in (args.cases or cases)]
    summary = summarise(results, config["validation"]["tolerances"])

    with pd.option_context("display.width", 200, "display.max_columns", 20):
        print(
            summary[
                ["case", "quantity", "engine_value", "analytic_value", "error", "tolerance", "passed", "steps_per_s"]
            ].to_string(index=False, float_format=lambda x: f"{x:.4g}")
        )


if __name__ == "__main__":
    main()
