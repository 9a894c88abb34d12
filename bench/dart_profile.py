"""Where DART's step time goes on the lab terrains (straight lab motion, config.yaml settings).

    .venv/bin/python bench/dart_profile.py --repeats 3

Per terrain, median over repeats (microseconds per step): the whole world.step() with the
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
    import dartpy as dart

    engine = get_engine("dart")
    built = engine.build(scenario)
    built.set_wheel_targets(commands[0])
    world = built.world
    solver = world.getConstraintSolver()
    lcp = solver.getBoxedLcpSolver()
    if hasattr(lcp, "resetStats"):
        lcp.resetStats()
    group, option = solver.getCollisionGroup(), solver.getCollisionOption()
    result = dart.collision.CollisionResult()
    steps, contacts, t_collide = commands.shape[0], 0, 0.0
    start = time.perf_counter()
    for _ in range(steps):
        world.step(False)
        if collide:
            t0 = time.perf_counter()
            result.clear()
            group.collide(option, result)
            t_collide += time.perf_counter() - t0
            contacts += result.getNumContacts()
    total = time.perf_counter() - start - t_collide
    stats = lcp.getStats() if hasattr(lcp, "getStats") else None
    return total / steps * 1e6, t_collide / steps * 1e6, contacts / steps, stats


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--terrains", nargs="*", default=None)
    parser.add_argument("--duration", type=float, default=None)
    args = parser.parse_args()
    config = yaml.safe_load((ROOT / "config.yaml").read_text())
    terrains = args.terrains or list(config["terrains"])
    for name, scenario, commands in lab_scenarios(config, "dart", terrains, args.duration):
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
            f"{name:7s} step {med['nsgs']:6.0f} us ({1e6 / med['nsgs']:5.0f}/s)  with Dantzig {med['dantzig']:5.0f} us"
            f"  -> friction-cone solve ~{med['nsgs'] - med['dantzig']:4.0f} us"
            f"  collision query {med['collide']:4.0f} us  NSGS sweeps/step {sweeps:4.1f} (at cap {capped:.0%})"
            f"  contacts/step {contacts:.1f}  n {args.repeats}",
            flush=True,
        )


if __name__ == "__main__":
    main()
