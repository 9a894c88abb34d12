"""What rule simulator_calibrate's job reads (:class:`CalibrateParams`)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field

from simpick.inputs.robot.settings import RobotParams
from simpick.params import JobParams, PhysicsStep, Positive


class CalibrateParams(JobParams):
    """What rule simulator_calibrate's job reads."""

    simulator: str
    engine: str
    robot_name: str = Field(description="the robot's URDF <robot name>")
    source: str = Field(description="the real data fitted on (segments-<dataset>, drive-<dataset>)")
    kind: Literal["segments", "replay", "drive"] = Field(
        "segments",
        description="segments: the committed segments' runs; replay: the full replay's runs, their steady "
        "turning windows; drive: DRIVE's steps, each a unit of its own, pooled over the target classes among "
        "the steps' (all of them where none is a target)",
    )
    engine_settings: dict[str, Any] = Field(description="the simulator's tuned profile in full (the fit starts there)")
    physics: PhysicsStep
    robot: RobotParams
    searchable: bool
    why_not: str | None
    space: dict[str, Any] = Field(description="the simulator's search space (SearchSpace)")
    classes: list[str] = Field(description="the firm terrain classes pooled (calibration.target.classes)")
    grounds: dict[str, Annotated[float, Field(gt=0)]] = Field(description="terrain class -> its friction")
    segments_case: dict[str, Any] | None = Field(
        None,
        description="kind segments: the calibrated profile's segments simulate job's params over every segment "
        "(simpick.simulate.real.SegmentsUnitParams, its plan-time settings: the tuned ones); the fit replays the "
        "training runs' turning segments with them, each trial's settings merged as the job merges the fit's",
    )
    replay_cases: dict[str, dict[str, Any]] | None = Field(
        None,
        description="kind replay: per terrain class, the calibrated profile's replay simulate job's params "
        "(simpick.simulate.real.RealUnitParams less its cases, its plan-time settings: the tuned ones); the fit "
        "replays the training runs with them, each trial's settings merged as the job merges the fit's",
    )
    replay_window: Positive = Field(10.0, description="kind replay: s of the held-out comparison's windows")
    replay_windows: Annotated[int, Field(ge=1, le=12)] = Field(
        1,
        description="kind replay: the turning windows per training run the fit replays, each run's first ones "
        "(the run replayed from rest up to the last one's end, as the held-out replay reaches it): one a run "
        "keeps an evaluation near the steady-turn fit's cost (a run's first turning window mostly ends at 10 s)",
    )
    steps_case: dict[str, Any] | None = Field(
        None,
        description="kind drive: the calibrated profile's DRIVE replay params (simpick.simulate.steps.StepsParams, "
        "its plan-time settings: the tuned ones); the fit replays the chosen training steps with them",
    )
    drive_tolerance: Positive | None = Field(
        None,
        description="kind drive: rad/s within which two steps' wheel commands are similar (the DRIVE comparison's "
        "tolerance): a class's spread is its step-to-step repeatability over such pairs, as the table's spread is",
    )
    tolerance: Positive = Field(
        0.005,
        description="gain within which a fit is said to reach the real one, and by which a class's own fit must "
        "beat the pooled one on its training runs to get a file of its own (the engine's noise)",
    )
    max_nfev: Annotated[int, Field(ge=1, le=20)] = Field(
        6,
        description="the pooled fit's evaluations of the residuals (scipy's max_nfev; mujoco.sysid's iterations are "
        "one fewer, its rejected steps held to the same count), each a replay of the training runs' turning "
        "segments; the finite-difference Jacobian adds one evaluation per setting each",
    )
    class_nfev: Annotated[int, Field(ge=0, le=12)] = Field(
        3,
        description="the same for each class's own fit (the pooled fit's settings in the search space's order, as "
        "many as the class's training runs, from the pooled values); 0: none",
    )
    diff_step: Annotated[float, Field(gt=0, lt=0.5)] = Field(
        0.05,
        description="the Jacobian's step, as a share of each setting's range (of its logarithm's for a log "
        "setting; scipy's forward, inward at a bound, mujoco.sysid's away from the nearer bound): well above the "
        "engines' roughness (ODE's gain moves by up to 0.01 between ratios 1e-3 apart), well below the range",
    )
    noise: Positive = Field(
        0.045,
        description="gain: the real robot's run-to-run spread within a class (the committed segments' 0.045, "
        "config verdict.margins.gain_error), the residuals' standard deviation of the intervals where the runs "
        "leave no degree of freedom (as many settings as runs)",
    )
    statistics: dict[str, Any] = Field(
        default_factory=dict,
        description="the study's statistics settings (min_runs, level): a class's held-out errors get their BCa "
        "interval over its held-out runs as the table's held-out column does, none below min_runs runs",
    )
    seed: int = Field(0, description="the study's seed: the bootstrap's resampling")
    drive_commands: Annotated[int, Field(ge=1, le=12)] = Field(
        6,
        description="kind drive: how many training steps the fit replays, each from its warm-up against its own "
        "real gain (the median step by |w| of each of as many equal bins): DRIVE has some 170 training steps, each "
        "a replay of some 7 s",
    )
