"""The search behind each simulator's tuned profile: within what the simulator exposes, the set-up that passes
mechanics.

``resources/simulators/tuning.yaml`` lists, per simulator, the settings its users can set and the values to
try. Every combination runs the study's validation cases (:mod:`simpick.studies.validation`, the study's robot)
over the simulator's shipped profile with the robot maker's tags; :func:`choose` ranks them by cases passed,
then by how far the isotropic yaw-rate gains lie from the Coulomb gain. The real data take no part: the tuned
profile meets every real run held out. The table written (``resources/simulators/tuning.csv``) is committed with
the command that regenerates it, and ``simulators.yaml`` states the chosen values (a test checks they agree).

    python -m simpick.cli.simulator_tuning [--simulators NAME ...] [--out resources/simulators/tuning.csv]
"""

from __future__ import annotations

import itertools
import json
import time
from pathlib import Path

import pandas as pd
from pydantic import Field

from simpick.inputs.robot.settings import RobotParams
from simpick.params import JobParams, NonNegative, PhysicsStep
from simpick.studies.validation.settings import ValidationCase

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


class TuningParams(JobParams):
    """What the search reads of the study: the robot's settings, the physics step, and the validation's cases
    and tolerances (the robot's file is given beside it, as the validation job's input is)."""

    robot: RobotParams
    physics: PhysicsStep
    cases: dict[str, ValidationCase] = Field(description="case name -> its kind and settings, in the config's order")
    tolerances: dict[str, NonNegative] = Field(description="quantity -> tolerance (the config's validation section)")


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


def run(params: TuningParams, urdf: str | Path, catalog, axes: dict, simulators: list[str]) -> pd.DataFrame:
    """Every candidate of each simulator's axes through the study's validation (``params``, the robot described
    by ``urdf``) over the simulator's shipped profile; the table, ranked (:func:`choose`), one row a candidate.
    A simulator without axes or without an engine here is a ValueError naming it."""
    from simpick.engines.simulators import SIMULATORS
    from simpick.studies.validation.cases import Setup, run_case
    from simpick.studies.validation.judge import summarise

    robot = params.robot.spec(urdf)
    cases = params.cases
    coulomb = None
    rows = []
    for simulator in simulators:
        if simulator not in axes or SIMULATORS.get(simulator) is None:
            raise ValueError(f"no axes for a runnable simulator {simulator!r}")
        shipped = catalog.settings(simulator, "shipped", robot.name)
        for k, candidate in enumerate(grid(axes[simulator])):
            setup = Setup(
                engine=SIMULATORS[simulator],
                robot=robot,
                timestep=params.physics.timestep,
                max_wheel_torque=params.robot.max_wheel_torque,
                track=params.robot.track,
                settings={**shipped, **candidate},
            )
            start = time.perf_counter()
            summary = summarise([run_case(setup, name, cases[name]) for name in cases], params.tolerances)
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
    return choose(pd.DataFrame(rows))[list(COLUMNS)]
