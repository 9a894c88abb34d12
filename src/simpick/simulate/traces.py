"""Parquet IMU traces: one file per engine x terrain x motion, self-describing.

The table holds the IMU at its output rate plus the robot's true pose, velocity and wheel
commands; the file's schema metadata (key ``simpick``) holds units and provenance:
engine and version, timestep, seed, config hash, wall and CPU time, step count, health.
Readers validate both, so a trace from another schema version or a half-written file is
refused with the file's name rather than half-understood.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from simpick.errors import InputError

if TYPE_CHECKING:
    import pandas as pd

SCHEMA = "simpick.trace/1"
METADATA_KEY = b"simpick"
UNITS = {
    "time": "s",
    "ax": "m/s^2",
    "ay": "m/s^2",
    "az": "m/s^2",
    "wx": "rad/s",
    "wy": "rad/s",
    "wz": "rad/s",
    "x": "m",
    "y": "m",
    "z": "m",
    "roll": "rad",
    "pitch": "rad",
    "yaw": "rad",
    "vx": "m/s",
    "vy": "m/s",
    "vz": "m/s",
    "v_forward": "m/s",
    "yaw_rate": "rad/s",
    "cmd_left": "rad/s",
    "cmd_right": "rad/s",
    "wheel_fl": "rad/s",
    "wheel_fr": "rad/s",
    "wheel_rl": "rad/s",
    "wheel_rr": "rad/s",
}
COLUMNS = list(UNITS)
FRAME = "body: x forward, y left, z up (REP-103); accelerometer = specific force (REP-145)"


def write_trace(frame: Mapping, metadata: dict, path: str | Path) -> None:
    """Write atomically: a killed job leaves a temp file, never a truncated trace.

    ``frame`` maps column names to arrays (a dict or a DataFrame): simulation jobs build a
    dict of arrays, so they need not import pandas.
    """
    missing = [c for c in COLUMNS if c not in frame]
    if missing:
        raise ValueError(f"trace is missing columns {missing}")
    meta = {"schema": SCHEMA, "units": UNITS, "frame": FRAME, **metadata}
    table = pa.Table.from_arrays([_float_array(frame[c]) for c in COLUMNS], names=COLUMNS)
    table = table.replace_schema_metadata(
        {**(table.schema.metadata or {}), METADATA_KEY: json.dumps(meta, sort_keys=True).encode()}
    )
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".partial")
    pq.write_table(table, tmp, compression="zstd")
    tmp.replace(path)


def _float_array(values) -> pa.Array:
    """A float64 Arrow array over the values' buffer. Not ``pa.array``: converting a NumPy array
    that way imports pandas (pyarrow 26 checks for pandas objects), 0.2-0.35 s of a simulation
    job that never uses it."""
    data = np.ascontiguousarray(values, dtype=np.float64)
    if data.ndim != 1:
        raise ValueError(f"a trace column must be one-dimensional, not of shape {data.shape}")
    return pa.Array.from_buffers(pa.float64(), len(data), [None, pa.py_buffer(data)])


def read_metadata(path: str | Path) -> dict:
    path = Path(path)
    try:
        raw = pq.read_schema(path).metadata or {}
    except (OSError, pa.ArrowInvalid) as exc:
        raise InputError(str(path), f"not a readable Parquet trace: {exc}", "delete it and rerun snakemake") from None
    if METADATA_KEY not in raw:
        raise InputError(str(path), "has no simpick metadata; it was not written by simpick")
    meta = json.loads(raw[METADATA_KEY])
    if meta.get("schema") != SCHEMA:
        raise InputError(
            str(path), f"trace schema {meta.get('schema')!r}, expected {SCHEMA!r}", "rerun snakemake to regenerate it"
        )
    return meta


def read_trace(path: str | Path) -> tuple[pd.DataFrame, dict]:
    meta = read_metadata(path)
    frame = pq.read_table(path).to_pandas()
    missing = [c for c in COLUMNS if c not in frame.columns]
    if missing:
        raise InputError(str(path), f"columns {missing} are missing")
    if len(frame) and not np.all(np.diff(frame["time"].to_numpy()) > 0):
        raise InputError(f"{path}: time", "time is not strictly increasing")
    return frame, meta
