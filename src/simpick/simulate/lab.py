"""A lab test's case (the lab source, simpick.sources.lab): the motion's constant command over the
generated terrain strip of its terrain."""

from __future__ import annotations

from pydantic import Field

from simpick.inputs.terrain import load
from simpick.simulate.run import Case, Recording, run_case, scenario_from
from simpick.simulate.settings import Motion, SimulationParams


class LabCaseParams(SimulationParams):
    """What a lab case's simulate job reads (the plan's simpick.sources.lab.case_params): the model's
    simulation settings, the terrain and the motion, and which unit of cases it is."""

    terrain: str = Field(description="the lab terrain driven (its strip is the job's input)")
    motion_name: str
    motion: Motion
    kind: str = Field(description="how the cases are driven: simpick.simulate.jobs.PREPARE")
    source: str
    cases: list[str]


def prepare_case(urdf: str, inputs: dict, params: dict, name: str):
    """A lab test: the motion's constant command over the generated terrain strip."""
    p = LabCaseParams.model_validate(params)
    motion = p.motion
    case = Case(
        engine=p.engine,
        terrain=p.terrain,
        motion=name,
        v=motion.v,
        w=motion.w,
        duration=motion.duration,
        start=tuple(motion.start),
    )
    which = {"terrain": case.terrain, "motion": case.motion, "test": f"{case.terrain}/{case.motion}"}

    def run():
        # simpick.simulate.run reads the params as a mapping still (scenario_from, Recording.from_params)
        scenario = scenario_from(params, urdf, load(inputs["terrain"]))
        return run_case(case, scenario, p.robot.track, Recording.from_params(params))

    return which, run
