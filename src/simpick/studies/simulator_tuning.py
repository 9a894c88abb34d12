"""The search behind each simulator's tuned profile: within what the simulator exposes, the set-up that passes
mechanics.

``resources/simulators/tuning.yaml`` lists, per simulator, the settings its users can set and the values to
try. Every combination runs the study's validation cases (:mod:`simpick.studies.validation`, the study's robot)
over the simulator's shipped profile with the robot maker's tags; :func:`choose` ranks them by cases passed,
then by how far the isotropic yaw-rate gains lie from the Coulomb gain. The real data take no part: the tuned
profile meets every real run held out. The table written (``resources/simulators/tuning.csv``) is committed with
the command that regenerates it, and ``simulators.yaml`` states the chosen values (a test checks they agree).

    python -m simpick.studies.simulator_tuning [--simulators NAME ...] [--out resources/simulators/tuning.csv]
"""

from __future__ import annotations

import argparse
import itertools
import json
import sys
import time
from pathlib import Path

import pandas as pd
import yaml

COLUMNS = (
    "simulator",
    "candidate",
    "settings",
    "passed",
    "checked",
    "failed",
    "gain_min",
    "gain_max",
    "gain_error",
    "wall_s",
    "chosen",
)


def grid(axes: dict[str, list]) -> list[dict]:
    """Every combination of the axes' values, in the file's order (the first is the shipped set-up's nearest)."""
    names = list(axes)
    return [dict(zip(names, values)) for values in itertools.product(*(axes[n] for n in names))]


def judge(summary: pd.DataFrame, coulomb: float) -> dict:
    """Cases passed and the isotropic turning of one candidate's validation summary."""
    checked = summary[summary.status != "skipped"]
    gains = checked[(checked.quantity == "yaw_rate_gain") & checked.friction_ratio.isna()].engine_value.astype(float)
    failed = sorted(set(checked[~checked.passed.astype(bool)].case))
    return {
        "passed": int(checked.passed.astype(bool).sum()),
        "checked": len(checked),
        "failed": " ".join(failed),
        "gain_min": float(gains.min()) if len(gains) else float("nan"),
        "gain_max": float(gains.max()) if len(gains) else float("nan"),
        "gain_error": float((gains - coulomb).abs().mean() / coulomb) if len(gains) else float("nan"),
    }


def choose(table: pd.DataFrame) -> pd.DataFrame:
    """Mark each simulator's chosen candidate: the most checks passed, then the smallest mean gain error."""
    table = table.copy()
    table["chosen"] = False
    for _, rows in table.groupby("simulator", sort=False):
        best = rows.sort_values(["passed", "gain_error"], ascending=[False, True], na_position="last").index[0]
        table.loc[best, "chosen"] = True
    return table


def main(argv: list[str] | None = None) -> None:
    from simpick.engines.catalog import load_catalog
    from simpick.engines.simulators import SIMULATORS
    from simpick.inputs.robot import load_from_config
    from simpick.studies.validation.cases import Setup, run_case
    from simpick.studies.validation.judge import summarise

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--config", default="config.yaml")
    parser.add_argument("--axes", default="resources/simulators/tuning.yaml")
    parser.add_argument("--simulators", nargs="*", default=None)
    parser.add_argument("--out", default="resources/simulators/tuning.csv")
    args = parser.parse_args(argv)

    config = yaml.safe_load(Path(args.config).read_text())
    catalog = load_catalog(config.get("simulators", {}).get("catalog") or "resources/simulators/simulators.yaml")
    axes = yaml.safe_load(Path(args.axes).read_text())
    robot = load_from_config(config["robot"])
    cases = config["validation"]["cases"]
    tolerances = config["validation"]["tolerances"]
    coulomb = None
    rows = []
    for simulator in args.simulators or list(axes):
        if simulator not in axes or SIMULATORS.get(simulator) is None:
            sys.exit(f"simpick: {args.axes} has no axes for a runnable simulator {simulator!r}")
        shipped = catalog.settings(simulator, "shipped", robot.name)
        for k, candidate in enumerate(grid(axes[simulator])):
            settings = {**shipped, **candidate}
            setup = Setup(
                engine=SIMULATORS[simulator],
                robot=robot,
                timestep=config["physics"]["timestep"],
                max_wheel_torque=config["robot"]["max_wheel_torque"],
                track=config["robot"]["track"],
                settings=settings,
            )
            start = time.perf_counter()
            summary = summarise([run_case(setup, name, cases[name]) for name in cases], tolerances)
            wall = time.perf_counter() - start
            if coulomb is None:
                coulomb = float(summary[summary.quantity == "yaw_rate_gain"].analytic_value.dropna().iloc[0])
            row = {"simulator": simulator, "candidate": k, "settings": json.dumps(candidate, sort_keys=True)}
            row |= judge(summary, coulomb) | {"wall_s": round(wall, 1)}
            rows.append(row)
            print(
                f"{simulator} {candidate}: {row['passed']}/{row['checked']} passed, gains "
                f"{row['gain_min']:.3f}-{row['gain_max']:.3f} ({wall:.0f} s)",
                flush=True,
            )
    table = choose(pd.DataFrame(rows))[list(COLUMNS)]
    old = Path(args.out)
    if args.simulators and old.is_file():  # keep the other simulators' rows
        kept = pd.read_csv(old, comment="#")
        table = pd.concat([kept[~kept.simulator.isin(table.simulator)], table], ignore_index=True)
    header = (
        f"# Tuning candidates per simulator (simpick.studies.simulator_tuning), {robot.name}, the validation of "
        f"{args.config}; regenerate: python -m simpick.studies.simulator_tuning --out {args.out}\n"
    )
    old.write_text(header + table.to_csv(index=False, float_format="%.4g"))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
