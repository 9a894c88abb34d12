"""Locked wheels on a slope: elliptic Coulomb friction on a translating body (METHOD.md section 10).

Every contact slides with the body's velocity u, so the elliptic law of :mod:`simpick.coulomb` (a wheel
contact resisting sliding across the wheel with ``ratio`` x its coefficient along it) moves the body as a
whole, m du/dt = m g_t - N M^2 u / |M u| (M = diag(mu_long, mu_lat), N = m g cos a): :func:`slope_slide`
integrates it from rest, :func:`slope_holds` and :func:`hold_angle` give when the ellipse holds the robot
parked. Across the wheels' axes it slides faster than g (sin a - mu cos a) for r < 1, and off the downhill
direction, towards the wheels' axis.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from simpick.coulomb import GRAVITY, _checked_ratio
from simpick.errors import InputError


def _ellipse(mu: float, ratio: float) -> tuple[float, float]:
    """(mu_l, mu_t): a wheel contact's coefficient along the wheel (the base's x) and across it."""
    mu, ratio = float(mu), _checked_ratio(ratio)
    if not (math.isfinite(mu) and mu > 0):
        raise InputError("mu", f"{mu!r} is not a positive finite friction coefficient", "give the ground's mu")
    return mu, ratio * mu


def _unit(down) -> tuple[float, float]:
    """``down`` (two components in the wheel frame) as a unit vector."""
    d = np.asarray(down, dtype=float).reshape(-1)
    norm = float(np.hypot(*d)) if d.size == 2 else math.nan
    if not (math.isfinite(norm) and norm > 0):
        raise InputError("down", f"{down!r} is not a direction in the slope plane", "give its wheel-frame (x, y)")
    return float(d[0] / norm), float(d[1] / norm)


def hold_angle(down, mu: float, ratio: float = 1.0) -> float:
    """The steepest slope (rad) that locked wheels hold when the downhill direction is ``down`` (x, y in
    the wheel frame: x along the wheels): tan a = 1 / sqrt((d_x / mu_l)^2 + (d_y / mu_t)^2), with
    mu_l = ``mu`` and mu_t = ``ratio`` x mu. atan(mu) for ratio 1; atan(mu_l) downhill along the
    wheels, atan(mu_t) across them."""
    mu_l, mu_t = _ellipse(mu, ratio)
    dx, dy = _unit(down)
    return math.atan2(1.0, math.hypot(dx / mu_l, dy / mu_t))


def slope_holds(angle: float, down, mu: float, ratio: float = 1.0) -> bool:
    """Whether locked wheels keep the robot parked on a slope of ``angle`` rad, downhill along ``down``
    (wheel frame): the friction that holds it, m g sin a d, lies inside the friction ellipse
    |M^-1 f| <= N = m g cos a, M = diag(mu_l, mu_t); that is sin a |M^-1 d| <= cos a (for ratio 1,
    a <= atan(mu))."""
    mu_l, mu_t = _ellipse(mu, ratio)
    dx, dy = _unit(down)
    return math.sin(angle) * math.hypot(dx / mu_l, dy / mu_t) <= math.cos(angle)


def _friction_step(px: float, py: float, bound: float, mu_l: float, mu_t: float) -> tuple[float, float]:
    """The velocity at the end of one implicit step: the minimiser of |v - p|^2 / 2 + bound |M v| (p: the
    velocity with the step's gravity impulse and no friction; bound: h g cos a). Zero when p lies in the
    ellipse of impulses friction can give, |M^-1 p| <= bound; else v = (I + lam M^2)^-1 p with
    lam |M v| = bound, found in t = lam / (1 + lam), whose residual rises from -bound at t = 0 to
    |M^-1 p| - bound > 0 at t = 1."""
    from scipy.optimize import brentq

    if math.hypot(px / mu_l, py / mu_t) <= bound:
        return 0.0, 0.0
    ml2, mt2 = mu_l * mu_l, mu_t * mu_t

    def excess(t: float) -> float:
        s = 1.0 - t
        return math.hypot(t * mu_l * px / (s + t * ml2), t * mu_t * py / (s + t * mt2)) - bound

    t = brentq(excess, 0.0, 1.0, xtol=1e-15, rtol=4 * np.finfo(float).eps)
    s = 1.0 - t
    return px * s / (s + t * ml2), py * s / (s + t * mt2)


@dataclass(frozen=True)
class SlopeSlide:
    """A robot on locked wheels released at rest on a slope (:func:`slope_slide`)."""

    time: np.ndarray  # (n + 1,) s: 0, h, ..., n h
    position: np.ndarray  # (n + 1, 2) m in the slope plane, wheel frame (x along the wheels), from the start
    velocity: np.ndarray  # (n + 1, 2) m/s, the same frame
    holds: bool  # the friction ellipse holds it (slope_holds): it stays parked
    acceleration: float  # m/s^2 along its path (0 when it holds)
    downhill_acceleration: float  # m/s^2, the acceleration's component along the downhill direction
    drift: float  # rad, the path's angle from the downhill direction (counter-clockwise, seen from above)


def slope_slide(
    angle: float,
    down,
    mu: float,
    ratio: float = 1.0,
    duration: float = 4.0,
    timestep: float = 1e-3,
    gravity: float = GRAVITY,
) -> SlopeSlide:
    """A robot on locked wheels released at rest on a slope of ``angle`` rad whose downhill direction is
    ``down`` (x, y in the wheel frame: x along the wheels), on ground of Coulomb coefficient ``mu`` with
    elliptic anisotropic wheel friction: mu_l = mu along the wheels, mu_t = ``ratio`` x mu across them.

    The wheels are locked, so every contact slides with the body's velocity u; the friction of a
    sliding contact is the maximum-dissipation force on its ellipse, -N_i M^2 u / |M u| (M = diag(mu_l,
    mu_t)): along -u only when u lies on an axis. The body then obeys m du/dt = m g sin a d - m g cos a
    M^2 u / |M u|, whatever the contacts' loads: all friction forces point the same way and scale with
    their loads, so their yaw moment about the centre of mass is that of the centre of pressure's
    offset, which the pitch and roll balances put along the friction force itself (it shifts by
    h F / N): none. That holds for every contact on the same ellipse (no skid, no caster) and for a
    body that does not yaw, which is then what it keeps doing. The law is integrated by implicit
    (backward) Euler on the velocity, as the engines' velocity-level contact solvers step it: each step
    solves for the friction at the step's end velocity, which holds the body at rest exactly inside the
    ellipse, never chatters about zero, and on the motion from rest is exact (below); positions by the
    trapezoid rule, exact for a constant acceleration.

    From rest the motion is a straight line at a constant acceleration c, the minimiser of
    |c|^2 / 2 - g sin a d.c + g cos a |M c| (the equation is homogeneous in u: u = c t solves it, and a
    convex friction law has one solution), so the path does not curve: it runs at the constant angle
    ``drift`` from the downhill direction, towards the axis of lower friction, and the acceleration
    along the downhill direction (``downhill_acceleration``, what a fit of the distance travelled
    downhill gives) is less than the one along the path (``acceleration``). With ratio 1, or the slope
    along an axis of the ellipse, c lies along d with g (sin a - mu cos a) (mu_l or mu_t on an axis).
    """
    mu_l, mu_t = _ellipse(mu, ratio)
    dx, dy = _unit(down)
    angle, duration, timestep = float(angle), float(duration), float(timestep)
    if not (math.isfinite(angle) and 0 <= angle < math.pi / 2):
        raise InputError("angle", f"{angle!r} rad is not a slope", "give the slope's angle in [0, pi/2) rad")
    if not (math.isfinite(duration) and math.isfinite(timestep) and 0 < timestep <= duration):
        raise InputError(
            "duration", f"duration {duration!r} s, timestep {timestep!r} s", "give 0 < timestep <= duration"
        )
    steps = int(round(duration / timestep))
    kick = gravity * math.sin(angle) * timestep
    bound = gravity * math.cos(angle) * timestep
    velocity = np.zeros((steps + 1, 2))
    vx = vy = 0.0
    for k in range(1, steps + 1):
        vx, vy = _friction_step(vx + kick * dx, vy + kick * dy, bound, mu_l, mu_t)
        velocity[k] = vx, vy
    position = np.zeros_like(velocity)
    position[1:] = np.cumsum((velocity[1:] + velocity[:-1]) * (timestep / 2), axis=0)
    end = steps * timestep
    ux, uy = velocity[-1]
    return SlopeSlide(
        time=np.arange(steps + 1) * timestep,
        position=position,
        velocity=velocity,
        holds=slope_holds(angle, (dx, dy), mu, ratio),
        acceleration=float(math.hypot(ux, uy) / end),
        downhill_acceleration=float((ux * dx + uy * dy) / end),
        drift=float(math.atan2(dx * uy - dy * ux, dx * ux + dy * uy)) if (ux or uy) else 0.0,
    )


__all__ = ["SlopeSlide", "hold_angle", "slope_holds", "slope_slide"]
