"""Where DART's step time goes on the lab terrains (straight lab motion, config.yaml settings), or on
DRIVE steps of the Warthog (``--drive N``: N steps per session, as bench/replay_speed.py builds them).

    .venv/bin/python bench/dart_profile.py --repeats 3
    .venv/bin/python bench/dart_profile.py --drive 2 --repeats 1 [--set solver_sweeps=100 ...]

Per terrain, median over repeats (microseconds of process CPU per step): the whole world.step() with the
configured friction solver (NSGS), the same world with DART's Dantzig LCP instead (what the
step costs without the friction-cone iterations), one extra collision query of the solver's
collision group on the same states (the collision detector's share), NSGS sweeps per step and
the share of steps that stop at the sweep cap, and contacts per step.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))
sys.path.insert(0, str(ROOT / "src"))

from run import lab_scenarios  # noqa: E402

from simpick.engines import get_engine  # noqa: E402


def run(scenario, commands, collide: bool):
    """(us per step, us per collision query, contacts per step, NSGS stats) of ``commands`` (steps,
    robots, wheels), each command set where it changes, as the job does."""
    import dartpy as dart

    from simpick.engines.runner import command_spans

    engine = get_engine("dart")
    built = engine.build(scenario)
    changes = {first: commands[first] for first, _ in command_spans(commands)}
    world = built.world
    solver = world.getConstraintSolver()
    lcp = solver.getBoxedLcpSolver()
    if hasattr(lcp, "resetStats"):
        lcp.resetStats()
    group, option = solver.getCollisionGroup(), solver.getCollisionOption()
    result = dart.collision.CollisionResult()
    steps, contacts, t_collide = commands.shape[0], 0, 0.0
    start = time.process_time()
    for k in range(steps):
        if k in changes:
            built.set_wheel_targets(changes[k])
        world.step(False)
        if collide:
            t0 = time.process_time()
            result.clear()
            group.collide(option, result)
            t_collide += time.process_time() - t0
            contacts += result.getNumContacts()
    total = time.process_time() - start - t_collide
    stats = lcp.getStats() if hasattr(lcp, "getStats") else None
    return total / steps * 1e6, t_collide / steps * 1e6, contacts / steps, stats


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--terrains", nargs="*", default=None)
    parser.add_argument("--duration", type=float, default=None)
    parser.add_argument("--drive", type=int, default=0, help="DRIVE steps per session instead of the lab runs")
    parser.add_argument("--set", nargs="*", default=[], help="engine setting overrides, key=value (YAML value)")
    args = parser.parse_args()
    overrides = {k: yaml.safe_load(v) for k, v in (s.split("=", 1) for s in args.set)}
    if args.drive:
        from replay_speed import drive_cases, load_config

        config = load_config("config/robots/warthog.yaml")
        cases = (
            (name.split("/")[0][15:] + "/" + name.split("/")[1], scenario, commands.reshape(len(commands), 1, -1))
            for name, scenario, commands, _ in drive_cases(config, "dart", args.drive, overrides)
        )
    else:
        config = yaml.safe_load((ROOT / "config.yaml").read_text())
        terrains = args.terrains or list(config["terrains"])
        cases = lab_scenarios(config, "dart", terrains, args.duration, overrides)
    for name, scenario, commands in cases:
        dantzig = type(scenario)(**{**scenario.__dict__, "settings": {**scenario.settings, "lcp_solver": "dantzig"}})
        rows = {"nsgs": [], "dantzig": [], "collide": []}
        sweeps = capped = contacts = None
        for _ in range(args.repeats):
            step, collide, contacts, stats = run(scenario, commands, collide=True)
            rows["collide"].append(collide)
            rows["nsgs"].append(run(scenario, commands, collide=False)[0])
            rows["dantzig"].append(run(dantzig, commands, collide=False)[0])
            sweeps = stats.numIterations / stats.numSolves
            capped = stats.numAcceptedAtCap / stats.numSolves
        med = {k: statistics.median(v) for k, v in rows.items()}
        print(
            f"{name:7s} {commands.shape[0]} steps: step {med['nsgs']:6.0f} us ({1e6 / med['nsgs']:5.0f}/s)"
            f"  with Dantzig {med['dantzig']:5.0f} us"
            f"  -> friction-cone solve ~{med['nsgs'] - med['dantzig']:4.0f} us"
            f"  collision query {med['collide']:4.0f} us  NSGS sweeps/step {sweeps:4.1f} (at cap {capped:.0%})"
            f"  contacts/step {contacts:.1f}  n {args.repeats}",
            flush=True,
        )


if __name__ == "__main__":
    main()
