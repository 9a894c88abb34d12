"""A lab test's case (the lab source, simpick.sources.lab): the motion's constant command over the
generated terrain strip of its terrain. A job runs a terrain's motions on one engine."""

from __future__ import annotations

from pydantic import Field, model_validator

from simpick.inputs.terrain import load
from simpick.simulate.run import Case, Recording, Unit, run_case, scenario_from
from simpick.simulate.settings import Motion, SimulationParams


class LabUnitParams(SimulationParams, Unit):
    """What a lab unit's simulate job reads (the plan's simpick.sources.lab.case_params): the model's
    simulation settings, the terrain, each case's motion, and which unit of cases it is."""

    terrain: str = Field(description="the lab terrain driven (its strip is the job's input)")
    motions: dict[str, Motion] = Field(description="each case's motion, by the case's (the motion's) name")

    @model_validator(mode="after")
    def _every_case_has_its_motion(self):
        missing = [name for name in self.cases if name not in self.motions]
        if missing:
            raise ValueError(f"cases {missing} have no motion under motions")
        return self


def prepare_case(urdf: str, inputs: dict, params: dict, name: str):
    """A lab test: the motion ``name``'s constant command over the generated terrain strip."""
    p = LabUnitParams.model_validate(params)
    motion = p.motions[name]
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
