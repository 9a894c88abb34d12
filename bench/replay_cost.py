"""A dataset replay's simulate jobs' CPU against their models' bare stepping loops, per model.

    .venv/bin/python bench/replay_cost.py                          # every model, on run asphalt/02
    .venv/bin/python bench/replay_cost.py dart isaac_sim-tuned --run ice/03 --repeats 3
    .venv/bin/python bench/replay_cost.py dart --profile /tmp/dart.prof   # cProfile of one whole case
    .venv/bin/python bench/replay_cost.py dart --set solver_sweeps=100      # a physics setting tried

Run from the repository root after a finished replay study (``snakemake --config borealtc_dir=PATH``): it reads
that study's results (``--results``, default results/). Per model, three figures for the whole study:

- ``job``: the simulate jobs' CPU seconds, from each job log's closing cost line (simpick.joblog: the job's
  process and the children it waited for, imports and trace writing included; Snakemake's ``benchmark:``
  files sample the CPU every 30 s and miss part of it);
- ``loop``: the runner's loop as the jobs timed it (each trace's ``cpu_time``: stepping, state reads and
  recording; a program-run engine's own CPU);
- ``bare``: the engine stepping alone, measured here on one run (``--run``): the world its adapter builds for
  that case, exactly as the job builds it (the plan's params, a calibrated profile's fit, the run's log),
  stepped under the run's commands, each set once where it changes, nothing read or recorded; process CPU,
  or the program's own CPU for an engine run in a program of its own (Gazebo's gz-physics). Scaled to the
  study as the study's ``loop`` times this run's bare/loop ratio, because a run's cost per simulated second
  depends on its class (DART's asphalt costs three times its ice); ``bare (by sim s)`` scales by the
  simulated seconds instead.

Also measured on the run: ``case``, the job's whole case (the log read, the world built, stepped, recorded,
the IMU and health check, the trace written), so ``case - bare`` is the per-case cost outside the stepping.
CPU time (not wall) because the machine may be shared; medians over ``--repeats``. With ``--set`` (a setting
tried) the run's own columns are the figures to read: compare its ``run bare`` with a run without it.
"""

from __future__ import annotations

import argparse
import cProfile
import datetime
import glob
import json
import os
import platform
import pstats
import resource
import statistics
import sys
import tempfile
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from simpick.engines import get_engine  # noqa: E402
from simpick.engines.runner import command_spans  # noqa: E402
from simpick.joblog import read_cost  # noqa: E402


def study_costs(results: Path, source: str) -> dict[str, dict[str, float]]:
    """Per model of ``source``'s replay in ``results``: its jobs' CPU (cost lines), the runner loops' CPU and
    the simulated seconds (the traces' metadata)."""
    import pyarrow.parquet as pq

    out: dict[str, dict[str, float]] = {}
    for folder in sorted((results / "logs" / "simulate" / source).iterdir()):
        costs = [read_cost(p.read_text()) for p in folder.glob("*.log")]
        out[folder.name] = {"jobs": len(costs), "job": sum(c[0] for c in costs if c), "loop": 0.0, "sim": 0.0}
    for path in glob.glob(str(results / "traces" / source / "*" / "*" / "*.parquet")):
        meta = json.loads(pq.read_schema(path).metadata[b"simpick"])
        row = out.setdefault(Path(path).parts[-3], {"jobs": 0, "job": 0.0, "loop": 0.0, "sim": 0.0})
        row["loop"] += float(meta["cpu_time"] or 0.0)
        row["sim"] += float(meta["sim_time"])
    return out


def plan_of(dataset_dir: str):
    from simpick.config import Study
    from simpick.plan import Plan

    config = yaml.safe_load((ROOT / "config.yaml").read_text())
    config["borealtc_dir"] = dataset_dir
    return Plan(config, Study.model_validate(config), basedir=str(ROOT))


def job_case(plan, source: str, model: str, run: str, results: Path, overrides: dict | None = None):
    """(params, inputs, case name) of ``run`` ("class/run") on ``model`` as its simulate job gets them: the
    plan's params with a calibrated profile's fit merged over them (simpick.simulate.calibrated), the unit's
    files under ``results``' parent; ``overrides``: engine settings tried over the model's."""
    from simpick.simulate.calibrated import with_calibrated

    group, name = run.split("/")
    names = [n for g, n in plan.sources[source]["cases"] if g == group]
    params = plan.simulate_params(source, model, group, names)
    inputs = plan.unit_inputs(source, model, group, names)
    base = results.resolve().parent
    inputs = {k: [str(base / p) for p in v] if isinstance(v, list) else str(base / v) for k, v in inputs.items()}
    params, _ = with_calibrated(params, inputs.get("calibrated"))
    if overrides:  # a setting tried (not the study's physics: its traces would change)
        params = {**params, "engine_settings": {**params["engine_settings"], **overrides}}
    return params, inputs, name


def captured_scenario(urdf: str, inputs: dict, params: dict, name: str):
    """(engine, scenario, wheel commands) that the job's replay of case ``name`` would step: the case is
    prepared and run up to its stepping, which is not done."""
    import simpick.simulate.real as real

    class Captured(Exception):
        pass

    seen = {}
    original = real.run_commands

    def capture(engine, commands, scenario, recording, noise_seed):
        seen.update(engine=engine, scenario=scenario, commands=commands)
        raise Captured

    real.run_commands = capture
    try:
        _, run = real.prepare_replay(urdf, inputs, params, name)
        run()
    except Captured:
        pass
    finally:
        real.run_commands = original
    return seen["engine"], seen["scenario"], seen["commands"]


def bare(engine_name: str, scenario, commands) -> float:
    """CPU s of the adapter's world stepped under ``commands`` (steps, wheels), each command set once where it
    changes, nothing read: the process's, or the program's own for a world stepped in a program (``cpu``); a
    reference model's whole computation."""
    commands = commands.reshape(len(commands), 1, -1)
    engine = get_engine(engine_name)
    if not hasattr(engine, "build"):  # a reference model (simpick.engines.baselines): formulas, no world
        cpu0 = time.process_time()
        engine.simulate(scenario, commands)
        return time.process_time() - cpu0
    world = engine.build(scenario)
    try:
        targets, step = world.set_wheel_targets, world.step
        spans = command_spans(commands)
        cpu0 = time.process_time()
        for first, end in spans:
            targets(commands[first])
            step(end - first)
        cpu = time.process_time() - cpu0
        return float(world.cpu) if hasattr(world, "cpu") else cpu
    finally:
        close = getattr(world, "close", None)
        if close is not None:
            close()


def whole_case(urdf: str, inputs: dict, params: dict, name: str, profile: str | None = None) -> tuple[float, float]:
    """(CPU s, loop CPU s) of one case as simulate_job runs it (prepared, run, its trace written to a temporary
    folder): this process's and the children's it waited for, and the runner loop's own (the trace's
    ``cpu_time``)."""
    from simpick.simulate.real import prepare_replay
    from simpick.simulate.traces import write_trace

    def usage() -> float:
        own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
        return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime

    with tempfile.TemporaryDirectory() as folder:
        profiler = cProfile.Profile() if profile else None
        cpu0 = usage()
        if profiler:
            profiler.enable()
        _, run = prepare_replay(urdf, inputs, params, name)
        frame, meta = run()
        write_trace(frame, meta, Path(folder) / "trace.parquet")
        if profiler:
            profiler.disable()
        cpu = usage() - cpu0
    if profiler:
        profiler.dump_stats(profile)
        pstats.Stats(profile).sort_stats("tottime").print_stats(30)
    return cpu, float(meta["cpu_time"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("models", nargs="*", help="models of the replay (default: every model the study ran)")
    parser.add_argument("--results", type=Path, default=ROOT / "results", help="a finished replay study's results")
    parser.add_argument("--dataset", default=str(ROOT.parent / "shared/data/borealtc"), help="borealtc_dir")
    parser.add_argument("--source", default="borealtc", help="the replay's source (its results/traces folder)")
    parser.add_argument("--run", default="asphalt/02", help="the run measured: class/run (asphalt/02: 9.5 s)")
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--set", nargs="*", default=[], help="engine settings tried, key=value (YAML value)")
    parser.add_argument("--profile", help="write a cProfile of one whole case here (one model) and print its top")
    args = parser.parse_args()
    overrides = {k: yaml.safe_load(v) for k, v in (s.split("=", 1) for s in args.set)}
    study = study_costs(args.results, args.source)
    plan = plan_of(args.dataset)
    models = args.models or sorted(study)
    load = open("/proc/loadavg").read().split()[:3]
    print(
        f"# {datetime.datetime.now():%Y-%m-%d %H:%M} {platform.processor() or platform.machine()},"
        f" {os.cpu_count()} cores, load {' '.join(load)}; run {args.run}, {args.repeats} repeat(s)"
        + (f"; settings tried: {overrides}" if overrides else "")
    )
    header = [
        "model",
        "jobs",
        "sim s",
        "job CPU-s",
        "loop CPU-s",
        "bare CPU-s",
        "job/bare",
        "bare (by sim s)",
        "run bare",
        "run loop",
        "run case",
    ]
    print("| " + " | ".join(header) + " |\n|" + "---|" * len(header), flush=True)
    total = {"job": 0.0, "loop": 0.0, "bare": 0.0, "by_sim": 0.0}
    nan = float("nan")
    for model in models:
        params, inputs, name = job_case(plan, args.source, model, args.run, args.results, overrides)
        urdf = str(ROOT / plan.settings.robot.urdf)
        if args.profile:
            whole_case(urdf, inputs, params, name, args.profile)
            return
        engine, scenario, commands = captured_scenario(urdf, inputs, params, name)
        run_sim = len(commands) * scenario.timestep
        bares, cases, loops = [], [], []
        for _ in range(args.repeats):
            bares.append(bare(engine, scenario, commands))
            case, loop = whole_case(urdf, inputs, params, name)
            cases.append(case)
            loops.append(loop)
        run_bare, run_case, run_loop = (statistics.median(v) for v in (bares, cases, loops))
        s = study.get(model, {"jobs": 0, "job": nan, "loop": nan, "sim": nan})
        # the study's bare loops: its runner loops scaled by this run's bare/loop ratio (a run's cost per
        # simulated second depends on its class: DART's asphalt costs three times its ice)
        scaled = s["loop"] * run_bare / run_loop if run_loop > 0 else nan
        by_sim = run_bare * s["sim"] / run_sim
        for key, value in (("job", s["job"]), ("loop", s["loop"]), ("bare", scaled), ("by_sim", by_sim)):
            total[key] += value
        print(
            f"| {model} | {s['jobs']} | {s['sim']:.0f} | {s['job']:.1f} | {s['loop']:.1f} | {scaled:.1f} |"
            f" {s['job'] / scaled:.2f} | {by_sim:.1f} | {run_bare:.2f} | {run_loop:.2f} | {run_case:.2f} |",
            flush=True,
        )
    print(f"| all | | | {total['job']:.0f} | {total['loop']:.0f} | {total['bare']:.0f} | | {total['by_sim']:.0f} |||")
    print(f"# bare loops / 2 cores: {total['bare'] / 2:.0f} s; jobs' CPU / 2: {total['job'] / 2:.0f} s (target 900 s)")


if __name__ == "__main__":
    main()
