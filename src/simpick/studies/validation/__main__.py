"""``python -m simpick.studies.validation ENGINE [CASE ...]``: a config's validation cases run on one
engine and printed, outside the workflow."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import pandas as pd
import yaml

from simpick.inputs.robot import load_from_config
from simpick.studies.validation.cases import Setup, run_case
from simpick.studies.validation.judge import summarise


def main(argv: list[str] | None = None) -> None:
    """``python -m simpick.studies.validation ENGINE [CASE ...]``: run the config's cases and print them."""
    parser = argparse.ArgumentParser(description=main.__doc__)
    parser.add_argument("engine")
    parser.add_argument("cases", nargs="*")
    parser.add_argument("--config", default="config.yaml")
    parser.add_argument("--set", action="append", default=[], help="engine setting key=value (JSON value)")
    args = parser.parse_args(argv)
    config = yaml.safe_load(Path(args.config).read_text())
    settings = dict(config["engines"].get(args.engine) or {})
    for item in args.set:
        key, value = item.split("=", 1)
        try:
            settings[key] = json.loads(value)
        except json.JSONDecodeError:
            settings[key] = value
    setup = Setup(
        engine=args.engine,
        robot=load_from_config(config["robot"]),
        timestep=config["physics"]["timestep"],
        max_wheel_torque=config["robot"]["max_wheel_torque"],
        track=config["robot"]["track"],
        settings=settings,
    )
    cases = config["validation"]["cases"]
    results = [run_case(setup, name, cases[name]) for name in (args.cases or cases)]
    summary = summarise(results, config["validation"]["tolerances"])

    with pd.option_context("display.width", 200, "display.max_columns", 20):
        print(
            summary[
                ["case", "quantity", "engine_value", "analytic_value", "error", "tolerance", "passed", "steps_per_s"]
            ].to_string(index=False, float_format=lambda x: f"{x:.4g}")
        )


if __name__ == "__main__":
    main()
