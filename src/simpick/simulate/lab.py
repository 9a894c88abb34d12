"""A lab test's case (the lab source, simpick.sources.lab): the motion's constant command over the
generated terrain strip of its terrain."""

from __future__ import annotations

from simpick.simulate.health import HealthLimits
from simpick.simulate.imu import ImuModel
from simpick.simulate.run import Case, run_case


def prepare_case(urdf: str, inputs: dict, params: dict, name: str):
    """A lab test: the motion's constant command over the generated terrain strip."""
    motion = params["motion"]
    case = Case(engine=params["engine"], terrain=params["terrain"], motion=name,
                v=motion["v"], w=motion["w"], duration=motion["duration"], start=tuple(motion["start"]))
    which = {"terrain": case.terrain, "motion": case.motion, "test": f"{case.terrain}/{case.motion}"}

    def run():
        return run_case(case, urdf=urdf, terrain_file=inputs["terrain"], track=params["robot"]["track"],
                        max_wheel_torque=params["robot"]["max_wheel_torque"],
                        timestep=params["physics"]["timestep"], ground_friction=params["physics"]["ground_friction"],
                        engine_settings=params["engine_settings"], imu=ImuModel(**params["imu"]),
                        seed=int(params["seed"]), limits=HealthLimits(**params["health"]),
                        robot_options=params["robot"])

    return which, run
