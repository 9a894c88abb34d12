"""The canonical real log: what every reader returns and what the workflow stores.

``RealLog``
    imu       DataFrame: time (s, first sample at 0), ax ay az (m/s^2, specific force,
              +9.81 on z at rest), wx wy wz (rad/s); body frame x forward, y left, z up
              (REP-103 / REP-145).
    commands  DataFrame: time (s, same clock as the IMU; may start before 0 when the
              command stream starts first) and either v_left v_right (m/s, side/wheel
              surface speeds: "wheels") or v (m/s) w (rad/s) (body twist: "body").
              Optional extra columns: current_left current_right (A, motor currents).
    meta      dict (JSON-able): dataset, run_id, terrain_class, source_files, units,
              frame, rates (declared and measured), time_offset_s, reader, checks.

Canonical file: ONE Parquet file, one long table with a ``stream`` column ("imu" or
"commands") and the union of the columns; a column that does not belong to a stream is
null on its rows. The schema metadata key ``b"simpick"`` holds JSON:
``{"schema": "simpick.reallog/1", "units", "frame", "streams": {"imu": [...],
"commands": [...]}, "commands_kind", "meta"}``. One file keeps a log atomic: it is
written to ``<name>.partial`` and renamed, so a killed job never leaves half a log.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from simpick.errors import InputError
from simpick.real.logs import validate as V

SCHEMA = "simpick.reallog/1"
METADATA_KEY = b"simpick"
DEFAULT_TRACK = 0.555  # m, Husky A200 wheel separation (METHOD.md section 5)
IMU_COLUMNS = ["time", "ax", "ay", "az", "wx", "wy", "wz"]
WHEEL_COLUMNS = ["time", "v_left", "v_right"]
BODY_COLUMNS = ["time", "v", "w"]
EXTRA_COMMAND_COLUMNS = ["current_left", "current_right"]
UNITS = {
    "time": "s",
    "ax": "m/s^2",
    "ay": "m/s^2",
    "az": "m/s^2",
    "wx": "rad/s",
    "wy": "rad/s",
    "wz": "rad/s",
    "v_left": "m/s",
    "v_right": "m/s",
    "v": "m/s",
    "w": "rad/s",
    "current_left": "A",
    "current_right": "A",
}
FRAME = (
    "body: x forward, y left, z up (REP-103); accelerometer = specific force, +9.81 m/s^2 "
    "on z at rest (REP-145); v_left/v_right = side surface speeds, w = yaw rate about +z"
)


@dataclass
class RealLog:
    imu: pd.DataFrame
    commands: pd.DataFrame
    meta: dict = field(default_factory=dict)

    @property
    def command_kind(self) -> str:
        """ "wheels" (v_left, v_right) or "body" (v, w)."""
        return command_kind(self.commands)

    def wheel_commands(self, track: float = DEFAULT_TRACK) -> pd.DataFrame:
        return self.commands if self.command_kind == "wheels" else body_to_wheels(self.commands, track)

    def body_commands(self, track: float = DEFAULT_TRACK) -> pd.DataFrame:
        return self.commands if self.command_kind == "body" else wheels_to_body(self.commands, track)


def command_kind(commands: pd.DataFrame) -> str:
    cols = set(commands.columns)
    if {"v_left", "v_right"} <= cols:
        return "wheels"
    if {"v", "w"} <= cols:
        return "body"
    raise InputError("commands", f"columns {sorted(cols)} hold neither v_left/v_right nor v/w")


def wheels_to_body(commands: pd.DataFrame, track: float = DEFAULT_TRACK) -> pd.DataFrame:
    """(time, v_left, v_right) -> (time, v, w): v = (l + r) / 2, w = (r - l) / track.

    Other columns pass through. ``track`` is the kinematic track; a skid-steer robot's
    effective track is larger, so w is the *commanded* yaw rate, not the achieved one.
    """
    if track <= 0:
        raise InputError("track", f"track {track} m must be positive")
    out = commands.drop(columns=["v_left", "v_right"])
    out.insert(1, "v", 0.5 * (commands["v_left"] + commands["v_right"]))
    out.insert(2, "w", (commands["v_right"] - commands["v_left"]) / track)
    return out


def body_to_wheels(commands: pd.DataFrame, track: float = DEFAULT_TRACK) -> pd.DataFrame:
    """(time, v, w) -> (time, v_left, v_right): l = v - w track / 2, r = v + w track / 2."""
    if track <= 0:
        raise InputError("track", f"track {track} m must be positive")
    out = commands.drop(columns=["v", "w"])
    out.insert(1, "v_left", commands["v"] - 0.5 * track * commands["w"])
    out.insert(2, "v_right", commands["v"] + 0.5 * track * commands["w"])
    return out


def jsonable(value):
    """Meta as plain JSON types (tuples -> lists, numpy scalars -> Python, Path -> str)."""
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, Path):
        return str(value)
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return str(value)


def validate_log(log: RealLog, where: str, *, row_label: V.RowLabel = V.plain_row) -> dict:
    """Structure, finiteness, time order and unit plausibility of a canonical log."""
    if not isinstance(log.imu, pd.DataFrame) or not isinstance(log.commands, pd.DataFrame):
        raise InputError(where, "imu and commands must be pandas DataFrames")
    V.require_columns(log.imu, IMU_COLUMNS, f"{where} [imu]")
    kind = command_kind(log.commands)
    cmd_cols = (WHEEL_COLUMNS if kind == "wheels" else BODY_COLUMNS) + [
        c for c in EXTRA_COMMAND_COLUMNS if c in log.commands
    ]
    for stream, frame, cols in (("imu", log.imu, IMU_COLUMNS), ("commands", log.commands, cmd_cols)):
        for c in cols:
            values = V.numeric_column(frame[c], f"{where} [{stream}]", c, row_label)
            V.check_finite(values, f"{where} [{stream}]", c, row_label)
        V.check_time(frame["time"].to_numpy(dtype=float), f"{where} [{stream}]", "time", row_label)
    checks = V.check_imu_units(log.imu, f"{where} [imu]", {}, row_label)
    V.check_command_units(log.commands, f"{where} [commands]", {}, row_label)
    return checks


def write_canonical(log: RealLog, path: str | Path) -> Path:
    """Write the log as one Parquet file (see module doc), atomically."""
    path = Path(path)
    validate_log(log, f"{path} (log being written)")
    kind = log.command_kind
    cmd_cols = (WHEEL_COLUMNS if kind == "wheels" else BODY_COLUMNS) + [
        c for c in EXTRA_COMMAND_COLUMNS if c in log.commands
    ]
    imu = log.imu[IMU_COLUMNS].astype("float64")
    cmd = log.commands[cmd_cols].astype("float64")
    columns = IMU_COLUMNS + [c for c in cmd_cols if c not in IMU_COLUMNS]
    long = pd.concat([imu.assign(stream="imu"), cmd.assign(stream="commands")], ignore_index=True)
    long = long.reindex(columns=["stream", *columns])
    meta = {
        "schema": SCHEMA,
        "units": {c: UNITS[c] for c in columns},
        "frame": FRAME,
        "streams": {"imu": IMU_COLUMNS, "commands": cmd_cols},
        "commands_kind": kind,
        "meta": jsonable(log.meta),
    }
    fields = [pa.field("stream", pa.string(), nullable=False)] + [pa.field(c, pa.float64()) for c in columns]
    table = pa.Table.from_pandas(long, schema=pa.schema(fields), preserve_index=False)
    table = table.replace_schema_metadata({METADATA_KEY: json.dumps(meta, sort_keys=True).encode()})
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".partial")
    try:
        pq.write_table(table, tmp, compression="zstd")
        tmp.replace(path)
    finally:
        tmp.unlink(missing_ok=True)
    return path


def read_canonical_meta(path: str | Path) -> dict:
    """The log's meta alone (rates, source files ...), from the Parquet footer: no data read."""
    try:
        raw = (pq.read_schema(path).metadata or {}).get(METADATA_KEY)
        meta = json.loads(raw) if raw is not None else None
    except (OSError, pa.ArrowException, ValueError) as exc:
        raise InputError(str(path), f"not a readable canonical log: {exc}", "delete it and write it again") from None
    if not isinstance(meta, dict) or meta.get("schema") != SCHEMA:
        raise InputError(str(path), "has no simpick reallog metadata; it was not written by write_canonical")
    return meta.get("meta") or {}


def read_canonical(path: str | Path) -> RealLog:
    """Read and validate a file written by ``write_canonical``."""
    path = Path(path)
    if not path.exists():
        raise InputError(str(path), "canonical log not found", "run the reader that writes it")
    try:
        table = pq.read_table(path)
    except (OSError, pa.ArrowException) as exc:
        raise InputError(str(path), f"not a readable Parquet file: {exc}", "delete it and write it again") from None
    raw = (table.schema.metadata or {}).get(METADATA_KEY)
    if raw is None:
        raise InputError(str(path), "has no simpick metadata; it was not written by write_canonical")
    try:
        meta = json.loads(raw)
    except ValueError:
        raise InputError(str(path), "its simpick metadata is not valid JSON") from None
    if not isinstance(meta, dict) or meta.get("schema") != SCHEMA:
        raise InputError(
            str(path),
            f"schema {meta.get('schema') if isinstance(meta, dict) else None!r}, expected {SCHEMA!r}",
            "write it again with this simpick",
        )
    streams = meta.get("streams") or {}
    imu_cols, cmd_cols = streams.get("imu"), streams.get("commands")
    if imu_cols != IMU_COLUMNS or not isinstance(cmd_cols, list):
        raise InputError(f"{path}: metadata 'streams'", f"unexpected stream layout {streams!r}")
    for c, unit in (meta.get("units") or {}).items():
        if UNITS.get(c) != unit:
            raise InputError(f"{path}: column {c!r}", f"unit {unit!r}, expected {UNITS.get(c)!r}")
    frame = table.to_pandas()
    V.require_columns(frame, ["stream", *imu_cols, *cmd_cols], str(path))
    unknown = sorted(set(frame["stream"].astype(str)) - {"imu", "commands"})
    if unknown:
        raise InputError(f"{path}: column 'stream'", f"unknown stream(s) {unknown}")
    is_imu = (frame["stream"] == "imu").to_numpy()
    imu = frame.loc[is_imu, imu_cols].reset_index(drop=True).astype("float64")
    cmd = frame.loc[~is_imu, cmd_cols].reset_index(drop=True).astype("float64")
    log = RealLog(imu=imu, commands=cmd, meta=meta.get("meta") or {})
    validate_log(log, str(path))
    return log
