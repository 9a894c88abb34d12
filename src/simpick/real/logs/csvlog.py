"""A generic CSV log read through a column and unit mapping (from the config).

Mapping (every key but the IMU, time and one command pair is optional)::

    time:    {column: t, unit: s | ms | us | ns}
    ax, ay, az:  {column: acc_x, unit: m/s^2 | g}
    wx, wy, wz:  {column: gyro_x, unit: rad/s | deg/s}
    v_left, v_right:  {column: ..., unit: m/s | cm/s | mm/s | km/h}    # side speeds, or
    v:  {column: ..., unit: m/s | cm/s | mm/s | km/h}
    w:  {column: ..., unit: rad/s | deg/s}                            # body twist
    commands_time: {column: ..., unit: ...}   # time column of a separate commands file
    frame:   {z: up | down}
    rates:   {imu: 100, commands: 10}         # declared Hz, checked within 20 %
    meta:    {dataset: ..., run_id: ..., terrain_class: ...}

A value may also be a bare column name (canonical unit). Units default to the canonical
ones. ``frame: {z: down}`` means the IMU (and the body yaw rate w) is in an x forward,
y right, z down frame; the reader turns it into x forward, y left, z up by a 180 degree
rotation about x: y -> -y, z -> -z for both the accelerometer and the gyro (a proper
rotation acts the same on vectors and angular rates), and w -> -w. v_left/v_right are
named by side, so no frame applies to them.

One file: every row must hold the IMU; command cells may be empty (or NaN) on rows where
no command was logged - the commands are the rows where they are present (both columns
of the pair, or neither: a row with one of them is an error). Two files:
``read_csv_log(imu_csv, mapping, commands_path=cmd_csv)``; both share one clock.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.errors import InputError
from simpick.real.logs import validate as V
from simpick.real.logs.assemble import finish, source_columns
from simpick.real.logs.canonical import DEFAULT_TRACK, RealLog
from simpick.real.logs.csvfile import check_file, file_info, load_csv

G0 = 9.80665
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}
ACCEL_UNITS = {"m/s^2": 1.0, "m/s2": 1.0, "g": G0}
GYRO_UNITS = {"rad/s": 1.0, "deg/s": np.pi / 180.0}
SPEED_UNITS = {"m/s": 1.0, "cm/s": 1e-2, "mm/s": 1e-3, "km/h": 1 / 3.6}
UNIT_TABLE = {
    "time": TIME_UNITS,
    "commands_time": TIME_UNITS,
    "ax": ACCEL_UNITS,
    "ay": ACCEL_UNITS,
    "az": ACCEL_UNITS,
    "wx": GYRO_UNITS,
    "wy": GYRO_UNITS,
    "wz": GYRO_UNITS,
    "v_left": SPEED_UNITS,
    "v_right": SPEED_UNITS,
    "v": SPEED_UNITS,
    "w": GYRO_UNITS,
}
IMU_KEYS = ["ax", "ay", "az", "wx", "wy", "wz"]
OTHER_KEYS = {"frame", "rates", "meta"}


def _parse_mapping(mapping, where: str) -> tuple[dict[str, tuple[str, str]], dict]:
    """{key: (column, unit)} and the options; every mistake names the mapping key."""
    if not isinstance(mapping, Mapping):
        raise InputError(where, f"the mapping must be a dict, got {type(mapping).__name__}")
    unknown = sorted(set(map(str, mapping)) - set(UNIT_TABLE) - OTHER_KEYS)
    if unknown:
        raise InputError(
            f"{where}: mapping key {unknown[0]!r}", "unknown key", f"use only {sorted(UNIT_TABLE) + sorted(OTHER_KEYS)}"
        )
    spec: dict[str, tuple[str, str]] = {}
    for key, table in UNIT_TABLE.items():
        if key not in mapping:
            continue
        value = mapping[key]
        if isinstance(value, str):
            value = {"column": value}
        if not isinstance(value, Mapping) or not isinstance(value.get("column"), str):
            raise InputError(
                f"{where}: mapping key {key!r}", f"must be a column name or {{column: ..., unit: ...}}, got {value!r}"
            )
        extra = sorted(set(value) - {"column", "unit"})
        if extra:
            raise InputError(f"{where}: mapping key {key!r}", f"unknown field {extra[0]!r}", "use column and unit")
        unit = value.get("unit", next(iter(table)))
        if unit not in table:
            raise InputError(f"{where}: mapping key {key!r}", f"unknown unit {unit!r}", f"use one of {list(table)}")
        spec[key] = (value["column"], unit)
    missing = [k for k in ["time", *IMU_KEYS] if k not in spec]
    if missing:
        raise InputError(
            f"{where}: mapping key {missing[0]!r}", "is required but missing", "map every IMU axis and the time column"
        )
    wheels, body = {"v_left", "v_right"} & set(spec), {"v", "w"} & set(spec)
    if wheels and body:
        raise InputError(
            f"{where}: mapping keys {sorted(wheels | body)}",
            "give side speeds (v_left, v_right) or body twist (v, w), not both",
        )
    pair = ["v_left", "v_right"] if wheels or not body else ["v", "w"]
    absent = [k for k in pair if k not in spec]
    if absent:
        raise InputError(
            f"{where}: mapping key {absent[0]!r}", "is required but missing", "map v_left and v_right, or v and w"
        )

    frame = mapping.get("frame", {"z": "up"})
    if not isinstance(frame, Mapping) or set(frame) - {"z"} or frame.get("z", "up") not in ("up", "down"):
        raise InputError(f"{where}: mapping key 'frame'", f"must be {{z: up}} or {{z: down}}, got {frame!r}")
    rates = mapping.get("rates", {})
    if (
        not isinstance(rates, Mapping)
        or set(rates) - {"imu", "commands"}
        or not all(isinstance(v, (int, float)) and not isinstance(v, bool) and v > 0 for v in rates.values())
    ):
        raise InputError(
            f"{where}: mapping key 'rates'", f"must be {{imu: Hz, commands: Hz}} with positive numbers, got {rates!r}"
        )
    meta = mapping.get("meta", {})
    if not isinstance(meta, Mapping):
        raise InputError(f"{where}: mapping key 'meta'", f"must be a dict, got {meta!r}")
    return spec, {"z": frame.get("z", "up"), "rates": dict(rates), "meta": dict(meta), "pair": pair}


def _check_columns(frame: pd.DataFrame, spec: dict, keys: list[str], path: Path) -> None:
    for key in keys:
        column = spec[key][0]
        if column not in frame.columns:
            present = ", ".join(repr(str(c)) for c in frame.columns)
            raise InputError(
                f"{path}: column {column!r} (mapping key {key!r})",
                f"not in the file; columns present: {present}",
                "fix the mapping or the file header",
            )


def read_csv_log(
    path: str | Path, mapping: Mapping, *, commands_path: str | Path | None = None, track: float = DEFAULT_TRACK
) -> RealLog:
    """A validated RealLog from one CSV (or an IMU CSV plus a commands CSV)."""
    path = check_file(path, "CSV log")
    spec, opts = _parse_mapping(mapping, str(path))
    pair = opts["pair"]
    names = {k: V.Label(f"column {c!r} (mapping key {k!r})") for k, (c, _) in spec.items()}
    imu_map = {"time": spec["time"][0], **{k: spec[k][0] for k in IMU_KEYS}}

    frame = load_csv(path)
    _check_columns(frame, spec, ["time", *IMU_KEYS], path)
    imu = source_columns(frame, imu_map, str(path), V.csv_row, labels=names)
    sources = {"imu": file_info(path)}

    if commands_path is None:
        _check_columns(frame, spec, pair, path)
        cmd, rows = _sparse_commands(frame, spec, pair, path, names)
        cmd.insert(0, "time", imu["time"].to_numpy()[rows])
        cmd_where, cmd_time_unit = str(path), spec["time"][1]
    else:
        cpath = check_file(commands_path, "commands CSV")
        cframe = load_csv(cpath)
        tkey = "commands_time" if "commands_time" in spec else "time"
        _check_columns(cframe, spec, [tkey, *pair], cpath)
        cmd = source_columns(
            cframe,
            {"time": spec[tkey][0], **{k: spec[k][0] for k in pair}},
            str(cpath),
            V.csv_row,
            labels={**names, "time": names[tkey]},
        )
        rows = np.arange(len(cmd))
        cmd_where, cmd_time_unit = str(cpath), spec[tkey][1]
        sources["commands"] = file_info(cpath)
    time_unit = spec["time"][1]

    # to seconds; ``finish`` puts both streams on the IMU's clock, zero at its first sample
    # (an ns epoch in float64 keeps ~0.25 us resolution: ample for IMU rates)
    imu["time"] = imu["time"] * TIME_UNITS[time_unit]
    cmd["time"] = cmd["time"] * TIME_UNITS[cmd_time_unit]

    for key in IMU_KEYS:
        imu[key] = imu[key] * UNIT_TABLE[key][spec[key][1]]
    for key in pair:
        cmd[key] = cmd[key] * UNIT_TABLE[key][spec[key][1]]
    if opts["z"] == "down":
        for key in ("ay", "az", "wy", "wz"):
            imu[key] = -imu[key]
        if "w" in cmd:
            cmd["w"] = -cmd["w"]

    meta = {
        **opts["meta"],
        "source_files": sources,
        "source_mapping": {k: {"column": c, "unit": u} for k, (c, u) in spec.items()},
        "source_frame": {"z": opts["z"]},
        "frame_conversion": (
            "none" if opts["z"] == "up" else "180 deg rotation about x: ay, az, wy, wz (and w) negated"
        ),
    }
    meta.setdefault("dataset", None)
    return finish(
        imu,
        cmd,
        imu_where=str(path),
        cmd_where=cmd_where,
        imu_names=names,
        cmd_names=names,
        imu_row_label=V.csv_row,
        cmd_row_label=V.csv_row,
        cmd_rows=rows,
        declared_hz=opts["rates"],
        track=track,
        meta=meta,
        reader="simpick.real.logs.csvlog",
    )


def _sparse_commands(
    frame: pd.DataFrame, spec: dict, pair: list[str], path: Path, names: dict
) -> tuple[pd.DataFrame, np.ndarray]:
    """Command rows of a combined file: those where the command cells are present."""
    values = {}
    for key in pair:
        col = spec[key][0]
        v = V.numeric_column(frame[col], str(path), names[key], V.csv_row)
        inf = np.flatnonzero(np.isinf(v))
        if len(inf):
            raise InputError(
                f"{path}: {names[key]}", f"infinite value at {V.csv_row(int(inf[0]))}", "remove or repair the row"
            )
        values[key] = v
    present = [~np.isnan(values[k]) for k in pair]
    half = np.flatnonzero(present[0] != present[1])
    if len(half):
        i = int(half[0])
        gap = pair[1] if present[0][i] else pair[0]
        raise InputError(
            f"{path}: {names[gap]}",
            f"empty at {V.csv_row(i)} while {spec[pair[0] if gap == pair[1] else pair[1]][0]!r} "
            "is set: a command row needs both values",
            "fill both or neither",
        )
    rows = np.flatnonzero(present[0])
    if len(rows) == 0:
        raise InputError(
            f"{path}: {names[pair[0]]}", "no row holds a command", "map the command columns, or give a commands file"
        )
    return pd.DataFrame({k: values[k][rows] for k in pair}), rows
