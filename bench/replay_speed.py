"""Each engine's job loop against its bare loop on the real-data jobs: BorealTC replays and DRIVE steps.

    .venv/bin/python bench/replay_speed.py drive dart drake --steps 3 --repeats 3
    .venv/bin/python bench/replay_speed.py replay mujoco ode --runs 2 --seconds 10
    .venv/bin/python bench/replay_speed.py lab pybullet --repeats 5
    .venv/bin/python bench/replay_speed.py drive dart --set solver_sweeps=100   # a setting tried

The commands are the jobs' own: ``drive`` builds each DRIVE step as ``simpick.simulate.steps.replay_step``
does (the Warthog, config/robots/warthog.yaml merged over config.yaml as Snakemake merges it, the step's
3 s warm-up then its measured wheel speeds, interpolated: a new command every physics step); ``replay``
a BorealTC run as ``simpick.simulate.real.replay_log`` does (the Husky, wheel speeds held at about 6.5 Hz);
``lab`` the straight lab motion (one command). Per case and engine, process CPU seconds (robust on a shared
machine; wall time is printed beside) of:

- ``bare``: the world built by the adapter, stepped under the same commands through its primitives,
  each command set once where it changes, nothing read or recorded: the engine's own cost of that run;
- ``job``: the runner's loop as the job runs it (``engine.simulate``: its stepping, reading and recording,
  the figure a job's record carries as ``cpu_time``);
- ``whole``: (drive only) the whole ``replay_step``: build, stepping, trace, health check; the line then
  gives the step's simulated and real steady speed and yaw rate (what a setting moves).

Ratio = bare CPU / job CPU (the job's speed as a fraction of the bare loop's; >= 0.9 is the target).
Medians over repeats with min-max; steps sampled evenly over the five sessions (``--steps`` per session).
"""

from __future__ import annotations

import argparse
import copy
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(ROOT / "bench"))

from simpick.engines import get_engine  # noqa: E402
from simpick.engines.runner import command_spans  # noqa: E402

DRIVE_DIR = ROOT.parent / "shared/data/drive/calib_data"
BOREALTC_DIR = ROOT.parent / "shared/data/borealtc"


def merged(base: dict, over: dict) -> dict:
    """``over`` merged into ``base`` key by key, as Snakemake merges a --configfile over the config."""
    out = copy.deepcopy(base)
    for key, value in over.items():
        out[key] = merged(out[key], value) if isinstance(value, dict) and isinstance(out.get(key), dict) else value
    return out


def load_config(*extra: str) -> dict:
    config = yaml.safe_load((ROOT / "config.yaml").read_text())
    for path in extra:
        config = merged(config, yaml.safe_load((ROOT / path).read_text()))
    return config


def drive_cases(config: dict, engine: str, per_session: int, overrides: dict, timestep: float | None = None):
    """(name, scenario, commands) of ``per_session`` DRIVE steps per session, spread evenly over each
    session's steps 1.., built as simpick.simulate.steps.replay_step builds them."""
    import pandas as pd

    from simpick.real.drive import _sessions, open_drive, replay_cases, wheel_table
    from simpick.simulate.real import flat_terrain, start_heading
    from simpick.simulate.run import scenario_from
    from simpick.simulate.steps import select_steps, step_samples, step_wheels
    from simpick.sources.base import engine_params

    declared = config["real_data"]["datasets"]["drive"]
    dataset = open_drive(str(DRIVE_DIR), declared=declared, name="drive")
    cases = replay_cases(dataset)
    wheels = pd.concat([wheel_table(s) for s in _sessions(dataset)], ignore_index=True)
    params = engine_params(config, engine)
    params["engine_settings"] = {**params["engine_settings"], **overrides}
    if timestep:
        params["physics"] = {**params["physics"], "timestep": timestep}
    dt, warmup = params["physics"]["timestep"], float(config["drive_replay"]["warmup"])
    urdf = str(ROOT / config["robot"]["urdf"])
    for session_name, group in select_steps(cases).groupby("session", sort=True):
        picks = np.unique(np.linspace(0, len(group) - 1, per_session).round().astype(int))
        for _, case in group.sort_values("step").iloc[picks].iterrows():
            samples = step_samples(wheels, session_name, int(case.step))
            ground = config["real_data"]["classes"][case.terrain_class]
            friction = ground["friction"]
            left, right, _ = step_wheels(samples, case, warmup, dt)
            heading = start_heading(params["seed"], case.dataset, case.terrain_class, case.session, case.case)
            terrain = flat_terrain(case.terrain_class, friction)
            scenario = scenario_from(params, urdf, terrain, ((0.0, 0.0, heading),), ground_friction=friction)
            job = params | {"terrain_class": case.terrain_class, "class": ground}
            yield case.case, scenario, scenario.robot.joint_speeds(left, right), (samples, case, urdf, job)


def replay_cases(config: dict, engine: str, runs: int, seconds: float, overrides: dict, timestep: float | None = None):
    """(name, scenario, commands) of the first ``seconds`` of ``runs`` BorealTC runs per class, built as
    simpick.simulate.real.replay_log builds them."""
    from simpick.real.datasets import find_runs
    from simpick.real.logs.borealtc import read_run
    from simpick.simulate.real import flat_terrain, start_heading
    from simpick.simulate.run import scenario_from
    from simpick.sources.base import engine_params

    params = engine_params(config, engine)
    params["engine_settings"] = {**params["engine_settings"], **overrides}
    if timestep:
        params["physics"] = {**params["physics"], "timestep": timestep}
    dt, track = params["physics"]["timestep"], config["robot"]["track"]
    urdf = str(ROOT / config["robot"]["urdf"])
    by_class: dict[str, list] = {}
    for run in find_runs(BOREALTC_DIR):
        by_class.setdefault(run.terrain_class, []).append(run)
    for terrain_class, found in by_class.items():
        for run in found[:runs]:
            log = read_run(run.imu, run.pro, terrain_class, track=track)
            cmd = log.wheel_commands(track)
            end = min(float(log.imu.time.iloc[-1]), float(cmd.time.iloc[-1]), seconds)
            t = dt * np.arange(int(round(end / dt)))
            held = np.clip(np.searchsorted(cmd.time.to_numpy(), t, side="right") - 1, 0, len(cmd) - 1)
            friction = config["real_data"]["classes"][terrain_class]["friction"]
            heading = start_heading(params["seed"], log.meta.get("dataset"), terrain_class, run.run, log.meta["name"])
            scenario = scenario_from(
                params, urdf, flat_terrain(terrain_class, friction), ((0.0, 0.0, heading),), ground_friction=friction
            )
            commands = scenario.robot.joint_speeds(cmd.v_left.to_numpy()[held], cmd.v_right.to_numpy()[held])
            yield f"{terrain_class}/{run.run}", scenario, commands, None


def lab_cases(config: dict, engine: str, overrides: dict, duration: float | None):
    from run import lab_scenarios

    for name, scenario, commands in lab_scenarios(config, engine, None, duration, overrides):
        yield name, scenario, commands[:, 0], None


def bare(engine, scenario, commands: np.ndarray) -> tuple[float, float]:
    """(CPU s, wall s) of the adapter's world stepped under ``commands`` (steps, wheels), nothing read."""
    commands = commands.reshape(len(commands), 1, -1)
    world = engine.build(scenario)
    try:
        spans = command_spans(commands)
        targets, step = world.set_wheel_targets, world.step
        cpu0, wall0 = time.process_time(), time.perf_counter()
        for first, end in spans:
            targets(commands[first])
            step(end - first)
        return time.process_time() - cpu0, time.perf_counter() - wall0
    finally:
        close = getattr(world, "close", None)
        if close is not None:
            close()


def spread(values: list[float]) -> str:
    return f"{statistics.median(values):8.0f} ({min(values):.0f}-{max(values):.0f})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("source", choices=("drive", "replay", "lab"))
    parser.add_argument("engines", nargs="+")
    parser.add_argument("--steps", type=int, default=2, help="drive: steps per session")
    parser.add_argument("--runs", type=int, default=1, help="replay: runs per terrain class")
    parser.add_argument("--seconds", type=float, default=10.0, help="replay: s of each run")
    parser.add_argument("--duration", type=float, default=None, help="lab: s simulated (default: the motion's)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--timestep", type=float, default=None, help="physics.timestep (default: the config's)")
    parser.add_argument("--loops", default="bare,job", help="which of bare,job,whole to time")
    parser.add_argument("--set", nargs="*", default=[], help="engine setting overrides, key=value (YAML value)")
    args = parser.parse_args()
    overrides = {k: yaml.safe_load(v) for k, v in (s.split("=", 1) for s in args.set)}
    config = load_config("config/robots/warthog.yaml") if args.source == "drive" else load_config()
    loops = args.loops.split(",")
    print(f"# {time.strftime('%Y-%m-%d %H:%M')}  load {open('/proc/loadavg').read().split()[:3]}  {args}")
    for name in args.engines:
        engine = get_engine(name)
        if args.source == "drive":
            cases = drive_cases(config, name, args.steps, overrides, args.timestep)
        elif args.source == "replay":
            cases = replay_cases(config, name, args.runs, args.seconds, overrides, args.timestep)
        else:
            cases = lab_cases(config, name, overrides, args.duration)
        totals = {loop: [0.0] * args.repeats for loop in loops}
        total_steps, sim_s = 0, 0.0
        for case, scenario, commands, job in cases:
            n = len(commands)
            total_steps += n
            sim_s += n * scenario.timestep
            rates: dict[str, list[float]] = {loop: [] for loop in loops}
            answer = ""
            walls: dict[str, list[float]] = {loop: [] for loop in loops}
            for r in range(args.repeats):
                for loop in loops:
                    if loop == "bare":
                        cpu, wall = bare(engine, scenario, commands)
                    elif loop == "job":
                        record = engine.simulate(scenario, commands.reshape(n, 1, -1))
                        cpu, wall = record.cpu_time, record.wall_time
                    else:
                        from simpick.simulate.steps import replay_step

                        samples, row, urdf, params = job
                        cpu0, wall0 = time.process_time(), time.perf_counter()
                        _, out = replay_step(samples, row, urdf, params, float(config["drive_replay"]["warmup"]))
                        cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
                        answer = (
                            f"  sim v {out['sim_v']:.4f} wz {out['sim_yaw_rate']:.4f} ({out['status']})"
                            f" real v {row.v_icp:.4f} wz {row.yaw_rate:.4f}"
                        )
                    rates[loop].append(n / cpu)
                    walls[loop].append(n / wall)
                    totals[loop][r] += cpu
            line = "  ".join(
                f"{loop} {spread(rates[loop])}/s cpu (wall {statistics.median(walls[loop]):.0f})" for loop in loops
            )
            ratio = ""
            if "bare" in rates and "job" in rates:
                ratio = f"  job/bare {statistics.median(rates['job']) / statistics.median(rates['bare']):.3f}"
            print(f"{name:8s} {case:48s} {n:6d} steps  {line}{ratio}{answer}", flush=True)
        summary = []
        for loop in loops:
            rate = [total_steps / t for t in totals[loop]]
            summary.append(f"{loop} {spread(rate)}/s cpu")
        ratio = ""
        if "bare" in totals and "job" in totals:
            r = [b / j for b, j in zip(totals["bare"], totals["job"])]
            ratio = f"  job/bare {statistics.median(r):.3f} ({min(r):.3f}-{max(r):.3f})"
        per_9s = "".join(
            f"  {loop}: {statistics.median(totals[loop]) / sim_s * 9:.2f} cpu s per 9 s step" for loop in loops
        )
        print(
            f"{name:8s} ALL {total_steps} steps  {'  '.join(summary)}{ratio}{per_9s if args.source == 'drive' else ''}"
        )


if __name__ == "__main__":
    main()
