"""The segments source: constant-command segments of real runs (the committed table
``real_data.segments``, or the one derived from a dataset folder), each segment's command driven on
its terrain class's flat ground and compared with the real window's statistics (simpick.compare.real).
The speed-accuracy sweep (simpick.studies.sweep) runs this source's simulate, compare and summarise steps at
each of its timesteps."""

from __future__ import annotations

import csv

from simpick.sources.base import canonical, real_params, unit_params

KIND = DRIVEN = "segments"
GROUP = "terrain_class"
MEM_MB = 400


# --- planning ---

def by_class(path: str, classes: dict | list) -> dict[str, list[str]]:
    """terrain class -> segment ids, from a segment table (plain csv: fast to parse). Raises
    ValueError on a class with no entry under real_data.classes."""
    found: dict[str, list[str]] = {}
    with open(path, newline="") as handle:
        for row in csv.DictReader(handle):
            found.setdefault(row["terrain_class"], []).append(row["segment"])
    unknown = sorted(set(found) - set(classes))
    if unknown:
        raise ValueError(f"{path}: terrain classes {unknown} have no entry under real_data.classes in the config")
    return found


def cases(path: str, classes: dict | list) -> list[tuple[str, str]]:
    """(terrain class, segment id) of every row of a segment table."""
    return [(c, s) for c, ids in by_class(path, classes).items() for s in ids]


def case_inputs(config: dict, source: str, spec: dict, group: str, names: list[str]) -> dict:
    return {"urdf": config["robot"]["urdf"], "segments": spec["table"]}


def case_params(config: dict, source: str, spec: dict, engine: str, group: str, names: list[str]) -> dict:
    return unit_params(real_params(config, engine, group), DRIVEN, source, names)


def compare_inputs(config: dict, source: str, spec: dict, cases: list[tuple[str, str]]) -> dict:
    return {"segments": spec.get("table")}


def compare_settings(config: dict) -> dict:
    return canonical({"track": config["robot"]["track"]})


# --- jobs ---

def class_table(table: str, terrain_class: str):
    """The segments of one terrain class (pandas, indexed by segment id)."""
    from simpick.simulate.real import class_segments
    return class_segments(table, terrain_class)


def simulate(seg, urdf: str, params: dict):
    """One segment's command on ``params["engine"]`` (simpick.simulate.real.simulate_segment)."""
    from simpick.simulate.real import simulate_segment
    return simulate_segment(seg, urdf, params)


def prepare_case(urdf: str, inputs: dict, params: dict, name: str):
    """A segment of the table: its constant command on its class's flat ground, compared in its window."""
    from simpick.errors import InputError

    table = class_table(inputs["segments"], params["terrain_class"])
    if name not in table.index:
        raise InputError(inputs["segments"], f"has no {params['terrain_class']} segment {name!r}", "rerun snakemake")
    seg = table.loc[name]
    which = {"terrain": params["terrain_class"], "motion": seg.name, "test": seg.name, "dataset": seg.dataset,
             "run": str(seg.run), "segment": seg.name,
             "window": [float(seg.settle), float(seg.settle + seg.duration)]}
    return which, lambda: simulate(seg, urdf, params)


def compare(traces: list[str], inputs: dict, params: dict):
    """Every simulated segment against its real window statistics (simpick.compare.real.segment_compare)."""
    from simpick.compare.real import segment_compare
    return segment_compare(inputs["segments"], traces, params["track"])
