"""A DRIVE session's terrain and the quirks its files needed, in words for ``meta``: the gyro's sign, the
gyro's copy in ``icp_vel_yaw_i``, a folder name naming another terrain, reversed ICP windows, commands
arriving early.

It stands apart because what the reader did about each file's oddities is provenance, recorded for a
person to read; no measurement depends on these words.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from simpick.errors import InputError
from simpick.real.logs.drive_files import METADATA
from simpick.real.logs.drive_icp import Icp
from simpick.real.logs.drive_layout import Layout
from simpick.real.logs.drive_signals import REVERSED_SPEED

GYRO_COPY = "icp_vel_yaw"  # a copy of imu_yaw in DRIVE's files: checked, never used


def gyro_copy(frame: pd.DataFrame, raw: dict, n: int) -> bool | None:
    """Whether DRIVE's icp_vel_yaw_i columns equal imu_yaw_i (None: the file has none)."""
    if all(f"{GYRO_COPY}_{i}" in frame.columns for i in range(n)):
        return bool(np.array_equal(frame[[f"{GYRO_COPY}_{i}" for i in range(n)]].to_numpy(float), raw["imu_yaw"]))
    return None


def folder_terrain_agrees(name: str, terrain: str) -> bool:
    """Whether a session folder's name (DRIVE: <robot>_<traction>_<terrain>_<date>) names ``terrain``."""
    return f"_{terrain.lower()}_" in f"_{name.lower()}_"


def session_terrain(
    folder: Path, md: dict, terrain_class: str | None, declared_by: str
) -> tuple[str, object, bool | None]:
    """The session's terrain class (declared, else metadata.yaml's), metadata's own terrain, and whether
    the folder's name names it (None: metadata names none)."""
    meta_terrain = md.get("terrain")
    if terrain_class is None and not isinstance(meta_terrain, str):
        raise InputError(
            f"{folder / METADATA}: field 'metadata.terrain'",
            "missing",
            f"add it, or declare the session's terrain class ({declared_by})",
        )
    terrain = str(terrain_class if terrain_class is not None else meta_terrain).lower()
    agrees = folder_terrain_agrees(folder.name, str(meta_terrain)) if isinstance(meta_terrain, str) else None
    return terrain, meta_terrain, agrees


def session_quirks(
    folder: Path,
    gyro: dict,
    copy: bool | None,
    terrain: tuple[str, object, bool | None],
    terrain_class: str | None,
    declared_by: str,
    icp: Icp,
    early: np.ndarray,
    layout: Layout,
) -> list[str]:
    """What this session's files needed (the module's quirks), in words for ``meta["quirks"]``."""
    terrain_name, meta_terrain, agrees = terrain
    reversed_w = icp.reversed
    quirks = []
    if gyro["sign"] < 0:
        quirks.append(f"imu_yaw has the opposite sign to the ICP yaw rate here: negated ({gyro['basis']})")
    if copy:
        quirks.append(f"{GYRO_COPY}_i is a copy of imu_yaw_i (not an ICP yaw rate): not used")
    if agrees is False:
        quirks.append(f"the folder name {folder.name!r} does not name the metadata terrain {meta_terrain!r}")
    if terrain_class is not None and isinstance(meta_terrain, str) and terrain_name != meta_terrain.lower():
        quirks.append(f"terrain {terrain_name!r} declared by {declared_by} replaces metadata's {meta_terrain!r}")
    if reversed_w.any():
        quirks.append(
            f"the ICP moves against the wheels (opposite signs, both over {REVERSED_SPEED:g} m/s) in "
            f"{int(reversed_w.sum())} window(s) of {int((layout.windows(reversed_w).any(axis=1)).sum())} "
            "step(s): those windows' ICP speed not used"
        )
    if early.any():
        quirks.append(
            f"the next command arrives up to {int(early.max())} sample(s) before the step's end in "
            f"{int((early > 0).sum())} step(s)"
        )
    return quirks
