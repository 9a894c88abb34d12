"""CoppeliaSim: a Lua snippet setting the Bullet engine parameters, and its reader."""

from __future__ import annotations

import re
from collections.abc import Mapping

from simpick.engines.simulator_files.common import _header, _meanings, _num


def write_coppeliasim(settings: Mapping, entries: Mapping | None, title: list[str]) -> dict[str, str]:
    notes = _meanings(entries, ("solver_iterations", "time_step", "contact_stiffness", "contact_damping"), settings)
    step = settings.get("time_step")
    lines = [
        "-- in a customization script of the scene (Lua), before the simulation starts",
        "sim.setInt32Param(sim.intparam_dynamic_engine, sim.physics_bullet)",
        "sim.setEngineInt32Param(sim.bullet_global_constraintsolvingiterations, -1, "
        f"{int(settings['solver_iterations'])})",
        *(
            [
                "-- the physics step: the engine steps dt / this many times per simulation step (simDyn)",
                f"sim.setFloatParam(sim.floatparam_physicstimestep, {_num(step)})",
            ]
            if step is not None
            else ["-- simpick ran a 1 ms physics step; CoppeliaSim's default is 5 ms (Dynamics dialog: dt)"]
        ),
    ]
    return {"lua": _header("--", [*title, *notes]) + "\n".join(lines) + "\n"}


def read_coppeliasim(text: str) -> dict:
    m = re.search(r"constraintsolvingiterations, -1, (\d+)\)", text)
    out = {"solver_iterations": int(m.group(1))}
    step = re.search(r"floatparam_physicstimestep, ([0-9.eE+-]+)\)", text)
    if step:
        out["time_step"] = float(step.group(1))
    return out
