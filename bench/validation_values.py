"""The validation cases (config.yaml validation.cases) for one engine, with optional setting
overrides: engine value, analytic value, error, tolerance, pass, steps/s. For comparing an
engine setting's effect on the analytic cases before adopting it.

    .venv/bin/python bench/validation_values.py dart --set solver_tolerance=1e-4
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import pandas as pd
import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from simpick.inputs.robot import load_robot  # noqa: E402
from simpick.studies.validation.cases import Setup, run_case  # noqa: E402
from simpick.studies.validation.judge import summarise  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("engine")
    parser.add_argument("--cases", nargs="*", default=None)
    parser.add_argument("--set", nargs="*", default=[], help="engine setting overrides, key=value (YAML value)")
    args = parser.parse_args()
    config = yaml.safe_load((ROOT / "config.yaml").read_text())
    overrides = {k: yaml.safe_load(v) for k, v in (s.split("=", 1) for s in args.set)}
    setup = Setup(
        engine=args.engine,
        robot=load_robot(ROOT / config["robot"]["urdf"]),
        timestep=config["physics"]["timestep"],
        max_wheel_torque=config["robot"]["max_wheel_torque"],
        track=config["robot"]["track"],
        settings={**(config["engines"][args.engine] or {}), **overrides},
    )
    cases = config["validation"]["cases"]
    results = [run_case(setup, name, cases[name]) for name in (args.cases or cases)]
    summary = summarise(results, config["validation"]["tolerances"])
    pd.set_option("display.width", 200)
    print(
        summary[
            ["case", "quantity", "engine_value", "analytic_value", "error", "tolerance", "passed", "steps_per_s"]
        ].to_string(index=False, float_format=lambda v: f"{v:.4g}")
    )
    print("passed", int(summary.passed.sum()), "of", len(summary))


if __name__ == "__main__":
    main()
