"""Physics health: catch a run that diverged or misbehaved before it reaches a score.

The failure modes are the ones Farley et al. (2022, section 3.1.2) met in the simulators'
engines: the robot falling through the floor, jumping in position or velocity, flipping,
and sliding while it should stand still. Thresholds come from config.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from simpick.engines.base import PhysicsRecord
from simpick.engines.kinematics import euler_rpy


@dataclass(frozen=True)
class HealthLimits:
    min_height: float = -0.05  # m, base_link z below the ground surface
    max_tilt: float = 1.0  # rad, |roll| or |pitch|
    max_speed: float = 5.0  # m/s; the Husky tops out near 1 m/s
    max_velocity_jump: float = 0.5  # m/s change of the base velocity within one physics step
    wheel_tracking: float = 0.5  # rad/s: mean wheel-speed error over a second, lag at a command change excused
    wheel_lag: float = 0.05  # s: time constant of the slowest servo response still counted as following
    max_parked_speed: float = 0.05  # m/s while every wheel is commanded to stand still
    timeout: float = 300.0  # s of wall time before a simulation job is stopped as hung


@dataclass
class Health:
    ok: bool = True
    reasons: list[str] = field(default_factory=list)

    def fail(self, reason: str) -> None:
        self.ok = False
        self.reasons.append(reason)

    def as_dict(self) -> dict:
        return {"status": "ok" if self.ok else "failed", "reasons": self.reasons}


def _first_sustained(flags: np.ndarray, samples: int) -> int | None:
    """Index where ``flags`` has been true for ``samples`` steps in a row, if ever."""
    if samples <= 1:
        hits = np.flatnonzero(flags)
        return int(hits[0]) if hits.size else None
    run = np.convolve(flags.astype(float), np.ones(samples), mode="valid")
    hits = np.flatnonzero(run >= samples)
    return int(hits[0] + samples - 1) if hits.size else None


def first_order_lag(commands: np.ndarray, a: float) -> np.ndarray:
    """``commands`` (steps, wheels) through the lag y[n] = a x[n] + (1 - a) y[n - 1] from rest, column by column:
    the same floats as ``scipy.signal.lfilter([a], [1, a - 1], commands, axis=0)``, each step's two products and
    sum taken in the order of its transposed direct form. Not lfilter itself: importing scipy.signal costs a
    simulation job 0.6 s of CPU, more than this loop over a whole replayed run (the columns are few and a
    replay's repeat: the Husky's left and right wheels share their side's command)."""
    commands = np.asarray(commands, dtype=np.float64)
    lagged = np.empty(commands.shape)
    b0, a1 = float(a), float(a) - 1.0
    done: list[int] = []
    for j in range(commands.shape[1]):
        column = commands[:, j]
        bits = column.view(np.uint64)
        same = next((k for k in done if np.array_equal(commands[:, k].view(np.uint64), bits)), None)
        if same is not None:  # a column met before, bit for bit: the same floats out
            lagged[:, j] = lagged[:, same]
            continue
        out, z = [], 0.0
        append = out.append
        for x in column.tolist():
            y = z + b0 * x
            z = 0.0 * x - a1 * y
            append(y)
        lagged[:, j] = out
        done.append(j)
    return lagged


def following_error(wheel_speed: np.ndarray, commands: np.ndarray, dt: float, lag: float) -> np.ndarray:
    """Per step, the mean over the wheels of how far each wheel's speed lies outside the band between
    its command and that command passed through a first-order lag of time constant ``lag`` (s), from
    rest: 0 for a wheel on its command, and 0 for a servo catching up with a change of its command at
    least as fast as that lag. A stuck or stalled wheel leaves the band as soon as the lagged command
    does: its error is nearly the command's speed itself.

    ``commands`` and ``wheel_speed``: (steps, wheels); ``dt``: the step, s."""
    if lag <= 0 or dt <= 0:
        return np.abs(wheel_speed - commands).mean(axis=1)
    a = -np.expm1(-dt / lag)  # exact for a command held over each step
    lagged = first_order_lag(commands, a)
    high, low = np.maximum(commands, lagged), np.minimum(commands, lagged)
    return (np.clip(wheel_speed - high, 0.0, None) + np.clip(low - wheel_speed, 0.0, None)).mean(axis=1)


def check(record: PhysicsRecord, limits: HealthLimits, commands: np.ndarray | None = None) -> Health:
    """``commands``: robot 0's (steps, 4) wheel-speed commands, for the tracking checks."""
    health = Health()
    arrays = {
        "position": record.position,
        "quaternion": record.quaternion,
        "linear velocity": record.linear_velocity,
        "angular velocity": record.angular_velocity,
        "IMU": record.imu_specific_force,
    }
    for name, values in arrays.items():
        bad = ~np.isfinite(values).all(axis=-1)
        if bad.any():
            health.fail(f"non-finite {name} from t = {record.time[np.argmax(bad)]:.3f} s (simulation diverged)")
    if not health.ok:
        return health
    z = record.position[:, 2]
    if (z < limits.min_height).any():
        k = int(np.argmax(z < limits.min_height))
        health.fail(f"fell through the ground: base z = {z[k]:.3f} m at t = {record.time[k]:.3f} s")
    tilt = np.abs(euler_rpy(record.quaternion)[:, :2]).max(axis=1)
    if (tilt > limits.max_tilt).any():
        k = int(np.argmax(tilt > limits.max_tilt))
        health.fail(
            f"flipped: roll/pitch {np.degrees(tilt[k]):.0f} deg at t = {record.time[k]:.3f} s "
            f"(limit {np.degrees(limits.max_tilt):.0f} deg)"
        )
    speed = np.linalg.norm(record.linear_velocity, axis=1)
    if (speed > limits.max_speed).any():
        k = int(np.argmax(speed > limits.max_speed))
        health.fail(f"exploded: speed {speed[k]:.1f} m/s at t = {record.time[k]:.3f} s")
    # The robot starts at rest, so the first step's change is measured from zero.
    jump = np.linalg.norm(np.diff(record.linear_velocity, axis=0, prepend=np.zeros((1, 3))), axis=1)
    if (jump > limits.max_velocity_jump).any():
        k = int(np.argmax(jump > limits.max_velocity_jump))
        health.fail(
            f"jump: base velocity changed by {jump[k]:.2f} m/s within one step at t = {record.time[k]:.3f} s "
            f"(limit {limits.max_velocity_jump} m/s; no wheel-terrain force explains it)"
        )
    if commands is not None:
        dt = float(record.time[0]) if len(record.time) else 0.0
        second = max(1, int(round(1.0 / dt))) if dt > 0 else 1
        # A servo lags at every change of its command (MuJoCo's settles a quarter second after a
        # step to 1 m/s): measured against the band a servo of time constant wheel_lag would sweep,
        # that lag is no error, while a wheel that cannot follow leaves the band.
        error = following_error(record.wheel_speed, commands, dt, limits.wheel_lag)
        smoothed = np.convolve(error, np.ones(second) / second, mode="same")
        k = _first_sustained(smoothed > limits.wheel_tracking, 1)
        if k is not None:
            health.fail(
                f"wheels do not track their command: mean speed error {smoothed[k]:.2f} rad/s "
                f"beyond a {limits.wheel_lag} s servo lag around t = {record.time[k]:.3f} s "
                f"(limit {limits.wheel_tracking} rad/s; torque bound too low or wheels stuck)"
            )
        # Parked = every wheel commanded to stop for a full second already: braking from speed
        # takes a moment on low friction, and is not sliding.
        stopped = np.all(commands == 0, axis=1)
        parked = np.convolve(stopped.astype(float), np.ones(second), mode="full")[: len(stopped)] >= second
        speed = np.linalg.norm(record.linear_velocity[:, :2], axis=1)
        k = _first_sustained(parked & (speed > limits.max_parked_speed), max(1, second // 10))
        if k is not None:
            health.fail(
                f"slides while commanded to stand still: {speed[k]:.2f} m/s at t = {record.time[k]:.3f} s "
                f"(limit {limits.max_parked_speed} m/s)"
            )
    return health
