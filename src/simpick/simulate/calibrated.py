"""A calibrated simulator profile's jobs (simulate, validate): the fit's settings merged over the plan's.

The calibrated profile's settings come from its fit (rule simulator_calibrate,
:mod:`simpick.studies.simulator_calibration`), a file its jobs take as an input; this module reads it and
nothing else, so that the simulate and validate jobs' code reaches no fitting or real-data code."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml


def read_calibrated(path: str | Path) -> dict[str, Any]:
    """The fitted settings of a calibration file (empty where nothing was fitted)."""
    data = yaml.safe_load(Path(path).read_text()) or {}
    settings = data.get("settings") or {}
    if not isinstance(settings, dict):
        raise ValueError(f"{path}: settings: a mapping of adapter setting -> value expected")
    return dict(settings)


def with_calibrated(params: dict, calibrated: str | None) -> tuple[dict, dict]:
    """A simulate or validate job's params with the calibration file's settings merged over its
    ``engine_settings``, and the provenance to record (the file and the settings); unchanged without one."""
    if not calibrated:
        return params, {}
    settings = read_calibrated(calibrated)
    return merge_settings(params, settings), {"calibrated_from": str(calibrated), "calibrated_settings": settings}


def merge_settings(params: dict, settings: dict) -> dict:
    """A job's params with ``settings`` merged over its ``engine_settings`` (a fit's, or a fit's trial)."""
    return {**params, "engine_settings": {**dict(params["engine_settings"]), **settings}}
