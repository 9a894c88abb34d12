"""Checks shared by every real-log reader: each failure is an InputError naming the file,
the column and, where there is one, the row.

Row labels are supplied by the reader (``csv_row``: "row 5 (line 6)" counting the header
as line 1; ``message_row``: "message 5" for bags), so the same checks serve CSV files,
bags and canonical Parquet files.

Plausibility limits (a Husky A200 tops out near 1 m/s and 2 rad/s):
  * gyro: a running median of |w| above 20 rad/s (over 11 samples, so a lone spike does
    not count) reads as deg/s;
  * accelerometer: the norm of the mean specific force must be near 9.81 (7..13 m/s^2);
    near 1 reads as g; near 0 reads as gravity removed; the mean must point along +z
    (z up) within 60 degrees;
  * wheel / body speeds above 5 m/s, body yaw rates above 20 rad/s;
  * gyro yaw rate more than 3x the commanded yaw rate on turning commands: deg/s again
    (skid-steer slip makes the real ratio 0.05..0.8; deg/s multiplies it by 57);
  * a declared sample rate: the median-interval rate must be within 20 %;
  * a steady stream (the dataset-folder reader asks for one): no interval longer than
    10 median intervals and 0.5 s (a gap: the real signal is unknown there), and at most
    10 % of the intervals more than 50 % off the median one (jitter: no single rate).
    Duplicated or backward times are refused for every stream (``check_time``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np
import pandas as pd

from simpick.errors import InputError

RowLabel = Callable[[int], str]

GYRO_LIMIT = 20.0  # rad/s, sustained
GYRO_WINDOW = 11  # samples in the running median
ACCEL_OK = (7.0, 13.0)  # m/s^2, norm of the mean specific force
ACCEL_G = (0.6, 1.6)  # the same in g
SPEED_LIMIT = 5.0  # m/s
YAW_RATE_LIMIT = 20.0  # rad/s, body command
YAW_GAIN_LIMIT = 3.0  # measured / commanded yaw rate
RATE_TOLERANCE = 0.20
GAP_INTERVALS = 10.0  # median intervals
GAP_MIN_S = 0.5  # s: shorter holes are interpolated over harmlessly
JITTER_OFF = 0.5  # an interval this far (relative) from the median one is off
JITTER_SHARE = 0.10  # share of off intervals above which a stream has no single rate


def csv_row(i: int) -> str:
    """Data row i (0-based) of a CSV with one header line."""
    return f"row {i + 1} (line {i + 2})"


def message_row(i: int) -> str:
    return f"message {i + 1}"


def plain_row(i: int) -> str:
    return f"row {i + 1}"


class Label(str):
    """A column label already worded for messages, e.g. "column 'gyro_x' (mapping key 'wx')"."""


def col_where(where: str, column: str) -> str:
    return f"{where}: {column}" if isinstance(column, Label) else f"{where}: column {column!r}"


def require_columns(frame: pd.DataFrame, columns: Sequence[str], where: str) -> None:
    missing = [c for c in columns if c not in frame.columns]
    if missing:
        present = ", ".join(repr(str(c)) for c in frame.columns) or "none"
        raise InputError(
            where,
            f"missing column(s) {', '.join(repr(c) for c in missing)}; columns present: {present}",
            "rename the columns or give a column mapping",
        )


def numeric_column(raw: pd.Series, where: str, column: str, row_label: RowLabel) -> np.ndarray:
    """The column as float64; a cell that is not a number is an error naming its row.

    Empty cells and NaN come back as NaN (``check_finite`` decides whether that is allowed).
    """
    if pd.api.types.is_bool_dtype(raw.dtype):
        raise InputError(col_where(where, column), f"holds true/false values, not numbers (first at {row_label(0)})")
    if pd.api.types.is_numeric_dtype(raw.dtype):
        return raw.to_numpy(dtype=np.float64, na_value=np.nan)
    values = pd.to_numeric(raw, errors="coerce")
    bad = np.flatnonzero(raw.notna().to_numpy() & values.isna().to_numpy())
    if len(bad):
        i = int(bad[0])
        raise InputError(
            col_where(where, column),
            f"non-numeric value {str(raw.iloc[i])[:40]!r} at {row_label(i)}",
            "every cell of this column must be a number",
        )
    return values.to_numpy(dtype=np.float64, na_value=np.nan)


def check_finite(values: np.ndarray, where: str, column: str, row_label: RowLabel) -> None:
    nan = np.flatnonzero(np.isnan(values))
    if len(nan):
        raise InputError(
            col_where(where, column),
            f"empty or NaN value at {row_label(int(nan[0]))}" + (f" ({len(nan)} in all)" if len(nan) > 1 else ""),
            "remove or repair the row",
        )
    inf = np.flatnonzero(np.isinf(values))
    if len(inf):
        raise InputError(
            col_where(where, column),
            f"infinite value at {row_label(int(inf[0]))}" + (f" ({len(inf)} in all)" if len(inf) > 1 else ""),
            "remove or repair the row",
        )


def check_time(time: np.ndarray, where: str, column: str, row_label: RowLabel, rows: np.ndarray | None = None) -> None:
    """Strictly increasing; ``rows`` maps positions in ``time`` to source rows."""
    if len(time) == 0:
        raise InputError(col_where(where, column), "has no samples")
    step = np.diff(time)
    bad = np.flatnonzero(~(step > 0))
    if len(bad):
        i = int(bad[0]) + 1
        src = (lambda k: int(rows[k])) if rows is not None else (lambda k: k)
        kind = "duplicates" if step[i - 1] == 0 else "goes backwards from"
        raise InputError(
            col_where(where, column),
            f"time is not strictly increasing: {float(time[i])!r} at {row_label(src(i))} "
            f"{kind} {float(time[i - 1])!r} at {row_label(src(i - 1))}",
            "sort the rows by time and drop duplicated samples",
        )


def measured_rate(time: np.ndarray) -> dict:
    """Sample-rate summary of a strictly increasing time vector (s)."""
    n = len(time)
    if n < 2:
        return {"samples": n, "duration_s": 0.0, "median_hz": None, "mean_hz": None}
    duration = float(time[-1] - time[0])
    step = np.diff(time)
    median = float(np.median(step))
    off = np.abs(step / median - 1.0)
    return {
        "samples": n,
        "duration_s": duration,
        "median_hz": float(1.0 / median),
        "mean_hz": float((n - 1) / duration),
        "median_interval_s": median,
        "max_interval_s": float(step.max()),
        "jitter_p95": float(np.quantile(off, 0.95)),
        "off_share": float(np.mean(off > JITTER_OFF)),
    }


def check_rate(
    time: np.ndarray,
    declared_hz: float | None,
    where: str,
    column: str,
    stream: str,
    tolerance: float = RATE_TOLERANCE,
    *,
    declared_by: str = "the reader's options",
    steady: bool = False,
    row_label: RowLabel = plain_row,
    rows: np.ndarray | None = None,
) -> dict:
    """The measured rates (median interval); an error when the stream is not steady (if
    ``steady``) or its rate contradicts the one ``declared_by`` declares."""
    rate = measured_rate(time)
    if rate["samples"] < 2:
        raise InputError(
            col_where(where, column), f"the {stream} stream has {rate['samples']} sample(s); at least 2 are needed"
        )
    median, got = rate["median_interval_s"], rate["median_hz"]
    if steady:
        step = np.diff(time)
        src = (lambda k: int(rows[k])) if rows is not None else (lambda k: k)
        gaps = np.flatnonzero(step > max(GAP_INTERVALS * median, GAP_MIN_S))
        if len(gaps):
            k = int(np.argmax(step))
            raise InputError(
                col_where(where, column),
                f"the {stream} stream stops for {step[k]:.4g} s ({step[k] / median:.0f} median "
                f"intervals) between {row_label(src(k))} (time {time[k]:.6g}) and "
                f"{row_label(src(k + 1))} (time {time[k + 1]:.6g})"
                + (f"; {len(gaps)} such gaps" if len(gaps) > 1 else ""),
                "split the run at the gap into two runs, or drop the file",
            )
        if rate["off_share"] > JITTER_SHARE:
            first = int(np.flatnonzero(np.abs(step / median - 1.0) > JITTER_OFF)[0])
            raise InputError(
                col_where(where, column),
                f"the {stream} stream has no steady rate: {100 * rate['off_share']:.0f} % of its "
                f"sample intervals are more than {100 * JITTER_OFF:.0f} % off the median "
                f"{median:.4g} s (first at {row_label(src(first + 1))})",
                "resample the stream to one rate, or check that the time column holds one stream",
            )
    if declared_hz is not None and abs(got / declared_hz - 1.0) > tolerance:
        raise InputError(
            col_where(where, column),
            f"measured {stream} sample rate {got:.4g} Hz (median interval {median:.4g} s) "
            f"contradicts the declared {declared_hz:g} Hz of {declared_by} "
            f"({100 * (got / declared_hz - 1):+.0f} %)",
            "correct the declared rate, or check the time unit (s, ms, ns)",
        )
    return rate


def check_imu_units(imu: pd.DataFrame, where: str, names: Mapping[str, str], row_label: RowLabel) -> dict:
    """Units plausibility of a canonical IMU frame; ``names`` maps canonical to source columns.

    Returns a summary (mean specific force, gravity estimate, peak gyro rate) for the meta.
    """
    gyro = imu[["wx", "wy", "wz"]].to_numpy(dtype=float)
    norm = np.linalg.norm(gyro, axis=1)
    window = min(GYRO_WINDOW, len(norm))
    running = pd.Series(norm).rolling(window, center=True, min_periods=window).median().to_numpy()
    over = np.flatnonzero(running > GYRO_LIMIT)
    if len(over):
        i = int(over[0])
        lo, hi = max(0, i - window // 2), min(len(norm), i + window // 2 + 1)
        axis = ["wx", "wy", "wz"][int(np.argmax(np.abs(gyro[lo:hi]).max(axis=0)))]
        raise InputError(
            col_where(where, names.get(axis, axis)),
            f"gyro rate stays above {GYRO_LIMIT:g} rad/s around {row_label(lo)} "
            f"(running median |w| = {running[i]:.4g}): the gyro looks like deg/s",
            "give the gyro unit as deg/s (or convert to rad/s)",
        )

    accel = imu[["ax", "ay", "az"]].to_numpy(dtype=float)
    mean = accel.mean(axis=0)
    g = float(np.linalg.norm(mean))
    dominant = ["ax", "ay", "az"][int(np.argmax(np.abs(mean)))]
    acc_where = col_where(where, names.get(dominant, dominant))
    if ACCEL_G[0] <= g <= ACCEL_G[1]:
        raise InputError(
            acc_where,
            f"mean specific force is {g:.3g}, near 1: the accelerometer looks like g, not m/s^2",
            "give the accelerometer unit as g (or multiply by 9.80665)",
        )
    if g < ACCEL_G[0]:
        raise InputError(
            acc_where,
            f"mean specific force is {g:.3g} m/s^2, near 0: gravity seems "
            "removed (simpick needs specific force, +9.81 on z at rest)",
            "use the raw accelerometer, not gravity-compensated acceleration",
        )
    if not ACCEL_OK[0] <= g <= ACCEL_OK[1]:
        raise InputError(
            acc_where,
            f"mean specific force is {g:.4g}, far from 9.81 m/s^2: implausible units",
            "check the accelerometer unit",
        )
    if mean[2] < 0.5 * g:
        raise InputError(
            col_where(where, names.get("az", "az")),
            f"mean az is {mean[2]:.3g} m/s^2 of {g:.3g}: gravity is not along +z, "
            "so z does not point up (or the axes are swapped)",
            "declare the frame as z down, or fix the axis mapping",
        )
    return {
        "mean_specific_force": [float(x) for x in mean],
        "gravity_estimate": g,
        "peak_gyro_rad_s": float(norm.max()) if len(norm) else 0.0,
    }


def check_command_units(
    commands: pd.DataFrame, where: str, names: Mapping[str, str], row_label: RowLabel, rows: np.ndarray | None = None
) -> None:
    limits = {"v_left": SPEED_LIMIT, "v_right": SPEED_LIMIT, "v": SPEED_LIMIT, "w": YAW_RATE_LIMIT}
    for column, limit in limits.items():
        if column not in commands:
            continue
        values = commands[column].to_numpy(dtype=float)
        bad = np.flatnonzero(np.abs(values) > limit)
        if len(bad):
            k = int(bad[0])
            row = int(rows[k]) if rows is not None else k
            unit = "rad/s" if column == "w" else "m/s"
            hint = "deg/s?" if column == "w" else "rad/s of the wheel, mm/s or km/h?"
            raise InputError(
                col_where(where, names.get(column, column)),
                f"{values[k]:.4g} {unit} at {row_label(row)} exceeds the plausible "
                f"{limit:g} {unit} for a ground robot ({hint})",
                "check the unit of this column",
            )


def yaw_check(imu: pd.DataFrame, commands: pd.DataFrame, track: float) -> dict:
    """Compare the gyro yaw rate with the commanded one (frame and unit sanity).

    The commanded yaw rate is (v_right - v_left) / track (or w); the gyro wz is averaged over
    each command interval. On commands that turn (|yaw rate| > 0.1 rad/s), the least-squares
    gain wz ~ gain * commanded is positive for z up / y left; skid-steer slip keeps it below 1.
    """
    if "w" in commands:
        cmd = commands["w"].to_numpy(dtype=float)
    else:
        cmd = (commands["v_right"] - commands["v_left"]).to_numpy(dtype=float) / track
    tc = commands["time"].to_numpy(dtype=float)
    ti, wz = imu["time"].to_numpy(dtype=float), imu["wz"].to_numpy(dtype=float)
    # mean gyro over [t_k, t_{k+1}) by cumulative trapezoid, interpolated at the edges
    cum = np.concatenate([[0.0], np.cumsum(np.diff(ti) * 0.5 * (wz[1:] + wz[:-1]))])
    edges = np.append(tc, tc[-1] + (np.median(np.diff(tc)) if len(tc) > 1 else 0.1))
    inside = (edges[:-1] >= ti[0]) & (edges[1:] <= ti[-1])
    area = np.interp(edges, ti, cum)
    measured = np.diff(area) / np.diff(edges)
    turning = inside & (np.abs(cmd) > 0.1)
    n = int(turning.sum())
    result = {
        "turning_commands": n,
        "yaw_gain": None,
        "verdict": "undetermined",
        "note": "fewer than 10 turning commands",
    }
    if n >= 10:
        c, m = cmd[turning], measured[turning]
        gain = float((c * m).sum() / (c * c).sum())
        agree = float(np.mean(np.sign(c) == np.sign(m)))
        result.update(yaw_gain=gain, sign_agreement=agree)
        if gain > 0:
            result.update(verdict="consistent", note="gyro wz has the sign of the commanded yaw rate (z up, y left)")
        else:
            result.update(
                verdict="contradicts",
                note="gyro wz has the opposite sign of the commanded yaw rate: z down, "
                "left/right swapped, or a reversing run; the data are NOT flipped",
            )
    return result


def check_yaw_units(check: dict, where: str, column: str) -> None:
    gain = check.get("yaw_gain")
    if gain is not None and gain > YAW_GAIN_LIMIT:
        raise InputError(
            col_where(where, column),
            f"the gyro yaw rate is {gain:.3g} x the commanded yaw rate on turning "
            "commands: the gyro looks like deg/s (or the speeds are too small)",
            "check the gyro and wheel-speed units",
        )
