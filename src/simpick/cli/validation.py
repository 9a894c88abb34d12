"""``python -m simpick.cli.validation ENGINE [CASE ...]``: the study's validation cases run on one engine
and printed, outside the workflow (for trying an engine setting before putting it in the config)."""

from __future__ import annotations

import argparse
import json

import pandas as pd

from simpick.config import read_study
from simpick.config.load import configured, entry_settings
from simpick.studies.validation.cases import Setup, run_case
from simpick.studies.validation.judge import summarise


def main(argv: list[str] | None = None) -> None:
    """Run the config's validation cases (or the named ones) on ENGINE and print each check."""
    parser = argparse.ArgumentParser(description=main.__doc__)
    parser.add_argument("engine")
    parser.add_argument("cases", nargs="*")
    parser.add_argument("--config", action="append", help="a config file; several are merged in order")
    parser.add_argument("--set", action="append", default=[], help="engine setting key=value (JSON value)")
    args = parser.parse_args(argv)
    study, _ = read_study(args.config or ["config.yaml"])
    engines = configured(study.engines)
    if args.engine not in engines:
        parser.error(f"{args.engine!r} is not an engine of the config; configured: {', '.join(engines)}")
    settings = entry_settings(study.engines, args.engine)
    for item in args.set:
        key, value = item.split("=", 1)
        try:
            settings[key] = json.loads(value)
        except json.JSONDecodeError:
            settings[key] = value
    setup = Setup(
        engine=args.engine,
        robot=study.robot.spec(study.robot.urdf),
        timestep=study.physics.timestep,
        max_wheel_torque=study.robot.max_wheel_torque,
        track=study.robot.track,
        settings=settings,
    )
    cases = study.validation.cases
    unknown = [name for name in args.cases if name not in cases]
    if unknown:
        parser.error(f"no validation case {', '.join(unknown)} in the config; known: {', '.join(cases)}")
    results = [run_case(setup, name, cases[name]) for name in (args.cases or cases)]
    summary = summarise(results, study.validation.tolerances)

    with pd.option_context("display.width", 200, "display.max_columns", 20):
        print(
            summary[
                ["case", "quantity", "engine_value", "analytic_value", "error", "tolerance", "passed", "steps_per_s"]
            ].to_string(index=False, float_format=lambda x: f"{x:.4g}")
        )


if __name__ == "__main__":
    main()
