"""The common tail of every reader: columns already numeric, finite and time-ordered in
source units converted to canonical ones; here the rates, the unit plausibility, the yaw
sign check, the shared clock and the meta."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from simpick import __version__
from simpick.errors import InputError
from simpick.real.logs import validate as V
from simpick.real.logs.canonical import DEFAULT_TRACK, FRAME, UNITS, RealLog, jsonable

READER_VERSION = "1"


def source_columns(
    frame: pd.DataFrame,
    columns: Mapping[str, str],
    where: str,
    row_label: V.RowLabel,
    *,
    labels: Mapping[str, str] | None = None,
    time_key: str = "time",
) -> pd.DataFrame:
    """Canonical-named float64 columns from source columns, each numeric and finite,
    with the time column strictly increasing. ``columns`` maps canonical -> source name;
    ``labels`` (canonical -> message label) overrides how errors name a column."""
    V.require_columns(frame, list(dict.fromkeys(columns.values())), where)
    labels = labels or {}
    out = {}
    for key, col in columns.items():
        values = V.numeric_column(frame[col], where, labels.get(key, col), row_label)
        V.check_finite(values, where, labels.get(key, col), row_label)
        out[key] = values
    V.check_time(out[time_key], where, labels.get(time_key, columns[time_key]), row_label)
    return pd.DataFrame(out)


def finish(
    imu: pd.DataFrame,
    commands: pd.DataFrame,
    *,
    imu_where: str,
    cmd_where: str,
    imu_names: Mapping[str, str],
    cmd_names: Mapping[str, str],
    imu_row_label: V.RowLabel,
    cmd_row_label: V.RowLabel,
    cmd_rows: np.ndarray | None = None,
    declared_hz: Mapping[str, float | None] | None = None,
    declared_by: str = "the reader's options",
    steady: bool = False,
    track: float = DEFAULT_TRACK,
    meta: Mapping | None = None,
    reader: str = "simpick.real.logs",
) -> RealLog:
    """Check and package canonical frames (times still on the source clock, in s).

    ``declared_hz`` ("imu", "commands"): rates the data must show, declared by ``declared_by``
    (named in the error); ``steady``: each stream must also keep one rate (no gaps, no jitter).
    """
    declared_hz = dict(declared_hz or {})
    t_imu = imu["time"].to_numpy(dtype=float)
    t_cmd = commands["time"].to_numpy(dtype=float)
    rates = {
        "imu": V.check_rate(
            t_imu,
            declared_hz.get("imu"),
            imu_where,
            imu_names.get("time", "time"),
            "IMU",
            declared_by=declared_by,
            steady=steady,
            row_label=imu_row_label,
        ),
        "commands": V.check_rate(
            t_cmd,
            declared_hz.get("commands"),
            cmd_where,
            cmd_names.get("time", "time"),
            "command",
            declared_by=declared_by,
            steady=steady,
            row_label=cmd_row_label,
            rows=cmd_rows,
        ),
    }
    overlap = min(t_imu[-1], t_cmd[-1]) - max(t_imu[0], t_cmd[0])
    shorter = min(t_imu[-1] - t_imu[0], t_cmd[-1] - t_cmd[0])
    if overlap < 0.5 * shorter:
        raise InputError(
            V.col_where(cmd_where, cmd_names.get("time", "time")),
            f"commands span {t_cmd[0]:.6g}..{t_cmd[-1]:.6g} s but the IMU spans "
            f"{t_imu[0]:.6g}..{t_imu[-1]:.6g} s: they overlap for less than half of "
            "the shorter stream (not the same run, or not the same clock/unit?)",
            "pair the right files and check the time units",
        )
    imu_checks = V.check_imu_units(imu, imu_where, imu_names, imu_row_label)
    V.check_command_units(commands, cmd_where, cmd_names, cmd_row_label, cmd_rows)

    offset = float(t_imu[0])
    imu = imu.assign(time=t_imu - offset).reset_index(drop=True)
    commands = commands.assign(time=t_cmd - offset).reset_index(drop=True)
    yaw = V.yaw_check(imu, commands, track)
    V.check_yaw_units(yaw, imu_where, imu_names.get("wz", "wz"))

    kind = "wheels" if "v_left" in commands else "body"
    full = {
        "dataset": None,
        "run_id": None,
        "terrain_class": None,
        **dict(meta or {}),
        "units": {c: UNITS[c] for c in [*imu.columns, *commands.columns]},
        "frame": FRAME,
        "commands_kind": kind,
        "track_m": track,
        "rates": {
            "declared_hz": declared_hz,
            "declared_by": declared_by if any(declared_hz.values()) else None,
            "imu": rates["imu"],
            "commands": rates["commands"],
        },
        "time_offset_s": offset,
        "time_zero": "first IMU sample",
        "checks": {"imu": imu_checks, "yaw": yaw},
        "reader": {"name": reader, "version": READER_VERSION, "simpick": __version__},
    }
    return RealLog(imu=imu, commands=commands, meta=jsonable(full))
