"""The geometry of the articulation case, for a robot on two coupled rockers: where its stairs stand,
how far the robot drives onto them, the chassis pose mechanics predicts there, and why a robot's
suspension takes no such case."""

from __future__ import annotations

import math
from dataclasses import dataclass

from simpick.errors import InputError
from simpick.inputs.robot import RobotSpec


@dataclass(frozen=True)
class Articulation:
    """Where an articulation case puts its blocks, how far the robot drives onto them, and the
    chassis pose mechanics predicts once it stands on them (see simpick.studies.validation)."""

    boxes: tuple[tuple[float, ...], ...]  # x, y, z, yaw, size x, y, z
    travel: float  # m driven forward from the start
    pitch: float  # rad
    roll: float  # rad
    height: float  # m, base frame origin above the ground


def articulation(robot: RobotSpec, h: float) -> Articulation:
    """The articulation case's layout and prediction for ``robot`` and blocks ``h`` high (raises
    InputError when it does not apply: see :func:`articulation_reason`)."""
    reason = articulation_reason(robot, h)
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


def articulation_reason(robot: RobotSpec, h: float | None = None) -> str | None:
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
