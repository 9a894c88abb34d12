"""One engine's stepping speed on the lab terrains, as bench/run.py measures it, but quick.

    .venv/bin/python bench/engine_speed.py dart --repeats 5 --duration 4
    .venv/bin/python bench/engine_speed.py pybullet --terrains gravel --set solver_iterations=50

The straight lab motion (config.yaml motions.straight) over each terrain; prints per terrain the
median, min and max of steps/s for the bare loop (``bare_loop``) and the simulation job's loop
(``simulate``), and the lab real-time factor (harmonic mean over terrains x timestep, as
bench/run.py's rtf_lab_study, but from whichever loop is given). The machine is shared:
compare settings back to back and read medians.
"""

from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(ROOT / "bench"))

from run import lab_scenarios  # noqa: E402 - the benchmark's own lab scenarios, so the figures compare

from simpick.engines import get_engine  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("engine")
    parser.add_argument("--terrains", nargs="*", default=None)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--duration", type=float, default=None, help="s simulated (default: the motion's)")
    parser.add_argument("--loop", choices=("bare", "job", "both"), default="both")
    parser.add_argument("--set", nargs="*", default=[], help="engine setting overrides, key=value (YAML value)")
    args = parser.parse_args()
    config = yaml.safe_load((ROOT / "config.yaml").read_text())
    overrides = {k: yaml.safe_load(v) for k, v in (s.split("=", 1) for s in args.set)}
    engine = get_engine(args.engine)
    terrains = args.terrains or list(config["terrains"])
    dt = config["physics"]["timestep"]
    rates = {"bare": [], "job": []}
    for name, scenario, commands in lab_scenarios(config, args.engine, terrains, args.duration, overrides):
        line = [f"{args.engine:9s} {name:7s}"]
        for loop in ("bare", "job"):
            if args.loop not in (loop, "both"):
                continue
            values = []
            for _ in range(args.repeats):
                if loop == "bare":
                    values.append(commands.shape[0] / engine.bare_loop(scenario, commands))
                else:
                    record = engine.simulate(scenario, commands)
                    values.append(record.steps / record.wall_time)
            med = statistics.median(values)
            rates[loop].append(med)
            line.append(f"{loop} {med:9.0f}/s (min {min(values):.0f} max {max(values):.0f} n {len(values)})")
        print("  ".join(line), flush=True)
    for loop, values in rates.items():
        if values:
            print(f"rtf_lab ({loop} loop, {len(values)} terrains): {len(values) / sum(1 / r for r in values) * dt:.2f}")


if __name__ == "__main__":
    main()
