"""The lab source: the paper's tests (terrain x motion of the config) on generated terrain strips,
compared with the paper's real statistics (Farley et al. 2022, Tables 8-9; simpick.inputs.reference)."""

from __future__ import annotations

from simpick.sources.base import canonical, simulation_params, unit_params

KIND = DRIVEN = "lab"
GROUP = "terrain"
MEM_MB = 400


# --- planning (``study``: the typed study, simpick.sources.base) ---


def cases(study) -> list[tuple[str, str]]:
    """Every terrain x every motion of the study."""
    return [(t, m) for t in study.terrains for m in study.motions]


def lab_params(study, engine: str, engine_settings: dict, terrain: str, motion_name: str) -> dict:
    """Everything one lab-study simulation depends on, and nothing else (the CPU-load job's case)."""
    return simulation_params(study, engine, engine_settings) | canonical(
        {
            "terrain": terrain,
            "motion_name": motion_name,
            "motion": study.motions[motion_name].model_dump(mode="json"),
        }
    )


def case_inputs(study, source: str, spec: dict, group: str, names: list[str]) -> dict:
    return {"urdf": study.robot.urdf, "terrain": f"results/terrains/{group}.json"}


def case_params(
    study, source: str, spec: dict, engine: str, engine_settings: dict, group: str, names: list[str]
) -> dict:
    """A unit of motions on one terrain (a job per engine x terrain): the terrain and each case's motion."""
    motions = {name: study.motions[name].model_dump(mode="json") for name in names}
    params = simulation_params(study, engine, engine_settings) | canonical({"terrain": group, "motions": motions})
    return unit_params(params, DRIVEN, source, names)


def compare_inputs(study, source: str, spec: dict, cases: list[tuple[str, str]]) -> dict:
    return {"published": study.reference.published}


def compare_settings(study) -> dict:
    return {}
