"""The interface every source module gives (:class:`Source`), and the parameters all share.

Planning (:mod:`simpick.plan`, at DAG time, from the typed study and the source's entry of
``Plan.sources``: ``spec``, with its ``cases`` and, for a segment table, its ``table``) and jobs (from
``params``) meet here: a source module is a plain module with these names, checked by
``tests/test_sources.py``.

``study`` is the typed study (:class:`simpick.config.Study`, read by attribute: the config lies in a layer
above this one, tests/test_layers.py); a model's settings (an engine's block, a simulator profile's or a
reference model's) come from the plan (:func:`model_settings`), as the profiles are the plan's own.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable


@runtime_checkable
class Source(Protocol):
    """One kind of source (a module satisfies it: ``isinstance(simpick.sources.lab, Source)``)."""

    KIND: str  # the kind's name (simpick.sources.KINDS)
    DRIVEN: str  # the kind whose jobs simulate and compare its cases (the params' "kind":
    # simpick.simulate.jobs.PREPARE, simpick.compare.kinds.BY_KIND): its own, or "replay"
    GROUP: str  # the column that groups its cases in summaries: "terrain" (the lab) or "terrain_class"
    MEM_MB: int  # memory of one simulate job of the kind (MB)

    # --- planning: what a case's simulation and the source's comparison need (``study``: module doc) ---
    def case_inputs(self, study, source: str, spec: dict, group: str, names: list[str]) -> dict: ...

    def case_params(
        self, study, source: str, spec: dict, engine: str, engine_settings: dict, group: str, names: list[str]
    ) -> dict: ...

    def compare_inputs(self, study, source: str, spec: dict, cases: list[tuple[str, str]]) -> dict: ...

    def compare_settings(self, study) -> dict: ...


def canonical(value):
    """Builtin types only, sorted keys, numbers as floats: Snakemake fingerprints params by
    repr, so 4 and 4.0, or a reordered mapping, must not look like an edit."""
    if isinstance(value, dict):
        return {str(k): canonical(value[k]) for k in sorted(value)}
    if isinstance(value, (list, tuple)):
        return [canonical(v) for v in value]
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return value
    return float(value)


def model_settings(config: dict, model: str) -> dict:
    """A model's settings from the plan's plain settings: an engine's block, a reference model's, or a simulator
    profile's (the plan puts the catalog's settings under ``profiles``)."""
    for block in ("engines", "profiles", "baselines"):
        # by block name: the profiles are the plan's own, in no section of the typed study, and each block is a
        # mapping keyed by model name (data), in the config's order
        found = config.get(block) or {}
        if model in found:
            return found[model] or {}
    raise KeyError(f"model {model!r} is neither a configured engine, a simulator profile nor a reference model")


def simulation_params(study, engine: str, engine_settings: dict) -> dict:
    """What every simulation on ``engine`` depends on, whatever it drives over, from the typed study (module
    doc) and the model's settings (:func:`model_settings`): the fields of
    :class:`simpick.simulate.settings.SimulationParams`."""
    return canonical(
        {
            "engine": engine,
            "engine_settings": engine_settings,
            "physics": study.physics.model_dump(mode="json"),
            # the robot's file is the job's input (Snakemake tracks its content), not a parameter
            "robot": study.robot.model_dump(mode="json", exclude={"urdf"}),
            "imu": study.imu.model_dump(mode="json"),
            "health": study.health.model_dump(mode="json"),
            "seed": study.seed,
        }
    )


def real_params(study, engine: str, engine_settings: dict, terrain_class: str) -> dict:
    """What a real-data case on ``engine`` depends on: the engine's, and its terrain class's ground (the fields of
    :class:`simpick.simulate.real_settings.RealCaseParams`)."""
    return simulation_params(study, engine, engine_settings) | canonical(
        {
            "terrain_class": terrain_class,
            "class": study.real_data.classes[terrain_class].model_dump(mode="json"),
        }
    )


def unit_params(params: dict, kind: str, source: str, names: list[str]) -> dict:
    """A simulate job's parameters: its cases' and which source, kind and cases they are."""
    return params | {"kind": kind, "source": source, "cases": list(names)}


def log_path(source: str, group: str, name: str) -> str:
    """Where a replayed source's canonical log of (terrain class, run) lies (rules/real.smk writes it)."""
    return f"results/real/{source}/logs/{group}/{name}.parquet"
