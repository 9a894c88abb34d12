"""A lab test's case (the lab source, simpick.sources.lab): the motion's constant command over the
generated terrain strip of its terrain."""

from __future__ import annotations

from simpick.inputs.terrain import load
from simpick.simulate.run import Case, Recording, run_case, scenario_from


def prepare_case(urdf: str, inputs: dict, params: dict, name: str):
    """A lab test: the motion's constant command over the generated terrain strip."""
    motion = params["motion"]
    case = Case(
        engine=params["engine"],
        terrain=params["terrain"],
        motion=name,
        v=motion["v"],
        w=motion["w"],
        duration=motion["duration"],
        start=tuple(motion["start"]),
    )
    which = {"terrain": case.terrain, "motion": case.motion, "test": f"{case.terrain}/{case.motion}"}

    def run():
        scenario = scenario_from(params, urdf, load(inputs["terrain"]))
        return run_case(case, scenario, params["robot"]["track"], Recording.from_params(params))

    return which, run
