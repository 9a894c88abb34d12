"""Dataset folders: what the full replay reads, checked before any job starts.

A dataset folder holds one sub-folder per terrain class, each with ``imu_<run>.csv`` /
``pro_<run>.csv`` pairs (the BorealTC layout), whatever the run numbering (``01``, ``1``,
``7``, ``12`` ...) and whatever the class names (``ASPHALT``, ``CONCRETE``, ``Dirt_Road``).
A class's config key is its folder name in lower case (``real_data.classes``).

Everything wrong with a folder that can be seen without reading the files is found here,
at DAG-build time, and reported as one line per problem (an :class:`InputError` naming the
folder or file and the fix); problems inside the files are the readers' (job-time) business.
This module reads directory listings only, so building the DAG stays cheap.
"""

from __future__ import annotations

import re
import sys
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import yaml

from simpick.errors import InputError

_FILE = re.compile(r"^(imu|pro)_(.*)\.csv$")
RUN_ID = re.compile(r"^[A-Za-z0-9_-]+$", re.ASCII)
CLASS_FOLDER = re.compile(r"^[A-Za-z0-9_]+$", re.ASCII)
NAME = re.compile(r"^[A-Za-z0-9_.-]+$", re.ASCII)
# source names of the case tables (simpick.plan): results/traces/<source>/ and results/metrics/<source>/
RESERVED_NAMES = {
    "own": "results/real/own holds the results of own_logs",
    "lab": "results/traces/lab and results/metrics/lab hold the lab study's",
    "segments": "results/traces/segments and results/metrics/segments hold the committed segments'",
}
LAYOUT = "one sub-folder per terrain class holding imu_<run>.csv / pro_<run>.csv pairs"


@dataclass(frozen=True)
class Run:
    terrain_class: str  # config key: the folder name in lower case
    run: str  # as in the file names: "01", "1", "12"
    folder: str  # the class folder's name on disk
    imu: Path
    pro: Path


@dataclass(frozen=True)
class Dataset:
    name: str
    folder: Path
    runs: tuple[Run, ...]

    @property
    def classes(self) -> list[str]:
        return list(dict.fromkeys(r.terrain_class for r in self.runs))

    def run(self, terrain_class: str, run: str) -> Run:
        for r in self.runs:
            if r.terrain_class == terrain_class and r.run == run:
                return r
        raise InputError(str(self.folder), f"has no run {run!r} of terrain class {terrain_class!r}")


class DatasetProblems(InputError):
    """Several problems with one folder, each an InputError (printed one per line)."""

    def __init__(self, problems: list[InputError]):
        self.problems = problems
        super().__init__(problems[0].where, problems[0].problem, problems[0].fix)
        self.args = ("\n".join(str(p) for p in problems),)


def run_key(run: str) -> tuple:
    """Natural order: 1, 2, 7, 12 (and 01 before 02); ties broken by the text."""
    return tuple((0, int(part), part) if part.isdigit() else (1, 0, part) for part in re.split(r"(\d+)", run) if part)


def _visible_dirs(folder: Path) -> list[Path]:
    return sorted(p for p in folder.iterdir() if p.is_dir() and not p.name.startswith((".", "_")))


def scan(folder: str | Path) -> tuple[list[Run], list[InputError]]:
    """Every run of a dataset folder, and every problem found (empty when none).

    A folder that is not a dataset at all (missing, empty, a single class folder, no
    sub-folder with runs) is one problem and no runs.
    """
    folder = Path(folder)
    if not folder.exists():
        return [], [InputError(str(folder), "dataset folder not found", "check the path given as borealtc_dir")]
    if not folder.is_dir():
        return [], [InputError(str(folder), "is a file, not a dataset folder", f"pass the folder with {LAYOUT}")]
    own = [f.name for f in folder.iterdir() if f.is_file() and _FILE.match(f.name)]
    subs = _visible_dirs(folder)
    if own and not any(_FILE.match(f.name) for s in subs for f in s.iterdir()):
        return [], [
            InputError(
                str(folder),
                f"holds {len(own)} imu_/pro_ file(s) itself: it looks like one terrain-class folder, not a dataset",
                f"pass its parent folder {folder.resolve().parent} (the dataset has {LAYOUT})",
            )
        ]
    if not subs:
        return [], [
            InputError(
                str(folder),
                "is empty: no terrain-class sub-folders",
                f"a dataset folder has {LAYOUT}, e.g. {folder}/ASPHALT/imu_1.csv + pro_1.csv",
            )
        ]
    listing = {s: sorted(f for f in s.iterdir() if f.is_file()) for s in subs}
    if not any(_FILE.match(f.name) for files in listing.values() for f in files):
        return [], [
            InputError(
                str(folder),
                f"is not a dataset folder: none of its {len(subs)} sub-folder(s) "
                "holds imu_<run>.csv / pro_<run>.csv files",
                f"pass the folder with {LAYOUT}, e.g. {folder}/ASPHALT/imu_1.csv + pro_1.csv",
            )
        ]

    runs: list[Run] = []
    problems: list[InputError] = []
    seen: dict[str, Path] = {}
    for sub, files in listing.items():
        cls = sub.name.lower()
        if not CLASS_FOLDER.match(sub.name):
            suggestion = re.sub(r"[^A-Za-z0-9_]+", "_", sub.name).strip("_").upper() or "CLASS"
            problems.append(
                InputError(
                    str(sub),
                    f"terrain-class folder name {sub.name!r} may hold only letters, digits and '_'",
                    f"rename the folder, e.g. to {suggestion}",
                )
            )
            continue
        if cls in seen:
            problems.append(
                InputError(
                    str(sub),
                    f"terrain class {cls!r} appears twice (also {seen[cls]})",
                    "merge the two folders into one",
                )
            )
            continue
        seen[cls] = sub
        found: dict[str, dict[str, Path]] = {}
        for f in files:
            m = _FILE.match(f.name)
            if not m:
                continue  # README, notes, other sensors
            kind, run = m.groups()
            if not RUN_ID.match(run):
                problems.append(
                    InputError(
                        str(f),
                        f"run id {run!r} may hold only letters, digits, '_' and '-'",
                        f"rename the file, e.g. to {kind}_1.csv (and its partner)",
                    )
                )
                continue
            found.setdefault(run, {})[kind] = f
        if not found:
            problems.append(
                InputError(
                    str(sub),
                    "terrain-class folder holds no imu_<run>.csv / pro_<run>.csv pair",
                    "add its runs or remove the folder",
                )
            )
            continue
        for run in sorted(found, key=run_key):
            pair = found[run]
            missing = "pro" if "imu" in pair and "pro" not in pair else "imu" if "imu" not in pair else None
            if missing:
                have = pair["imu" if missing == "pro" else "pro"]
                problems.append(
                    InputError(
                        str(have),
                        f"has no partner {missing}_{run}.csv in {sub}",
                        "restore the missing file or remove this one",
                    )
                )
                continue
            runs.append(Run(cls, run, sub.name, pair["imu"], pair["pro"]))
    return runs, problems


def find_runs(folder: str | Path) -> list[Run]:
    """The runs of a dataset folder; the problems, if any, raised together."""
    runs, problems = scan(folder)
    if problems:
        raise DatasetProblems(problems)
    return runs


def dataset_name(folder: str | Path, given: str | None = None) -> str:
    """``given`` (``--config real_dataset=NAME``), else the folder's own name in lower case."""
    if given:
        name = str(given)
        if not NAME.match(name):
            raise InputError(
                f"real_dataset {name!r}",
                "may hold only letters, digits, '_', '.' and '-'",
                "pass e.g. --config real_dataset=yard_2024",
            )
    else:
        name = re.sub(r"[^a-z0-9_.-]+", "_", Path(folder).resolve().name.lower()).strip("._-") or "dataset"
    if name in RESERVED_NAMES:
        raise InputError(
            f"dataset name {name!r} (from {'real_dataset' if given else folder})",
            f"is reserved: {RESERVED_NAMES[name]}",
            "pass another name: --config real_dataset=NAME",
        )
    return name


def unknown_classes(runs: Iterable[Run], classes: Mapping) -> list[InputError]:
    """One problem per terrain class found in the folder with no ground model in the config."""
    problems, done = [], set()
    for r in runs:
        if r.terrain_class in classes or r.terrain_class in done:
            continue
        done.add(r.terrain_class)
        example = f'real_data: {{classes: {{{r.terrain_class}: {{friction: 0.6, source: "where 0.6 comes from"}}}}}}'
        problems.append(
            InputError(
                str(r.imu.parent),
                f"terrain class {r.terrain_class!r} has no ground model",
                f"add it under real_data.classes in config.yaml or in a file passed with --configfile, e.g. {example}",
            )
        )
    return problems


def previous_folder(manifest: str | Path) -> str | None:
    """The folder whose results a dataset's results folder already holds (its manifest), if any."""
    try:
        data = yaml.safe_load(Path(manifest).read_text())
    except (OSError, yaml.YAMLError):
        return None
    return str(data.get("folder")) if isinstance(data, dict) and data.get("folder") else None


def open_dataset(
    folder: str | Path, *, classes: Mapping, name: str | None = None, results: str | Path = "results/real"
) -> Dataset:
    """The dataset behind ``borealtc_dir``: every run, every class known to the config, and a
    name whose results folder holds no other folder's results. Raises :class:`DatasetProblems`."""
    folder = Path(folder)
    runs, problems = scan(folder)
    try:
        dataset = dataset_name(folder, name)
    except InputError as exc:
        problems.insert(0, exc)
        dataset = None
    problems += unknown_classes(runs, classes)
    if dataset is not None:
        manifest = Path(results) / dataset / "dataset.yaml"
        before = previous_folder(manifest)
        if before is not None and Path(before) != folder.resolve():
            problems.insert(
                0,
                InputError(
                    f"{Path(results) / dataset}",
                    f"holds the results of dataset folder {before}, not of {folder.resolve()}",
                    "pass --config real_dataset=OTHER_NAME, or delete that results folder",
                ),
            )
    if problems:
        raise DatasetProblems(problems)
    return Dataset(dataset, folder.resolve(), tuple(runs))


def open_dataset_or_exit(folder: str | Path, **kwargs) -> Dataset:
    """For the Snakefile: the dataset, or one ``simpick:`` line per problem and exit 1 (no job runs)."""
    try:
        return open_dataset(folder, **kwargs)
    except DatasetProblems as exc:
        for problem in exc.problems:
            print(f"simpick: {problem}", file=sys.stderr)
        sys.exit(1)
