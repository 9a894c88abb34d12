"""The validation's cases run: each kind of case (:mod:`simpick.studies.validation` describes them)
on one engine, measured into checks beside the value mechanics predicts, with the reason a case
does not apply to the robot studied."""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from pydantic import ValidationError

from simpick.coulomb import braking_deceleration as coulomb_braking
from simpick.coulomb import contact_layout, yaw_rate_gain
from simpick.engines import get_engine
from simpick.engines.base import GRAVITY, PhysicsRecord, Scenario
from simpick.engines.kinematics import euler_rpy, rotation_matrices
from simpick.errors import InputError, validation_problems
from simpick.inputs.motions import side_speeds
from simpick.inputs.robot import RobotSpec
from simpick.simulate.imu import block_average
from simpick.slope import hold_angle, slope_holds, slope_slide
from simpick.studies.validation.measures import DEFAULT_HEADING, KINDS, QUANTITIES, SETTLE_S
from simpick.studies.validation.settings import ValidationCase
from simpick.studies.validation.suspension import articulation, articulation_reason

FLAT = {"schema": "simpick.inputs.terrain/1", "name": "flat", "boxes": [], "spheres": [], "friction": 0.0}


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


def _or(value, default):
    """A case's optional setting, else its kind's own default."""
    return default if value is None else value


def own_friction_ratio(setup: Setup) -> float:
    """The lateral/longitudinal wheel friction ratio of the set-up's own settings (a calibrated profile's
    fitted one; 1 for every other): the ratio of the mechanics a case without one of its own is judged by."""
    return float(dict(setup.settings).get("friction_ratio", 1.0))


def _yaw_gain(setup: Setup, p: ValidationCase):
    v, w, mu, duration, heading = p.v, p.w, p.mu, _or(p.duration, 6.0), p.heading
    ratio = p.friction_ratio
    if ratio is not None:  # the engine's anisotropic friction at this ratio (run_case checked it has one)
        setup = replace(setup, settings={**dict(setup.settings), "friction_ratio": float(ratio)})
    record = get_engine(setup.engine).simulate(
        _scenario(setup, mu, heading=heading), _commands(setup, [(duration, v, w)])
    )
    half = record.steps // 2
    # body yaw rate: the angular velocity's component on the body z axis
    rate = np.einsum("nji,nj->ni", rotation_matrices(record.quaternion), record.angular_velocity)[:, 2]
    gain = rate[half:].mean() / w
    # the mechanics of the set-up's own parameters: a case that sets no ratio is judged against the Coulomb
    # solution with the model's own friction ratio (a calibrated profile's fitted one; 1 for every other)
    own = own_friction_ratio(setup)
    layout = contact_layout(setup.robot, friction_ratio=own if ratio is None else float(ratio))
    analytic = yaw_rate_gain(layout, v, w, setup.track)
    extra = {} if ratio is None else {"friction_ratio": float(ratio)}
    return record, [_check("yaw_rate_gain", gain, analytic, v=v, w=w, mu=mu, heading=heading, **extra)]


def _straight(setup: Setup, p: ValidationCase):
    v, mu, duration = p.v, p.mu, _or(p.duration, 6.0)
    record = get_engine(setup.engine).simulate(
        _scenario(setup, mu, heading=p.heading), _commands(setup, [(duration, v, 0.0)])
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


def _slide(setup: Setup, p: ValidationCase):
    """Locked wheels after cruising: the contacts slide along the wheels (the base's x), so their friction
    is the longitudinal coefficient's, mu g, whatever the profile's lateral/longitudinal ``friction_ratio``
    (elliptic friction acts along the slip when the slip lies on an axis of the ellipse): the reference
    needs no ratio."""
    v, mu, cruise, heading = p.v, p.mu, _or(p.cruise, 2.0), p.heading
    record = get_engine(setup.engine).simulate(
        _scenario(setup, mu, heading=heading), _commands(setup, [(cruise, v, 0.0), (2.0, 0.0, 0.0)])
    )
    brake = int(round(cruise / setup.timestep))
    deceleration = braking_deceleration(body_velocity(record)[brake:, 0], setup.timestep)
    analytic, _ = braking_deceleration_of(setup.robot, mu)  # mu g unless casters roll free
    return record, [_check("deceleration", deceleration, analytic, v=v, mu=mu, heading=heading)]


def downhill_acceleration(position: np.ndarray, down: np.ndarray, start: int, timestep: float) -> float:
    """Acceleration along ``down`` fitted to the distance travelled downhill from sample ``start`` on:
    s = s0 + v0 t + a t^2 / 2 (the engine's record and the reference's path, measured alike)."""
    s = position[start:, :2] @ down
    t = np.arange(start, len(position)) * timestep
    return float(2 * np.polyfit(t, s, 2)[0])


def path_angle(position: np.ndarray, down: np.ndarray, start: int) -> float:
    """Angle (rad, counter-clockwise) of the displacement from sample ``start`` to the last from ``down``."""
    dx, dy = position[-1, :2] - position[start, :2]
    return float(math.atan2(down[0] * dy - down[1] * dx, down[0] * dx + down[1] * dy)) + 0.0  # no -0.0


def _incline(setup: Setup, p: ValidationCase):
    """Parked on locked wheels on a slope of ``angle_factor`` x atan(mu) (gravity tilted): judged by the
    elliptic anisotropic Coulomb law with the set-up's own ``friction_ratio`` (:func:`simpick.slope.slope_slide`;
    1: isotropic). Whether the robot holds follows that law's friction ellipse at this downhill
    direction, not the factor: a case set below atan(mu) that the profile's ellipse cannot hold is judged
    as a slide, and the checks say which (``expected``, ``hold_angle``). A slide is judged by the same fit
    of the distance travelled downhill, over the same window, on the engine's record and on the law's
    path; the path's angle from downhill (``drift``, the law's ``analytic_drift``) is recorded, not judged."""
    mu, factor, duration = p.mu, p.angle_factor, _or(p.duration, 4.0)
    angle = factor * math.atan(mu)
    # downhill points along -(cos h, sin h); h = 0: along -x, the robot's back. h = 45 deg puts the
    # slope across the world axes, where an engine with world-aligned friction directions holds
    # up to sqrt(2) mu N (ODE's default pyramid did: parked at 1.2 atan(mu))
    heading = math.radians(p.heading)
    down = np.array([-math.cos(heading), -math.sin(heading)])
    horizontal = GRAVITY * math.sin(angle) * down
    gravity = (horizontal[0], horizontal[1], -GRAVITY * math.cos(angle))
    record = get_engine(setup.engine).simulate(_scenario(setup, mu, gravity), _commands(setup, [(duration, 0.0, 0.0)]))
    settle = int(round(SETTLE_S / setup.timestep))
    # the wheels' frame: the robot starts at the default heading (0: the world's)
    yaw = math.radians(DEFAULT_HEADING)
    turn = np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]])
    ratio = own_friction_ratio(setup)
    wheel_down = turn.T @ down
    limit = hold_angle(wheel_down, mu, ratio)
    extra = {"mu": mu, "angle": angle, "hold_angle": limit, **({} if ratio == 1.0 else {"friction_ratio": ratio})}
    if slope_holds(angle, wheel_down, mu, ratio):
        s = record.position[:, :2] @ down  # distance travelled downhill
        creep = abs(s[-1] - s[settle]) / ((record.steps - 1 - settle) * setup.timestep)
        return record, [_check("creep_speed", creep, 0.0, expected="hold", **extra)]
    # the law from rest over the record's steps: its sample k + 1 (time (k + 1) h) is the record's k
    law = slope_slide(angle, wheel_down, mu, ratio, duration=record.steps * setup.timestep, timestep=setup.timestep)
    path = law.position[1:] @ turn.T
    accel = downhill_acceleration(record.position, down, settle, setup.timestep)
    analytic = downhill_acceleration(path, down, settle, setup.timestep)
    drift = {"drift": path_angle(record.position, down, settle), "analytic_drift": path_angle(path, down, settle)}
    # all contacts slide the same way, so Coulomb friction (isotropic or elliptic) has no yaw moment about
    # the centre of mass and damps any yaw rate: the robot slides without turning
    rpy_yaw = np.unwrap(euler_rpy(record.quaternion)[:, 2])
    return record, [
        _check("slide_acceleration", accel, analytic, expected="slide", **drift, **extra),
        _check("slide_yaw", rpy_yaw[-1] - rpy_yaw[settle], 0.0, expected="slide", **extra),
    ]


def _rest(setup: Setup, p: ValidationCase):
    mu, duration = p.mu, _or(p.duration, 10.0)
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


def _rest_pose(setup: Setup, p: ValidationCase):
    mu, duration = p.mu, _or(p.duration, 4.0)
    record = get_engine(setup.engine).simulate(_scenario(setup, mu), _commands(setup, [(duration, 0.0, 0.0)]))
    # the rockers' damping slows the settling: the last half of the run, at least the parked cases' settle
    start = max(int(round(SETTLE_S / setup.timestep)), record.steps // 2)
    pitch, roll, height = _chassis_pose(record, start)
    return record, [
        _check("chassis_pitch", pitch, 0.0, mu=mu),
        _check("chassis_roll", roll, 0.0, mu=mu),
        _check("chassis_height", height, setup.robot.base_height, mu=mu),
    ]


def _articulation(setup: Setup, p: ValidationCase):
    h, mu, v = p.h, p.mu, _or(p.v, 0.2)
    plan = articulation(setup.robot, h)
    hold = _or(p.duration, 3.0)
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


def not_applicable(robot: RobotSpec, case: ValidationCase) -> str | None:
    """Why a case's analytic value does not describe ``robot`` (None: it does)."""
    kind = case.kind
    if kind == "slide":
        return braking_deceleration_of(robot, case.mu)[1]
    if kind == "rest_pose" and not robot.suspension:
        return "the robot has no suspension (its rest is the rest case's)"
    if kind == "articulation":
        return articulation_reason(robot, case.h)
    if kind == "incline" and robot.casters:
        return (
            "the robot's casters roll freely, so only its driven wheels hold it on the slope, and the "
            "analytic values (every wheel locked: parked inside the friction ellipse, sliding outside it) do not apply"
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


def case_of(name: str, case: ValidationCase | Mapping[str, Any]) -> ValidationCase:
    """A case as its model (a mapping, e.g. a test's or a helper's, is checked as the config's are): a bad
    case is the config's error, naming the case's key, never a failed run."""
    if isinstance(case, ValidationCase):
        return case
    try:
        return ValidationCase.model_validate(case)
    except ValidationError as exc:
        key, problem = validation_problems(exc, ("validation", "cases", name))[0]
        raise InputError(key, problem, f"see the case kinds and their settings: {list(KINDS)}") from None


def _recorded(case: ValidationCase) -> dict:
    """A case's settings as its record states them: those it sets, without its kind (beside them)."""
    return case.model_dump(mode="json", exclude_none=True, exclude={"kind"})


def run_case(setup: Setup, name: str, params: ValidationCase | Mapping[str, Any]) -> dict:
    """Run one case on one engine; returns its record (checks, cost, health)."""
    case = case_of(name, params)
    kind, params = case.kind, _recorded(case)
    engine = get_engine(setup.engine)
    reason = not_applicable(setup.robot, case)
    if (
        reason is None
        and case.friction_ratio is not None
        and "friction_ratio" not in engine.settings_model.model_fields
    ):
        reason = (
            f"{setup.engine} has no anisotropic wheel friction here (no friction_ratio setting: "
            "see docs/engines.md, 'Turning like the real Husky')"
        )
    elif reason is None and case.friction_ratio is not None:
        # a set-up (a simulator's profile) whose other settings exclude the ratio: the adapter says why
        try:
            engine.settings_model.of(
                {**dict(setup.settings), "friction_ratio": float(case.friction_ratio)}, setup.engine
            )
        except InputError as exc:
            reason = f"this set-up takes no friction_ratio ({exc})"
    elif reason is None and kind == "incline" and setup.robot.skids and own_friction_ratio(setup) != 1.0:
        reason = (
            f"the robot's skids slide with isotropic friction beside its wheels' anisotropic friction (friction_ratio "
            f"{own_friction_ratio(setup):g}): their forces point different ways, and the slope's law (one friction "
            "ellipse for every contact) does not describe it"
        )
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
    record, checks = RUNNERS[kind](setup, case)
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


def failed_record(
    setup: Setup, version: str, name: str, case: ValidationCase | Mapping[str, Any], reason: str, wall: float = 0.0
) -> dict:
    """The record of a case that ended before it measured anything (hung, crashed, or not run
    because a case before it hung): failed, no checks, the reason; the summary lists it as a
    failed row of the case's first quantity (:data:`CASE_QUANTITY`)."""
    return {
        "engine": setup.engine,
        "engine_version": version,
        "case": name,
        "kind": case_of(name, case).kind,
        "params": _recorded(case_of(name, case)),
        "checks": [],
        "status": "failed",
        "reasons": [reason],
        "steps": 0,
        "sim_time": 0.0,
        "steps_per_s": None,
        "wall_time": float(wall),
    }
