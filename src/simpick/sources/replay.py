"""The replay source: every run of a dataset folder (BorealTC layout; simpick.real.datasets), imported to
the canonical form (rules/real.smk), driven by its recorded wheel speeds and compared with the
real log window by window (simpick.compare.real.replay_compare)."""

from __future__ import annotations

from simpick.sources.base import canonical, log_path, real_params, unit_params

KIND = DRIVEN = "replay"
GROUP = "terrain_class"
MEM_MB = 800  # a whole run's trace and log in memory


# --- planning (``study``: the typed study, simpick.sources.base) ---


def cases(dataset) -> list[tuple[str, str]]:
    """(terrain class, run) of every run of an opened dataset folder (simpick.real.datasets)."""
    return [(r.terrain_class, r.run) for r in dataset.runs]


def case_inputs(study, source: str, spec: dict, group: str, names: list[str]) -> dict:
    """The robot and the logs of the unit's runs, in the order of ``names`` (one terrain class's runs)."""
    return {"urdf": study.robot.urdf, "logs": [log_path(source, group, name) for name in names]}


def case_params(
    study, source: str, spec: dict, engine: str, engine_settings: dict, group: str, names: list[str]
) -> dict:
    return unit_params(real_params(study, engine, engine_settings, group), DRIVEN, source, names)


def compare_inputs(study, source: str, spec: dict, cases: list[tuple[str, str]]) -> dict:
    return {"logs": [log_path(source, c, run) for c, run in cases]}


def compare_settings(study) -> dict:
    return canonical({"track": study.robot.track, "window": study.real_data.window})
