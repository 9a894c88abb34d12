"""The simulate stage's jobs: a unit of cases stepped on one model under the watchdog, one trace per
case (whatever its source: :mod:`simpick.sources` says how a case is driven), and the CPU-load run.
"""

from __future__ import annotations

import importlib
import json
import sys
from collections.abc import Mapping
from pathlib import Path

from simpick.simulate.cpuload import hung_result, measure
from simpick.simulate.health import HealthLimits
from simpick.simulate.run import UnitParams, config_hash, fields_of, simulation
from simpick.simulate.traces import COLUMNS, write_trace
from simpick.simulate.watchdog import DEFAULT_TIMEOUT_S, Watchdog, hung_reason

# How a case of each kind is driven (a source's DRIVEN kind, simpick.sources): "module:function" of
# its prepare function, imported by name when a job runs, so that a lab job loads none of the real
# data's code (simpick.real); the plan names the module as part of the job's code version.
PREPARE = {
    "lab": "simpick.simulate.lab:prepare_case",
    "segments": "simpick.simulate.real:prepare_segment",
    "replay": "simpick.simulate.real:prepare_replay",
    "steps": "simpick.simulate.steps:prepare_step",
}

# What a unit of each kind reads (its PREPARE function's model), by name as PREPARE: the plan validates each
# simulate job's params against it (simpick.plan.models.ModelPlanning.simulate_params).
PARAMS = {
    "lab": "simpick.simulate.lab:LabUnitParams",
    "segments": "simpick.simulate.real:SegmentsUnitParams",
    "replay": "simpick.simulate.real:RealUnitParams",
    "steps": "simpick.simulate.steps:StepUnitParams",
}

TRACE_KEYS = ("source", "test", "engine", "terrain", "motion", "dataset", "run", "segment", "window")


def simulate_job(
    outputs: list[str],
    urdf: str,
    inputs: dict,
    params: Mapping,
    after_hung=None,
    log: str | None = None,
    start: int = 0,
) -> list[dict]:
    """A unit's cases (:class:`simpick.simulate.run.UnitParams`: ``cases``, one trace each in ``outputs``) on
    one model, each under the watchdog: a case still running after ``health.timeout`` s of wall time is
    written as a failed (hung) trace. The stopped process cannot run the cases after it: with ``log`` (the
    job's log) a fresh process takes them up (:func:`resume`), else they are written as failed (not run)
    traces; the source's compare job lists either like any failed run. ``kind`` says how a case is driven
    (lab, segments, replay, steps: its :data:`PREPARE` function, imported by name, which reads the params as
    its kind's model); ``inputs`` holds the files it reads. ``after_hung``: called once the hung traces are
    written, before the process ends (a job that compares its own traces, the sweep, does so then).
    ``start``: the first case to run (the cases before it were run by the process this one took over from)."""
    from simpick.simulate.calibrated import with_calibrated

    # a calibrated profile's fitted settings (its fit's file, an input) over its plan-time (tuned) settings
    params, provenance = with_calibrated(params, inputs.get("calibrated"))
    unit = fields_of(UnitParams, params)
    if len(outputs) != len(unit.cases):
        raise ValueError(f"{len(unit.cases)} cases for {len(outputs)} outputs")
    module, _, function = PREPARE[unit.kind].partition(":")
    prepare = getattr(importlib.import_module(module), function)
    units = []
    for name, output in list(zip(unit.cases, outputs))[start:]:
        described, run = prepare(urdf, inputs, params, name)
        which = {key: None for key in TRACE_KEYS} | described | {"source": unit.source, "engine": unit.engine}
        units.append((which, run, output))
    timeout = unit.health.timeout
    done = []
    for i, (which, run, output) in enumerate(units):

        def hung(i=i):
            write_hung_trace(units[i][2], units[i][0], params, timeout)
            if log is not None and after_hung is None and i + 1 < len(units):
                resume(outputs, urdf, inputs, params, log, start + i + 1)  # does not return
            for later, _, path in units[i + 1 :]:
                write_hung_trace(path, later, params, timeout, reason=f"not run: {units[i][0]['test']} hung before it")
            if after_hung is not None:
                after_hung()

        with Watchdog(timeout, hung):
            frame, meta = run()
        # the fingerprint of the params as the rule gave them (simpick.seeds.config_hash)
        meta = meta | which | provenance | {"config_hash": config_hash(params)}
        write_trace(frame, meta, output)
        done.append(meta)
    return done


def resume(outputs: list[str], urdf: str, inputs: Mapping, params: Mapping, log: str, start: int) -> None:
    """Replace this process (a simulate job whose case ``start - 1`` hung: the engine cannot be trusted to
    step again in it) by a fresh Python that runs the job's cases from ``start`` on
    (:func:`take_over`, this module run as a program), so that one hung case does not cost the cases after it. The same
    process id, so Snakemake waits for it as for the job; the job's log goes on. What it needs is written
    beside the log as JSON (plain data: the rule's params, the file names)."""
    import os

    state = {
        "outputs": list(outputs),
        "urdf": urdf,
        "inputs": {k: v if isinstance(v, str) else list(v) for k, v in inputs.items()},
        "params": dict(params),
        "log": log,
        "start": start,
    }
    path = Path(f"{log}.resume.json")
    path.write_text(json.dumps(state))
    print(f"simpick: the {len(outputs) - start} case(s) after it go on in a fresh process", file=sys.stderr)
    sys.stderr.flush()
    sys.stdout.flush()
    # this module run as a program (its take_over); named by the function, so a rename is caught at once
    os.execv(sys.executable, [sys.executable, "-m", take_over.__module__, str(path)])


def take_over(state_file: str) -> None:
    """The rest of a simulate job after one of its cases hung (:func:`resume`): what the job was given, read
    from ``state_file`` (JSON beside the job's log, removed once read); its cases from the one after the hung
    case on, the job's log appended to. Run as ``python -m simpick.simulate.jobs STATE`` in the job's
    process, which the hung one was replaced by."""
    from simpick.joblog import logged

    path = Path(state_file)
    state = json.loads(path.read_text())
    path.unlink()
    with logged(state["log"], append=True):
        simulate_job(
            state["outputs"], state["urdf"], state["inputs"], state["params"], log=state["log"], start=state["start"]
        )


def write_hung_trace(output: str, which: dict, params: Mapping, timeout: float, reason: str | None = None) -> None:
    """An empty trace whose health record says the engine hung (or ``reason``), so the run is
    reported. ``which``: the metadata that names the case (TRACE_KEYS), so the job that compares
    it finds it like any other; ``params``: the unit's, as the rule gave them."""
    sim = simulation(params)
    waited = 0.0 if reason else float(timeout)  # a case not run used no time
    reason = reason or hung_reason(timeout)
    print(f"simpick: {which['engine']} {which['source']} {which['test']}: {reason}", file=sys.stderr)
    write_trace(
        {c: [] for c in COLUMNS},
        {
            "engine_version": "",
            **which,
            "timestep": sim.physics.timestep,
            # the seed as the rule's params carry it (canonical: a float)
            "seed": float(sim.seed),
            "steps": 0,
            "sim_time": 0.0,
            "wall_time": waited,
            "cpu_time": float("nan"),
            "real_time_factor": None,
            "health": {"status": "failed", "reasons": [reason]},
            "config_hash": config_hash(params),
        },
        output,
    )


def cpu_job(output: str, terrain_file: str, urdf: str, params: dict, timeout: float = DEFAULT_TIMEOUT_S) -> None:
    """The CPU-load measurement of one engine (simpick.simulate.cpuload: its params, CpuLoadParams), under the
    watchdog: still running after ``timeout`` s of wall time (simpick.simulate.watchdog.runtime_timeout of the
    rule's runtime), the job writes :func:`simpick.simulate.cpuload.hung_result` instead, which the scores
    leave out and name."""
    sim = simulation(params)

    def write(result: dict) -> None:
        Path(output).parent.mkdir(parents=True, exist_ok=True)
        Path(output).write_text(json.dumps(result, indent=1))

    def hung() -> None:
        result = hung_result(params, timeout)
        print(f"simpick: cpu_load {sim.engine}: {result['health']['reasons'][0]}", file=sys.stderr)
        write(result)

    with Watchdog(timeout, hung):
        result = measure(params, urdf, terrain_file, limits=HealthLimits(**sim.health.model_dump()))
    write(result)


if __name__ == "__main__":  # a simulate job's rest after a hung case (resume)
    take_over(sys.argv[1])
