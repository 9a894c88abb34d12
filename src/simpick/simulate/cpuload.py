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

import dataclasses
import os
import statistics

import numpy as np
import psutil
from pydantic import Field

from simpick.engines import get_engine
from simpick.inputs import terrain as terrain_io
from simpick.inputs.motions import constant_commands
from simpick.simulate.settings import CpuLoad, Motion, SimulationParams

DEFINITION = (
    "CPU load = process CPU time (user + system) spent stepping / simulated time, "
    "in % of one core: the load the engine would put on one core if paced to real time. "
    "Median over repeats."
)


class CpuLoadParams(SimulationParams):
    """What rule cpu_load's job reads: the model's simulation settings, the lab terrain and motion driven, and
    the CPU-load scenarios."""

    terrain: str = Field(description="the lab terrain driven (its strip is the job's input)")
    motion_name: str
    motion: Motion
    cpu_load: CpuLoad


def convoy(robots: int, start: tuple[float, float, float], spacing: float) -> tuple:
    """Robots one behind another, so all of them cross the same strip."""
    x, y, yaw = start
    return tuple((x - i * spacing, y, yaw) for i in range(robots))


def _robots(cpu: CpuLoad, scenario: str) -> int:
    """Robots in one world of a scenario: the paper's Scenario 1 (average) or 2 (intense)."""
    return {"average": cpu.robots_average, "intense": cpu.robots_intense}[scenario]


def measure(params: dict, urdf: str, terrain_file: str, limits=None) -> dict:
    """CPU load per scenario of the job's params (:class:`CpuLoadParams`: the model, its settings, the robot,
    the motion and the ``cpu_load`` block: duration, repeats, robots_average, robots_intense, spacing).
    With ``limits`` (a :class:`simpick.simulate.health.HealthLimits`) every repeat is health-checked like
    a simulation job (on the lead robot, the one the engine records), and a failed repeat fails the
    measurement (``health``), so the scores leave it out."""
    from simpick.simulate.health import check
    from simpick.simulate.run import scenario_from

    p = CpuLoadParams.model_validate(params)
    engine_name, cpu, motion = p.engine, p.cpu_load, p.motion
    engine = get_engine(engine_name)
    # simpick.simulate.run reads the params as a mapping still
    base = scenario_from(params, urdf, terrain_io.load(terrain_file))
    timestep, duration = base.timestep, cpu.duration
    result = {
        "engine": engine_name,
        "engine_version": engine.version(),
        "definition": DEFINITION,
        "cpu_count": psutil.cpu_count(),
        "affinity": sorted(os.sched_getaffinity(0)),
    }
    all_reasons: list[str] = []
    for scenario_name in ("average", "intense"):
        robots = _robots(cpu, scenario_name)
        scenario = dataclasses.replace(base, starts=convoy(robots, tuple(motion.start), cpu.spacing))
        commands = constant_commands(motion.v, motion.w, duration, timestep, p.robot.track, scenario.robot, robots)
        loads, reasons = [], []
        for _ in range(cpu.repeats):
            record = engine.simulate(scenario, commands)
            loads.append(100.0 * record.cpu_time / (record.steps * timestep))
            if limits is not None:
                health = check(record, limits, np.asarray(commands)[:, 0])
                reasons += [
                    f"{scenario_name} ({robots} robots): {r}"
                    for r in health.reasons
                    if f"{scenario_name} ({robots} robots): {r}" not in reasons
                ]
        result[scenario_name] = {
            "robots": robots,
            "load_percent": statistics.median(loads),
            "repeats_percent": loads,
            "simulated_seconds": duration,
        }
        all_reasons += reasons
    result["health"] = {
        "status": "failed" if all_reasons else "ok",
        "reasons": all_reasons,
        "checked": limits is not None,
    }
    return result


def hung_result(params: dict, timeout: float) -> dict:
    """The record of a CPU-load job stopped by the watchdog: no load, health failed with the
    reason, so the scores leave the engine out of both CPU metrics and list why (as for a
    failed repeat) instead of scoring a partial measurement."""
    from simpick.simulate.watchdog import hung_reason

    p = CpuLoadParams.model_validate(params)
    cpu = p.cpu_load
    reason = hung_reason(timeout)
    return {
        "engine": p.engine,
        "engine_version": "",
        "definition": DEFINITION,
        **{
            scenario: {
                "robots": _robots(cpu, scenario),
                "load_percent": None,
                "repeats_percent": [],
                "simulated_seconds": cpu.duration,
            }
            for scenario in ("average", "intense")
        },
        "health": {"status": "failed", "reasons": [reason], "checked": True},
    }
