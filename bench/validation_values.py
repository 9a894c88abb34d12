"""The validation cases (config.yaml validation.cases) for one engine, with optional setting
overrides: engine value, analytic value, error, tolerance, pass, steps/s. For comparing an
engine setting's effect on the analytic cases before adopting it.

    .venv/bin/python bench/validation_values.py dart --set solver_tolerance=1e-4
    .venv/bin/python bench/validation_values.py drake --timestep 0.002 --configfile config/robots/warthog.yaml

``--timestep`` replaces physics.timestep (the whole run at that step), ``--configfile`` merges a robot's
config over config.yaml as Snakemake does. The last line gives the cases passed and the process CPU
seconds of all the cases (robust on a shared machine, unlike the wall-based steps/s column).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import pandas as pd
import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from simpick.inputs.robot import load_from_config  # noqa: E402
from simpick.studies.validation.cases import Setup, run_case  # noqa: E402
from simpick.studies.validation.judge import summarise  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("engine")
    parser.add_argument("--cases", nargs="*", default=None)
    parser.add_argument("--set", nargs="*", default=[], help="engine setting overrides, key=value (YAML value)")
    parser.add_argument("--timestep", type=float, default=None, help="physics.timestep (default: the config's)")
    parser.add_argument("--configfile", default=None, help="a config merged over config.yaml (a robot's)")
    args = parser.parse_args()
    sys.path.insert(0, str(ROOT / "bench"))
    from replay_speed import load_config

    config = load_config(*([args.configfile] if args.configfile else []))
    overrides = {k: yaml.safe_load(v) for k, v in (s.split("=", 1) for s in args.set)}
    setup = Setup(
        engine=args.engine,
        robot=load_from_config({**config["robot"], "urdf": str(ROOT / config["robot"]["urdf"])}),
        timestep=args.timestep or config["physics"]["timestep"],
        max_wheel_torque=config["robot"]["max_wheel_torque"],
        track=config["robot"]["track"],
        settings={**(config["engines"].get(args.engine) or {}), **overrides},
    )
    cases = config["validation"]["cases"]
    cpu = time.process_time()
    results = [run_case(setup, name, cases[name]) for name in (args.cases or cases)]
    cpu = time.process_time() - cpu
    summary = summarise(results, config["validation"]["tolerances"])
    pd.set_option("display.width", 200)
    print(
        summary[
            ["case", "quantity", "engine_value", "analytic_value", "error", "tolerance", "passed", "steps_per_s"]
        ].to_string(index=False, float_format=lambda v: f"{v:.4g}")
    )
    print("passed", int(summary.passed.sum()), "of", len(summary), f"cpu {cpu:.1f} s", args)


if __name__ == "__main__":
    main()
