"""What planning checks of a DRIVE folder before any job runs (rules/drive.smk): each session's
``metadata.yaml`` (plain YAML, safe to read; no pickle is opened here) against the study.

A session is replayed on the study's robot, on the ground model of its terrain class. So a session that
another robot drove (DRIVE holds sessions of several robots, some tracked), or whose terrain has no ground
model in the config, is refused here, one line per session with the file, the field and the fix, rather
than replayed on the wrong robot or stopped half-way through the jobs.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from simpick.errors import InputError
from simpick.real.drive import unmodelled_terrain
from simpick.real.logs.drive_files import METADATA, read_metadata


def session_problems(
    folders: list[Path],
    declared: Mapping,
    classes: Mapping,
    robot_name: str,
    name: str = "drive",
) -> list[InputError]:
    """One problem per session folder that this study cannot replay: driven by a robot other than the
    study's (``metadata.robot`` against ``declared["robot"]``, else the study's URDF ``<robot name>``), on
    tracks, or on a terrain (``metadata.terrain``, or the config's per-session ``terrain_class``) that has
    no entry in ``classes`` (``real_data.classes``)."""
    expected = str(declared.get("robot") or robot_name)
    overrides = declared.get("sessions") or {}
    key = f"real_data.datasets.{name}"
    problems: list[InputError] = []
    for folder in folders:
        try:
            md = read_metadata(Path(folder))["metadata"]
        except InputError as exc:
            problems.append(exc)
            continue
        where = f"{Path(folder) / METADATA}"
        robot, traction = md.get("robot"), md.get("traction")
        if isinstance(robot, str) and robot.strip().lower() != expected.strip().lower():
            problems.append(
                InputError(
                    f"{where}: field 'metadata.robot'",
                    f"is {robot!r}, but this study's robot is {expected!r} (robot.urdf's <robot name>, or {key}.robot)",
                    f"replay it in a study of that robot, name a folder without this session, or set "
                    f"{key}.robot: {robot} if the study's robot is the one DRIVE calls {robot!r}",
                )
            )
        elif isinstance(traction, str) and traction.strip().lower() not in ("wheels", "wheel"):
            problems.append(
                InputError(
                    f"{where}: field 'metadata.traction'",
                    f"is {traction!r}: simpick replays wheeled robots",
                    "name a folder without this session",
                )
            )
        declared_terrain = (overrides.get(Path(folder).name) or {}).get("terrain_class")
        terrain = declared_terrain or md.get("terrain")
        if not isinstance(terrain, str):
            problems.append(
                InputError(
                    f"{where}: field 'metadata.terrain'",
                    "missing",
                    f"add it, or declare the session's terrain_class under {key}.sessions.{Path(folder).name}",
                )
            )
        elif terrain.lower() not in classes:
            source = f"declared by {key}.sessions" if declared_terrain else "its metadata"
            problems.append(
                unmodelled_terrain(
                    f"{where}: field 'metadata.terrain'", terrain.lower(), source, Path(folder).name, name
                )
            )
    return problems
