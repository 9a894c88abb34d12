"""DRIVE's arrays turned into measurements (:mod:`simpick.real.logs.drive` describes the quirks they
answer): the per-sample series read and checked, the ICP's update-to-update rates and the windows
composed into a step's frame, the windows whose ICP moves against the wheels, the command held over a
step, the gyro's sign against the ICP, and a hash of the data."""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.errors import InputError

RATE_HZ = 20.0  # DRIVE's logger writes one sample per 0.05 s (sample-and-hold of each topic)
DT = 1.0 / RATE_HZ
MIN_SIGN_STEPS = 3  # steps turning faster than SIGN_TURN (ICP) needed to fix the gyro's sign
SIGN_TURN = 0.2  # rad/s
MIN_SIGN_CORRELATION = 0.9
REVERSED_SPEED = 0.3  # m/s: an ICP window moving against its wheels faster than this, both ways, is not used
# (ten times the ICP's spread against the wheels on grass, where no window reverses: median |ICP - wheels| per
# step 0.01-0.04 m/s; the reversed windows of the shared sessions run at 0.3-3.2 m/s against their wheels)


def series_of(frame: pd.DataFrame, base: str, n: int, path: Path) -> np.ndarray:
    names = [f"{base}_{i}" for i in range(n)]
    missing = [c for c in names if c not in frame.columns]
    if missing:
        raise InputError(
            f"{path}: column {missing[0]!r}",
            f"missing ({len(missing)} of {base}_0..{base}_{n - 1})",
            "the file is not a complete DRIVE slip dataset; use the pickle DRIVE's parser wrote",
        )
    values = frame[names].to_numpy()
    if values.dtype.kind not in "fiu":
        raise InputError(
            f"{path}: columns {base}_*", f"not numeric (dtype {values.dtype})", "use the pickle DRIVE's parser wrote"
        )
    bad = np.argwhere(~np.isfinite(values.astype(float)))
    if len(bad):
        row, col = bad[0]
        raise InputError(
            f"{path}: column {names[col]!r}",
            f"not finite at row {row}",
            "repair or drop that step (its three rows) from the file",
        )
    return values.astype(float)


def column_of(frame: pd.DataFrame, name: str, path: Path) -> np.ndarray:
    if name not in frame.columns:
        raise InputError(f"{path}: column {name!r}", "missing", "use the pickle DRIVE's parser wrote")
    return series_of(frame.rename(columns={name: f"{name}_0"}), name, 1, path)[:, 0]


def content_sha256(arrays: Mapping[str, np.ndarray]) -> str:
    """A hash of the arrays read (names, shapes and float64 bytes): equal for the same data whatever
    the file's pickle protocol, folder or name."""
    h = hashlib.sha256()
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name], dtype="<f8")
        h.update(name.encode() + repr(a.shape).encode() + a.tobytes())
    return h.hexdigest()


def update_rates(x: np.ndarray, y: np.ndarray, yaw: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per window, the mean body speed (vx, vy) and yaw rate between the first and the last ICP pose
    update (the ticks where the held pose changes): both poses are fresh to within one tick, so the
    interval is known, where the window's first sample is a held origin of unknown age."""
    n_rows = len(x)
    vx, vy, wz = (np.full(n_rows, np.nan) for _ in range(3))
    changed = (np.diff(x, axis=1) != 0) | (np.diff(y, axis=1) != 0) | (np.diff(yaw, axis=1) != 0)
    for k in range(n_rows):
        ticks = np.flatnonzero(changed[k]) + 1
        if len(ticks) < 2:
            continue
        a, b = ticks[0], ticks[-1]
        dt = DT * (b - a)
        dpsi = yaw[k, b] - yaw[k, a]
        mid = 0.5 * (yaw[k, a] + yaw[k, b])
        dx, dy = x[k, b] - x[k, a], y[k, b] - y[k, a]
        # chord in the mid-heading frame, lengthened to the arc of a constant-curvature path
        arc = 1.0 if abs(dpsi) < 1e-9 else (dpsi / 2) / np.sin(dpsi / 2)
        vx[k] = (dx * np.cos(mid) + dy * np.sin(mid)) * arc / dt
        vy[k] = (-dx * np.sin(mid) + dy * np.cos(mid)) * arc / dt
        wz[k] = dpsi / dt
    return vx, vy, wz


def reversed_windows(vx: np.ndarray, wheel_left: np.ndarray, wheel_right: np.ndarray, radius: float) -> np.ndarray:
    """Per window, whether its ICP forward speed ``vx`` (m/s) and its wheels' kinematic forward speed (the
    mean of the measured wheel speeds, rad/s, times ``radius``) both exceed :data:`REVERSED_SPEED` with
    opposite signs: motion no ground gives driven wheels (simpick.real.logs.drive's quirks)."""
    v_kin = radius * (wheel_left.mean(axis=1) + wheel_right.mean(axis=1)) / 2
    with np.errstate(invalid="ignore"):
        return (np.abs(v_kin) > REVERSED_SPEED) & (np.abs(vx) > REVERSED_SPEED) & (np.sign(vx) != np.sign(v_kin))


def compose_windows(x: np.ndarray, y: np.ndarray, yaw: np.ndarray, per_step: int) -> tuple[np.ndarray, ...]:
    """Each step's windows (poses relative to each window's start) in the step's start frame: window
    j+1 starts where window j's last sample ends (0.05 s of motion between them is not logged)."""
    X, Y, Yaw = x.copy(), y.copy(), yaw.copy()
    for first in range(0, len(x), per_step):
        ox = oy = oyaw = 0.0
        for k in range(first, first + per_step):
            c, s = np.cos(oyaw), np.sin(oyaw)
            X[k] = ox + c * x[k] - s * y[k]
            Y[k] = oy + s * x[k] + c * y[k]
            Yaw[k] = oyaw + yaw[k]
            ox, oy, oyaw = X[k, -1], Y[k, -1], Yaw[k, -1]
    return X, Y, Yaw


def held_longest(values: np.ndarray) -> np.ndarray:
    """Per row, the value held longest (the step's command, where the next one may arrive early)."""
    out = np.empty(len(values))
    for k, row in enumerate(values):
        uniq, counts = np.unique(row, return_counts=True)
        out[k] = uniq[counts.argmax()]
    return out


def fix_gyro_sign(gyro: np.ndarray, icp: np.ndarray, declared: int | None, path: Path, declared_by: str) -> dict:
    """The sign that makes the gyro agree with the ICP yaw rate, from the correlation of the steps' steady means."""
    ok = np.isfinite(icp)
    turning = int((np.abs(icp[ok]) > SIGN_TURN).sum())
    corr = (
        float(np.corrcoef(gyro[ok], icp[ok])[0, 1])
        if ok.sum() >= 3 and np.ptp(gyro[ok]) > 0 and np.ptp(icp[ok]) > 0
        else float("nan")
    )
    basis = (
        f"correlation of the steps' steady gyro means with the ICP yaw rate {corr:+.4f} over {int(ok.sum())} "
        f"steps, {turning} turning faster than {SIGN_TURN} rad/s"
    )
    decided = turning >= MIN_SIGN_STEPS and abs(corr) >= MIN_SIGN_CORRELATION
    if declared is not None:
        if declared not in (1, -1):
            raise InputError(f"gyro_sign ({declared_by})", f"{declared!r} must be +1 or -1")
        if decided and int(np.sign(corr)) != declared:
            raise InputError(
                f"{path}: column 'imu_yaw_*'",
                f"gyro sign {declared:+d} declared by {declared_by}, "
                f"but the data say {int(np.sign(corr)):+d} ({basis})",
                "remove the declared gyro_sign (the reader fixes it from the data)",
            )
        return {"sign": declared, "by": f"declared by {declared_by}", "basis": basis, "correlation": corr}
    if not decided:
        raise InputError(
            f"{path}: column 'imu_yaw_*'",
            f"the gyro's sign cannot be fixed from the data ({basis}; needed: at least "
            f"{MIN_SIGN_STEPS} turning steps and |correlation| >= {MIN_SIGN_CORRELATION})",
            f"declare gyro_sign (+1 or -1) for this session ({declared_by})",
        )
    return {"sign": int(np.sign(corr)), "by": "the ICP yaw rate", "basis": basis, "correlation": corr}
