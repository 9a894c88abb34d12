"""The simulated IMU: from physics-rate kinematics to what a 3DM-GX3-25 would output.

Chain (METHOD.md section 3): specific force and angular rate in the body frame at the
physics rate -> block average down to the output rate (the sensor's moving-average
decimation) -> optional seeded bias and white noise -> saturation at the sensor's range.
Convention REP-145: specific force, so +9.81 m/s^2 on z at rest with z up; rad/s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from simpick.engines.base import GRAVITY


@dataclass(frozen=True)
class ImuModel:
    rate_hz: float = 100.0
    accel_range: float = 5 * GRAVITY  # +-5 g
    gyro_range: float = np.deg2rad(300.0)  # +-300 deg/s
    accel_noise_std: float = 0.0  # m/s^2 per output sample
    gyro_noise_std: float = 0.0  # rad/s per output sample
    accel_bias: tuple[float, float, float] = (0.0, 0.0, 0.0)
    gyro_bias: tuple[float, float, float] = (0.0, 0.0, 0.0)


def model_at_rate(settings: dict, rate_hz: float, timestep: float) -> ImuModel:
    """The configured sensor (``imu:`` settings, noise given per sample at ``settings["rate_hz"]``)
    read out at ``rate_hz`` instead: the nearest rate a whole number of physics steps per
    sample gives (the block average's own), with the white noise per sample scaled by
    sqrt(new rate / configured rate), since averaging over a longer block narrows its band.
    This is how a replay's simulated IMU is brought to the real log's rate."""
    block = max(1, int(round(1.0 / (rate_hz * timestep))))
    if block == int(round(1.0 / (settings["rate_hz"] * timestep))):
        return ImuModel(**settings)
    rate = 1.0 / (block * timestep)
    scale = float(np.sqrt(rate / settings["rate_hz"]))
    fields = {**settings, "rate_hz": rate}
    for key in ("accel_noise_std", "gyro_noise_std"):
        fields[key] = float(settings.get(key, 0.0)) * scale
    return ImuModel(**fields)


def rotation_matrices(quaternion: np.ndarray) -> np.ndarray:
    """(n, 4) w, x, y, z unit quaternions -> (n, 3, 3) body-to-world rotations."""
    w, x, y, z = np.moveaxis(np.asarray(quaternion, dtype=float), -1, 0)
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], -2)


def matrices_to_quaternions(rot: np.ndarray) -> np.ndarray:
    """(n, 3, 3) rotations -> (n, 4) unit quaternions w, x, y, z with w >= 0."""
    m = rot
    trace = np.trace(m, axis1=1, axis2=2)
    candidates = np.stack([
        np.stack([1 + trace, m[:, 2, 1] - m[:, 1, 2], m[:, 0, 2] - m[:, 2, 0], m[:, 1, 0] - m[:, 0, 1]], -1),
        np.stack([m[:, 2, 1] - m[:, 1, 2], 1 + m[:, 0, 0] - m[:, 1, 1] - m[:, 2, 2],
                  m[:, 0, 1] + m[:, 1, 0], m[:, 0, 2] + m[:, 2, 0]], -1),
        np.stack([m[:, 0, 2] - m[:, 2, 0], m[:, 0, 1] + m[:, 1, 0],
                  1 - m[:, 0, 0] + m[:, 1, 1] - m[:, 2, 2], m[:, 1, 2] + m[:, 2, 1]], -1),
        np.stack([m[:, 1, 0] - m[:, 0, 1], m[:, 0, 2] + m[:, 2, 0], m[:, 1, 2] + m[:, 2, 1],
                  1 - m[:, 0, 0] - m[:, 1, 1] + m[:, 2, 2]], -1),
    ], 1)  # (n, 4 candidates, 4): each is 4 q_i q for the i-th largest-component choice
    diag = np.stack([trace, m[:, 0, 0], m[:, 1, 1], m[:, 2, 2]], -1)
    best = np.argmax(diag, axis=1)  # the numerically safest candidate
    quat = candidates[np.arange(len(m)), best]
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    return quat * np.where(quat[:, :1] < 0, -1.0, 1.0)


def euler_rpy(quaternion: np.ndarray) -> np.ndarray:
    """(n, 4) w, x, y, z -> (n, 3) roll, pitch, yaw (rad, ZYX convention)."""
    w, x, y, z = np.moveaxis(np.asarray(quaternion, dtype=float), -1, 0)
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0))
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return np.stack([roll, pitch, yaw], -1)


def imu_from_kinematics(quaternion: np.ndarray, linear_velocity: np.ndarray,
                        angular_velocity: np.ndarray, mount: tuple[float, float, float],
                        dt: float, gravity=(0.0, 0.0, -GRAVITY)) -> tuple[np.ndarray, np.ndarray]:
    """Specific force and angular rate at an IMU mounted at ``mount`` (body frame).

    For engines with no IMU: the mount point's velocity is v + w x R r; its acceleration
    over each step is the finite difference of that velocity (the robot starts at rest,
    so the velocity before the first step is zero). Subtracting gravity and rotating
    into the body frame gives the accelerometer's reading.
    """
    rot = rotation_matrices(quaternion)
    lever = rot @ np.asarray(mount, dtype=float)
    v_mount = linear_velocity + np.cross(angular_velocity, lever)
    accel = np.diff(v_mount, axis=0, prepend=np.zeros((1, 3))) / dt
    specific_force_world = accel - np.asarray(gravity, dtype=float)
    to_body = np.transpose(rot, (0, 2, 1))
    specific_force = np.einsum("nij,nj->ni", to_body, specific_force_world)
    gyro = np.einsum("nij,nj->ni", to_body, angular_velocity)
    return specific_force, gyro


def block_average(samples: np.ndarray, block: int) -> np.ndarray:
    """Average consecutive blocks of ``block`` rows; an incomplete last block is dropped."""
    n = (len(samples) // block) * block
    return samples[:n].reshape(n // block, block, *samples.shape[1:]).mean(axis=1)


def interval_average(samples: np.ndarray, timestep: float, period: float) -> np.ndarray:
    """Average over consecutive output periods of a signal held constant over each physics step.

    Row i of ``samples`` holds over (i dt, (i + 1) dt]; output row k is its mean over
    (k T, (k + 1) T] for every whole period T the samples cover. Where T is a whole number of
    steps this is :func:`block_average`; otherwise a step that straddles two periods counts in
    each by the time it spends there (the integral of a piecewise constant signal is piecewise
    linear, so interpolating it at the period boundaries is exact).
    """
    steps = len(samples)
    n = int(np.floor(steps * timestep / period + 1e-9))
    flat = samples.reshape(steps, -1)
    integral = np.vstack([np.zeros((1, flat.shape[1])), np.cumsum(flat, axis=0) * timestep])
    knots = timestep * np.arange(steps + 1)
    bounds = period * np.arange(n + 1)
    at = np.column_stack([np.interp(bounds, knots, integral[:, j]) for j in range(flat.shape[1])])
    return (np.diff(at, axis=0) / period).reshape(n, *samples.shape[1:])


def sensor_output(specific_force: np.ndarray, gyro: np.ndarray, model: ImuModel,
                  rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Add bias and seeded white noise, then saturate at the sensor's range."""
    accel = specific_force + np.asarray(model.accel_bias)
    rate = gyro + np.asarray(model.gyro_bias)
    if model.accel_noise_std > 0:
        accel = accel + rng.normal(0.0, model.accel_noise_std, accel.shape)
    if model.gyro_noise_std > 0:
        rate = rate + rng.normal(0.0, model.gyro_noise_std, rate.shape)
    return (np.clip(accel, -model.accel_range, model.accel_range),
            np.clip(rate, -model.gyro_range, model.gyro_range))
