"""The segments source: constant-command segments of real runs (the committed table
``real_data.segments``, or the one derived from a dataset folder), each segment's command driven on
its terrain class's flat ground and compared with the real window's statistics (simpick.compare.real).
The speed-accuracy sweep (simpick.studies.sweep) runs this source's simulate, compare and summarise steps at
each of its timesteps."""

from __future__ import annotations

import csv

from simpick.sources.base import canonical, simulation_params, unit_params

KIND = DRIVEN = "segments"
GROUP = "terrain_class"
MEM_MB = 400


# --- planning (``study``: the typed study, simpick.sources.base) ---


def by_class(path: str, classes: dict | list) -> dict[str, list[str]]:
    """terrain class -> segment ids, from a segment table (plain csv: fast to parse). Raises
    ValueError on a class with no entry under real_data.classes, or on an id given twice (a job finds a
    segment by its id: simpick.simulate.real.prepare_segment)."""
    found: dict[str, list[str]] = {}
    seen: set[str] = set()
    with open(path, newline="") as handle:
        for row in csv.DictReader(handle):
            if row["segment"] in seen:
                raise ValueError(f"{path}: segment id {row['segment']!r} is given more than once")
            seen.add(row["segment"])
            found.setdefault(row["terrain_class"], []).append(row["segment"])
    unknown = sorted(set(found) - set(classes))
    if unknown:
        raise ValueError(f"{path}: terrain classes {unknown} have no entry under real_data.classes in the config")
    return found


def cases(path: str, classes: dict | list) -> list[tuple[str, str]]:
    """(terrain class, segment id) of every row of a segment table."""
    return [(c, s) for c, ids in by_class(path, classes).items() for s in ids]


def case_inputs(study, source: str, spec: dict, group: str, names: list[str]) -> dict:
    return {"urdf": study.robot.urdf, "segments": spec["table"]}


def case_params(
    study, source: str, spec: dict, engine: str, engine_settings: dict, group: str | None, names: list[str]
) -> dict:
    """The unit's cases on one model and the ground of each of their terrain classes: ``group``, or, for a unit
    over several classes (``group`` None: the committed table's, one job per model), each case's class in the
    source's case table (``spec["cases"]``)."""
    if group is None:
        wanted = set(names)
        classes = list(dict.fromkeys(c for c, name in spec["cases"] if name in wanted))
    else:
        classes = [group]
    grounds = {c: study.real_data.classes[c].model_dump(mode="json") for c in classes}
    params = simulation_params(study, engine, engine_settings) | canonical({"classes": grounds})
    return unit_params(params, DRIVEN, source, names)


def compare_inputs(study, source: str, spec: dict, cases: list[tuple[str, str]]) -> dict:
    return {"segments": spec.get("table")}


def compare_settings(study) -> dict:
    return canonical({"track": study.robot.track})
