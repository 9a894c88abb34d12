"""What calibration may tune on an engine: the parameters its adapter declares, with the config's
bounds, their as-configured values, and the one place that applies chosen values to a job's
parameters (``friction`` the terrain class's coefficient, any other name the adapter's own setting)."""

from __future__ import annotations

import copy
from dataclasses import replace

from simpick.engines import get_engine
from simpick.errors import InputError
from simpick.simulate.real_settings import RealCaseParams


def parameter_space(engine: str, overrides: dict | None = None) -> dict:
    """name -> Calibratable: what the adapter declares, with the config's bounds overrides."""
    space = dict(get_engine(engine).calibratable)
    for name, bounds in (overrides or {}).items():
        if name not in space:
            raise InputError(
                f"calibration.bounds.{engine}.{name}",
                f"{engine} has no calibratable parameter {name!r}",
                f"use one of {sorted(space)}",
            )
        space[name] = replace(space[name], low=float(bounds[0]), high=float(bounds[1]))
    return space


def configured_values(params: dict, space: dict) -> dict:
    """The as-configured value of each parameter (clipped into its bounds); ``params``: a real-data case's
    (:class:`simpick.simulate.real_settings.RealCaseParams`)."""
    case = RealCaseParams.model_validate(params)
    settings = get_engine(case.engine).settings_model.of(case.engine_settings, case.engine)
    out = {}
    for name, p in space.items():
        value = case.ground.friction if name == "friction" else getattr(settings, name)
        out[name] = min(max(value, p.low), p.high)
    return out


def apply_parameters(params: dict, values: dict) -> dict:
    """A copy of a real-data job's params with the parameter values in place: ``friction`` is the
    class's ground friction, every other name an engine setting."""
    out = copy.deepcopy(params)
    for name, value in values.items():
        if name == "friction":
            out["class"] = dict(out["class"], friction=float(value))
        else:
            out["engine_settings"] = dict(out.get("engine_settings") or {}, **{name: float(value)})
    return out
