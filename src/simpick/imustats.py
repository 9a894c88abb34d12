"""The statistics an IMU window is described by, the same for a real log and a simulated trace:
per-axis mean (the paper's Eq. 5) and 1 %-trimmed range (Eq. 6), and the yaw-rate gain (measured
over kinematic yaw rate). The real data's segments are described by them (simpick.real.segments)
and the comparison compares them (simpick.compare.metrics, simpick.compare.realmetrics).
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import pandas as pd

# the IMU columns of a trace or a canonical log, per quantity, in the order of AXES
IMU_AXES = {"linear": ["ax", "ay", "az"], "angular": ["wx", "wy", "wz"]}
TRIM_FRACTION = 0.01
AXES = ("x", "y", "z")


def trimmed_range(values: Iterable[float], fraction: float = TRIM_FRACTION) -> float:
    """Mean of the top ``fraction`` of samples minus mean of the bottom ``fraction``.

    The tail holds max(1, round(fraction * n)) samples, so short series still have one.
    """
    x = np.asarray(values, dtype=float)
    if x.size == 0 or not np.isfinite(x).all():
        raise ValueError("trimmed_range needs a non-empty series of finite values")
    k = max(1, int(round(fraction * x.size)))
    ordered = np.sort(x)
    return float(ordered[-k:].mean() - ordered[:k].mean())


def axis_stats(values: Iterable[float], fraction: float = TRIM_FRACTION) -> dict[str, float]:
    x = np.asarray(values, dtype=float)
    return {"mean": float(x.mean()), "range": trimmed_range(x, fraction)}


def trace_stats(frame: pd.DataFrame) -> dict[str, dict[str, dict[str, float]]]:
    """{'linear'|'angular': {axis: {'mean', 'range'}}} of an IMU trace."""
    return {
        quantity: {axis: axis_stats(frame[col]) for axis, col in zip(AXES, cols)} for quantity, cols in IMU_AXES.items()
    }


def yaw_rate_gain(
    yaw_rate: np.ndarray, v_left: np.ndarray, v_right: np.ndarray, track: float, min_kinematic: float = 0.05
) -> float:
    """Least-squares gain through the origin of measured over kinematic yaw rate.

    Only samples whose kinematic yaw rate exceeds ``min_kinematic`` rad/s count; NaN if none.
    """
    kinematic = (np.asarray(v_right, float) - np.asarray(v_left, float)) / track
    yaw = np.asarray(yaw_rate, float)
    turning = np.abs(kinematic) > min_kinematic
    if not turning.any():
        return float("nan")
    k, y = kinematic[turning], yaw[turning]
    return float(np.dot(y, k) / np.dot(k, k))
