"""The lab source: the paper's tests (terrain x motion of the config) on generated terrain strips,
compared with the paper's real statistics (Farley et al. 2022, Tables 8-9; simpick.inputs.reference)."""

from __future__ import annotations

from simpick.sources.base import canonical, engine_params, unit_params

KIND = DRIVEN = "lab"
GROUP = "terrain"
MEM_MB = 400


# --- planning ---


def cases(config: dict) -> list[tuple[str, str]]:
    """Every terrain x every motion of the config."""
    return [(t, m) for t in config["terrains"] for m in config["motions"]]


def lab_params(config: dict, engine: str, terrain: str, motion_name: str) -> dict:
    """Everything one lab-study simulation depends on, and nothing else."""
    return engine_params(config, engine) | canonical(
        {
            "terrain": terrain,
            "motion_name": motion_name,
            "motion": config["motions"][motion_name],
        }
    )


def case_inputs(config: dict, source: str, spec: dict, group: str, names: list[str]) -> dict:
    return {"urdf": config["robot"]["urdf"], "terrain": f"results/terrains/{group}.json"}


def case_params(config: dict, source: str, spec: dict, engine: str, group: str, names: list[str]) -> dict:
    (name,) = names  # a lab case is one job
    return unit_params(lab_params(config, engine, group, name), DRIVEN, source, names)


def compare_inputs(config: dict, source: str, spec: dict, cases: list[tuple[str, str]]) -> dict:
    return {"published": config["reference"]["published"]}


def compare_settings(config: dict) -> dict:
    return {}
