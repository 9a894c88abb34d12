"""CPU load of an engine with one robot (paper Scenario 1) and five robots (Scenario 2).

The paper read CPU % off the Ubuntu System Monitor while each simulator ran at real time.
simpick's engines run as fast as they can, so it measures the equivalent directly:

    load = process CPU seconds spent stepping / simulated seconds x 100 %

i.e. the share of one core the engine would use if paced to real time (above 100 %: it
cannot keep up). CPU time is the process's user + system time (the counter psutil
reads), taken around the stepping loop only, so imports and model building are not
counted. The median over repeats is reported with every repeat, so the spread shows.
"""

from __future__ import annotations

import os
import statistics

import numpy as np
import psutil

from simpick.inputs import terrain as terrain_io
from simpick.engines import get_engine
from simpick.engines.base import Scenario
from simpick.inputs.motions import constant_commands
from simpick.inputs.robot import load_from_config

DEFINITION = ("CPU load = process CPU time (user + system) spent stepping / simulated time, "
              "in % of one core: the load the engine would put on one core if paced to real time. "
              "Median over repeats.")


def convoy(robots: int, start: tuple[float, float, float], spacing: float) -> tuple:
    """Robots one behind another, so all of them cross the same strip."""
    x, y, yaw = start
    return tuple((x - i * spacing, y, yaw) for i in range(robots))


def measure(engine_name: str, *, urdf: str, terrain_file: str, motion: dict, timestep: float,
            ground_friction: float, max_wheel_torque: float, track: float, engine_settings: dict,
            duration: float, repeats: int, robots_average: int, robots_intense: int,
            spacing: float, limits=None, robot_options: dict | None = None) -> dict:
    """CPU load per scenario; with ``limits`` (a :class:`simpick.simulate.health.HealthLimits`) every
    repeat is health-checked like a simulation job (on the lead robot, the one the engine
    records), and a failed repeat fails the measurement (``health``), so the scores leave it out."""
    from simpick.simulate.health import check

    engine = get_engine(engine_name)
    robot = load_from_config({**(robot_options or {}), "urdf": urdf})
    terrain = terrain_io.load(terrain_file)
    result = {"engine": engine_name, "engine_version": engine.version(), "definition": DEFINITION,
              "cpu_count": psutil.cpu_count(), "affinity": sorted(os.sched_getaffinity(0))}
    all_reasons: list[str] = []
    for scenario_name, robots in (("average", robots_average), ("intense", robots_intense)):
        scenario = Scenario(robot=robot, terrain=terrain, ground_friction=ground_friction,
                            timestep=timestep, max_wheel_torque=max_wheel_torque,
                            starts=convoy(robots, tuple(motion["start"]), spacing), settings=engine_settings)
        commands = constant_commands(motion["v"], motion["w"], duration, timestep, track, robot, robots)
        loads, reasons = [], []
        for _ in range(repeats):
            record = engine.simulate(scenario, commands)
            loads.append(100.0 * record.cpu_time / (record.steps * timestep))
            if limits is not None:
                health = check(record, limits, np.asarray(commands)[:, 0])
                reasons += [f"{scenario_name} ({robots} robots): {r}" for r in health.reasons if
                            f"{scenario_name} ({robots} robots): {r}" not in reasons]
        result[scenario_name] = {"robots": robots, "load_percent": statistics.median(loads),
                                 "repeats_percent": loads, "simulated_seconds": duration}
        all_reasons += reasons
    result["health"] = {"status": "failed" if all_reasons else "ok", "reasons": all_reasons,
                        "checked": limits is not None}
    return result


def hung_result(params: dict, timeout: float) -> dict:
    """The record of a CPU-load job stopped by the watchdog: no load, health failed with the
    reason, so the scores leave the engine out of both CPU metrics and list why (as for a
    failed repeat) instead of scoring a partial measurement."""
    from simpick.simulate.watchdog import hung_reason

    cpu = params["cpu_load"]
    reason = hung_reason(timeout)
    return {"engine": params["engine"], "engine_version": "", "definition": DEFINITION,
            **{scenario: {"robots": int(cpu[f"robots_{scenario}"]), "load_percent": None, "repeats_percent": [],
                          "simulated_seconds": cpu["duration"]} for scenario in ("average", "intense")},
            "health": {"status": "failed", "reasons": [reason], "checked": True}}

