"""The own-logs source: the user's logs (config ``own_logs``: a mapped CSV or a ROS bag), imported to
the canonical form (rules/real.smk, import_own_log) and then replayed and compared exactly as a
dataset folder's runs: its jobs are the replay source's (``DRIVEN``)."""

from __future__ import annotations

from simpick.sources.replay import (  # noqa: F401 - the replay's planning is the own logs'
    GROUP,
    MEM_MB,
    case_inputs,
    case_params,
    compare_inputs,
    compare_settings,
)

KIND = "own"
DRIVEN = "replay"


def cases(study) -> list[tuple[str, str]]:
    """(terrain class, name) of every entry of ``own_logs`` (``study``: the typed study, simpick.sources.base)."""
    return [(entry.terrain_class, entry.name) for entry in study.own_logs]
