"""What the report's jobs read (rules/report.smk: the figure rules, report_evidence and report), as typed
models: the slices of the study the report shows, built by the plan (simpick.plan.report) and validated by
the jobs (:func:`simpick.report.draw.figure_job`, :func:`simpick.report.context.build_context` and
:func:`simpick.report.context.evidence_context`).

Every field has a default, so that a report by hand (a test, a script) gives only what it has; the workflow's
rules give each field (the plan's :func:`simpick.plan.jobs.job_params`). No model here holds the weights but
:class:`ReportParams`: a weight edit reruns the report, neither a figure nor the evidence.
"""

from __future__ import annotations

from typing import Any

from pydantic import Field

from simpick.params import JobParams, NonNegative, Positive
from simpick.real.settings import DeclaredRates, SegmentRules, TerrainClass
from simpick.score.settings import Statistics
from simpick.simulate.settings import Motion


class ReportRobot(JobParams):
    """The robot as the report names it."""

    track: Positive | None = Field(None, description="m, the controller's track (the commanded paths)")
    name: str | None = Field(None, description="the URDF's <robot name>")
    label: str | None = Field(None, description="the robot's name in the report")
    real_data_robot: str | None = Field(
        None, description="whose the committed real data are, where not the study's robot's (None: its own)"
    )


class ReportConfig(JobParams):
    """The slice of the study the report shows and reads: the strips, the commanded paths and the robot."""

    # the config's Terrain model (simpick.config.lab, a layer above the report) validated each strip, whose keys
    # beyond rule, friction and tiles are its rule's own: the report reads the tiles and shows the rest
    terrains: dict[str, dict[str, Any]] = Field({}, description="lab terrain name -> its strip, as configured")
    motions: dict[str, Motion] = Field({}, description="lab motion name -> its open-loop command")
    robot: ReportRobot = Field(ReportRobot(), description="the robot studied")


class ShownDataset(JobParams):
    """A real-data set's dataset, as the report states it (simpick.plan.report: report_datasets)."""

    name: str | None = Field(None, description="the dataset's name")
    label: str | None = Field(None, description="its name in the report")
    source: str = Field("", description="where the data come from")
    folder: str | None = Field(None, description="the dataset folder (a full replay's)")
    declared: DeclaredRates = Field(DeclaredRates(), description="the rates the config declares")
    simulated_imu_hz: Positive | None = Field(None, description="Hz of the simulated IMU the comparison uses")


class ShownDatasets(JobParams):
    segments: ShownDataset | None = Field(None, description="the committed segments' dataset")
    replay: ShownDataset | None = Field(None, description="the full replay's dataset (None: no dataset folder)")


class ReportRealData(JobParams):
    """The real data's settings the report shows: the datasets, the terrain classes, the window and the rules."""

    dataset: str | None = Field(None, description="the dataset of the committed segment table")
    datasets: ShownDatasets = Field(ShownDatasets(), description="each real-data set's dataset and rates")
    classes: dict[str, TerrainClass] = Field({}, description="terrain class -> its ground model, in order")
    window: Positive | None = Field(None, description="s, a full replay's comparison window")
    segment_rules: SegmentRules | None = Field(None, description="how segments are cut from a log")


class OptIn(JobParams):
    """A registered engine the study leaves out and an opt-in config adds (simpick.plan: Plan.opt_in)."""

    switch: str = Field(description="the command that runs it")
    seconds: NonNegative | None = Field(None, description="its jobs' measured wall seconds on one core")
    study_seconds: NonNegative | None = Field(None, description="the configured engines' (None: unmeasured)")


class FigureParams(JobParams):
    """What a figure rule's job reads: the engines, whose order gives their colours (rules/report.smk)."""

    engines: list[str] = Field([], description="the study's engines, then its baselines, each sorted by name")


class PathsFigureParams(FigureParams):
    """Rule figure_paths: the strips and the commanded paths."""

    config: ReportConfig = Field(ReportConfig(), description="the report's slice of the study")


class RealGainFigureParams(FigureParams):
    """Rule figure_real_gain: the terrain classes' order and the statistics of the intervals."""

    statistics: Statistics = Field(Statistics(), description="intervals over independent real runs")
    real_data: ReportRealData = Field(ReportRealData(), description="the terrain classes (their order)")


class ReplayFigureParams(FigureParams):
    """Rule figure_replay: the controller's track (the commanded yaw rate from the wheel commands)."""

    track: Positive = Field(description="m, the controller's track")


class EvidenceParams(JobParams):
    """Rule report_evidence: what the evidence's sections 2-5 and the appendices read (no weight)."""

    config: ReportConfig = Field(ReportConfig(), description="the report's slice of the study")
    statistics: Statistics = Field(Statistics(), description="intervals over independent real runs")
    engines: list[str] = Field([], description="the evidence's engine order (no ranking) and colours")
    real_data: ReportRealData = Field(ReportRealData(), description="the real data's settings")
    title: str | None = Field(None, description="the page's title (None: the robot's question)")


class ReportParams(EvidenceParams):
    """Rule report: the evidence's fields, the weights, the engines left out and where the DRIVE tables and the
    simulators' files are (the rule gives these from its inputs: empty when absent)."""

    weights: dict[str, NonNegative] | None = Field(None, description="metric -> weight (None: the paper's)")
    unavailable: dict[str, str] = Field({}, description="configured engines this machine cannot run -> why")
    opt_in: dict[str, OptIn] = Field({}, description="registered engines an opt-in config adds")
    drive: str = Field("", description="the DRIVE tables' folder ('': no drive_dir)")
    drive_calibration: str = Field("", description="the DRIVE calibration's turning table ('': none)")
    simulators: str = Field("", description="the simulators' folder ('': the study runs none)")


def report_params(params: Any) -> ReportParams:
    """``params`` as the report's model: a :class:`ReportParams` as it is, a mapping validated (less ``code``,
    the rules' rerun trigger). The evidence reads its fields of it: the report's job renders the evidence
    from its own params where rule report_evidence's files are not given (a report by hand)."""
    if isinstance(params, ReportParams):
        return params
    if isinstance(params, EvidenceParams):
        return ReportParams.model_validate(params.model_dump())
    return ReportParams.model_validate({k: v for k, v in dict(params).items() if k != "code"})


__all__ = [
    "EvidenceParams",
    "FigureParams",
    "OptIn",
    "PathsFigureParams",
    "RealGainFigureParams",
    "ReplayFigureParams",
    "ReportConfig",
    "ReportParams",
    "ReportRealData",
    "ReportRobot",
    "ShownDataset",
    "ShownDatasets",
    "report_params",
]
