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


def sensor_output(
    specific_force: np.ndarray, gyro: np.ndarray, model: ImuModel, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """Add bias and seeded white noise, then saturate at the sensor's range."""
    accel = specific_force + np.asarray(model.accel_bias)
    rate = gyro + np.asarray(model.gyro_bias)
    if model.accel_noise_std > 0:
        accel = accel + rng.normal(0.0, model.accel_noise_std, accel.shape)
    if model.gyro_noise_std > 0:
        rate = rate + rng.normal(0.0, model.gyro_noise_std, rate.shape)
    return (np.clip(accel, -model.accel_range, model.accel_range), np.clip(rate, -model.gyro_range, model.gyro_range))
