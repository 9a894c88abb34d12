"""How results are judged: accuracy, the simulators, the statistics over runs, the verdict's margins
and mechanics gate."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from simpick.config.base import Strict
from simpick.score.settings import Statistics, Verdict


class Accuracy(Strict):
    reference: Literal["real", "paper", "own"] = Field(
        description="what the IMU accuracy scores rest on: real (BorealTC: the committed segments, or the full "
        "replay when borealtc_dir is set), paper (its one lab test, gravel/straight) or own (own_logs)"
    )


class Simulators(Strict):
    """The simulators as rows (simpick.engines.simulators): each run through its engine as it ships and as tuned."""

    catalog: str = Field(
        "resources/simulators/simulators.yaml",
        description="the simulator catalog: facts, sources and the two profiles of each simulator",
    )
    run: list[str] | None = Field(
        None,
        description="simulators whose profiles the study runs; null: every one whose engine the study "
        "runs (an engine the study leaves out leaves its simulators out, named in the report)",
    )
    variants: list[Literal["shipped", "tuned", "calibrated"]] = Field(
        ["shipped", "tuned", "calibrated"],
        description="which profiles of each simulator run; calibrated: fitted on training runs of the real robot "
        "(needs the study's calibration section and its committed segments)",
    )
    calibration: str = Field(
        "resources/simulators/calibration.yaml",
        description="per simulator, the settings its users can set that move the steady turning, each with its "
        "bounds and source: the calibrated profile's search space (simpick.studies.simulator_calibration)",
    )
    drive: bool = Field(
        False,
        description="replay the DRIVE steps (drive_dir) with the profiles too; off by default: each profile "
        "adds its engine's replay time (docs/drive.md)",
    )


__all__ = ["Accuracy", "Simulators", "Statistics", "Verdict"]
