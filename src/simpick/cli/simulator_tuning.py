"""``python -m simpick.cli.simulator_tuning [--simulators NAME ...] [--out resources/simulators/tuning.csv]``:
every candidate of resources/simulators/tuning.yaml through the study's validation
(:mod:`simpick.studies.simulator_tuning`), written as the committed table with the command that
regenerates it. Naming simulators reruns theirs and keeps the other rows of the table."""

from __future__ import annotations

import argparse
import os
import sys
from datetime import date
from pathlib import Path

import pandas as pd
import yaml

from simpick.config import Study, read_study
from simpick.engines.catalog import CatalogError, load_catalog
from simpick.inputs.robot.settings import RobotParams
from simpick.params import PhysicsStep
from simpick.plan.jobs import fields_of
from simpick.studies.simulator_tuning import TuningParams, run


def tuning_params(study: Study) -> TuningParams:
    """The study's slice the search reads (:class:`simpick.studies.simulator_tuning.TuningParams`)."""
    return TuningParams.model_validate(
        {
            "robot": fields_of(study.robot, RobotParams),
            "physics": fields_of(study.physics, PhysicsStep),
            "cases": study.validation.cases,
            "tolerances": study.validation.tolerances,
        }
    )


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--config", action="append", help="a config file; several are merged in order")
    parser.add_argument("--axes", default="resources/simulators/tuning.yaml")
    parser.add_argument("--simulators", nargs="*", default=None)
    parser.add_argument("--out", default="resources/simulators/tuning.csv")
    args = parser.parse_args(argv)

    paths = args.config or ["config.yaml"]
    study, _ = read_study(paths)
    try:
        catalog = load_catalog(study.simulators.catalog)
    except CatalogError as exc:
        sys.exit(f"simpick: {exc}")
    try:
        axes = yaml.safe_load(Path(args.axes).read_text()) or {}
    except (OSError, yaml.YAMLError) as exc:
        sys.exit(f"simpick: cannot read the tuning axes {args.axes}: {exc}")
    try:
        table = run(tuning_params(study), study.robot.urdf, catalog, axes, args.simulators or list(axes))
    except ValueError as exc:
        sys.exit(f"simpick: {args.axes}: {exc}; add its axes or name a simulator it lists")
    old = Path(args.out)
    if args.simulators and old.is_file():  # keep the other simulators' rows
        kept = pd.read_csv(old, comment="#")
        table = pd.concat([kept[~kept.simulator.isin(table.simulator)], table], ignore_index=True)
    robot = study.robot.spec(study.robot.urdf).name
    header = (
        f"# Tuning candidates per simulator (simpick.studies.simulator_tuning), {robot}, "
        f"the validation of {' + '.join(paths)}, measured {date.today()} on {os.cpu_count()} cores; "
        f"regenerate: python -m simpick.cli.simulator_tuning --out {args.out}\n"
    )
    old.write_text(header + table.to_csv(index=False, float_format="%.4g"))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
