"""The DRIVE source: the steps of a DRIVE folder's sessions (``--config drive_dir=PATH``), each a unit
replayed from its warm-up by its measured wheel speeds and compared with the real robot over its steady
part, paired by its command (every engine replays the same step).

Planning reads a DRIVE folder's listing and each session's ``metadata.yaml`` only (YAML, safe to read):
DRIVE's data are pickles, which can run code when read, so they are read by the jobs alone, from the
folder the user named (rules/drive.smk's import step, :func:`simpick.real.drive.tables_job`, which writes
the canonical step tables the rest reads). What this module says at planning time:

- which folders are sessions (:func:`folders`), naming each sub-folder it leaves out and why;
- which sessions this study cannot replay (:func:`problems`): another robot's, a tracked one, or one on a
  terrain without a ground model, one line each with the file, the field and the fix;
- which models replay the steps (:func:`models`);
- a case's inputs and parameters and the comparison's (the :class:`~simpick.sources.base.Source` names):
  a job replays one session's chosen steps (a unit of cases, as a segments job batches its segments).

The steps themselves are known once the import step has run (a checkpoint): :func:`cases` reads its
case table.

Like the other kinds' (:mod:`simpick.sources.base`), this module's planning functions read the typed study
(``study``, :class:`simpick.config.Study`, by attribute): rules/drive.smk, simpick.plan.answer and
simpick.plan.jobs pass it.
"""

from __future__ import annotations

import csv
import sys
from collections.abc import Mapping
from pathlib import Path

from simpick.errors import InputError
from simpick.real.datasets import DatasetProblems
from simpick.real.drive import SIMILAR, unmodelled_terrain
from simpick.real.logs.drive_files import METADATA, PICKLE, find_sessions, read_metadata, unrecognised
from simpick.sources.base import canonical, simulation_params

KIND = "drive"
DRIVEN = "steps"  # simpick.simulate.jobs.PREPARE / simpick.compare.kinds.BY_KIND: a step unit's replay
GROUP = "terrain_class"
MEM_MB = 1500  # a session's samples and its steps' traces in memory
TABLES = ("sessions", "steps", "turning", "bins", "cases")  # what the import step writes (real.drive), as CSV
WHEELS = "wheels.parquet"  # and the wheels table the steps are driven by (simpick.real.steps.WHEEL_COLUMNS)


def root(study) -> str:
    """Where the source's tables lie: ``results/drive/<drive_dataset>``."""
    return f"results/drive/{study.drive_dataset}"


def declared(study) -> dict:
    """What the jobs read of the dataset's declaration (``real_data.datasets.<drive_dataset>``): all but its
    robot, which is planning's alone (:func:`problems`)."""
    found = study.real_data.datasets[study.drive_dataset]  # keyed by dataset name (data)
    return canonical(found.model_dump(mode="json", exclude={"robot"}))


def session_files(folder: Path) -> list[str]:
    """The files of one session the import step reads (its metadata and its pickle); no other job reads
    them."""
    return [str(folder / METADATA), str(folder / PICKLE)]


# --- planning: which folders, which sessions, which models ---


def folders(folder) -> list[Path]:
    """The session folders under ``folder`` (a directory listing: no pickle is read at planning time); a
    sub-folder that is no session is named on stderr with the reason (never left out in silence). A
    problem (no session, a half session) is one ``simpick:`` line each and exit 1: no job runs."""
    try:
        found = find_sessions(folder)
    except DatasetProblems as exc:
        found, problems = None, exc.problems
    except InputError as exc:
        found, problems = None, [exc]
    if found is None:
        for problem in problems:
            print(f"simpick: {problem}", file=sys.stderr)
        sys.exit(1)
    for path, reason in unrecognised(folder):
        print(f"simpick: {path}: left out of the DRIVE dataset: {reason}", file=sys.stderr)
    return found


def problems(
    sessions: list[Path],
    declared,
    classes: Mapping,
    robot_name: str,
    name: str = "drive",
) -> list[InputError]:
    """One problem per session folder that this study cannot replay: driven by a robot other than the
    study's (``metadata.robot`` against ``declared.robot``, else the study's URDF ``<robot name>``), on
    tracks, or on a terrain (``metadata.terrain``, or the config's per-session ``terrain_class``) that has
    no entry in ``classes`` (``real_data.classes``). ``declared``: the dataset's declaration
    (:class:`simpick.config.real.DeclaredDataset`), None where the study declares none."""
    expected = str((declared.robot if declared else None) or robot_name)
    overrides = declared.sessions if declared else {}  # keyed by session folder name (data)
    key = f"real_data.datasets.{name}"
    found: list[InputError] = []
    for folder in sessions:
        try:
            md = read_metadata(Path(folder))["metadata"]
        except InputError as exc:
            found.append(exc)
            continue
        where = f"{Path(folder) / METADATA}"
        robot, traction = md.get("robot"), md.get("traction")
        if isinstance(robot, str) and robot.strip().lower() != expected.strip().lower():
            found.append(
                InputError(
                    f"{where}: field 'metadata.robot'",
                    f"is {robot!r}, but this study's robot is {expected!r} (robot.urdf's <robot name>, or {key}.robot)",
                    f"replay it in a study of that robot, name a folder without this session, or set "
                    f"{key}.robot: {robot} if the study's robot is the one DRIVE calls {robot!r}",
                )
            )
        elif isinstance(traction, str) and traction.strip().lower() not in ("wheels", "wheel"):
            found.append(
                InputError(
                    f"{where}: field 'metadata.traction'",
                    f"is {traction!r}: simpick replays wheeled robots",
                    "name a folder without this session",
                )
            )
        override = overrides.get(Path(folder).name)
        declared_terrain = override.terrain_class if override else None
        terrain = declared_terrain or md.get("terrain")
        if not isinstance(terrain, str):
            found.append(
                InputError(
                    f"{where}: field 'metadata.terrain'",
                    "missing",
                    f"add it, or declare the session's terrain_class under {key}.sessions.{Path(folder).name}",
                )
            )
        elif terrain.lower() not in classes:
            source = f"declared by {key}.sessions" if declared_terrain else "its metadata"
            found.append(
                unmodelled_terrain(
                    f"{where}: field 'metadata.terrain'", terrain.lower(), source, Path(folder).name, name
                )
            )
    return found


def models(chosen: list[str] | None, configured: list[str], unavailable: dict | None = None) -> list[str]:
    """The models that replay the steps: ``drive_replay.models`` (None: every configured one), in the
    configured order. A model that is not configured is one clear error; one configured but not installed
    here is left out (the study says so at planning time)."""
    unavailable = unavailable or {}
    if chosen is None:
        return list(configured)
    unknown = [m for m in chosen if m not in configured and m not in unavailable]
    if unknown:
        raise InputError(
            "drive_replay.models in the config",
            f"names {unknown}, which the study does not configure",
            f"choose among {configured} (engines and baselines), or null for all",
        )
    return [m for m in configured if m in chosen]


def cases(path: str) -> list[tuple[str, str]]:
    """(session, case) of every step of the import step's case table (``cases.csv``): a job replays one
    session's chosen steps."""
    with open(path, newline="") as handle:
        return [(row["session"], row["case"]) for row in csv.DictReader(handle)]


# --- planning: what a job reads and depends on (the Source names) ---


def case_inputs(study, source: str, spec: dict, group: str, names: list[str]) -> dict:
    """A session's replay job: the import step's case and wheels tables, and the robot (never the session's
    own files: the import step alone reads them)."""
    return {"cases": f"{root(study)}/cases.csv", "wheels": f"{root(study)}/{WHEELS}", "urdf": study.robot.urdf}


def case_params(
    study, source: str, spec: dict, engine: str, engine_settings: dict, group: str, names: list[str]
) -> dict:
    """What a session's replay on ``engine`` depends on: the engine's, every terrain class's ground (the
    session's is in the case table), the replay's settings and the session (``group``): the fields of
    :class:`simpick.simulate.steps.SessionReplayParams`."""
    classes = {c: ground.model_dump(mode="json") for c, ground in study.real_data.classes.items()}
    replay = study.drive_replay.model_dump(mode="json")
    return canonical(
        simulation_params(study, engine, engine_settings) | {"classes": classes, "replay": replay, "session": group}
    )


def compare_inputs(study, source: str, spec: dict, cases: list[tuple[str, str]]) -> dict:
    return {"cases": f"{root(study)}/cases.csv", "steps": f"{root(study)}/steps.csv"}


def answer_tables(study) -> dict:
    """The comparison's tables the first page's answer reads where it rests on these steps (rule answer,
    its figure, the decision tree: simpick.plan's answer_tables), in the verdict's form: rule drive_compare
    writes them beside its outcomes."""
    return {t: f"{root(study)}/{t}.csv" for t in ("outcomes", "mechanics", "metrics", "table", "per_test")}


def answer_basis(study, dataset: str, robot: str) -> dict:
    """What the answer's sentence says it rests on: the dataset's label, its unit of pairing
    (``drive_replay.unit``: a step, or its session) and how the units were compared."""
    unit = study.drive_replay.unit
    return {
        "dataset": dataset,
        "unit": unit,
        "noun": f"{dataset} {unit}s",
        "title": f"the {robot}'s own sessions, each step replayed in every engine from its measured "
        f"wheel speeds; every engine against the best, paired by {unit}",
        "others": [],
    }


def compare_settings(study) -> dict:
    """The comparison's settings, less the engines it judges (the plan's)."""
    return canonical(
        {
            "verdict": study.verdict.model_dump(mode="json"),
            "statistics": study.statistics.model_dump(mode="json"),
            "unit": study.drive_replay.unit,
            "tolerance": SIMILAR,
            "seed": study.seed,
        }
    )
