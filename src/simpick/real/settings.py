"""The real data's settings as the jobs are given them: a terrain class (its ground, and its source) and the
rules that cut constant-command segments. Defined here, in the real layer, so that the jobs below the config can read
them typed; the config's ``real_data`` section (:mod:`simpick.config.real`) uses these models, so each
field has one definition."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from simpick.params import JobParams, NonNegative, Positive


class Ground(JobParams):
    """A terrain class's ground as the engines see it: rigid and flat, with one friction coefficient."""

    friction: Annotated[float, Field(ge=0, le=10, allow_inf_nan=False)] = Field(
        description="Coulomb coefficient the engines give this class's ground"
    )


class TerrainClass(Ground):
    """A real terrain class as the engines see it: rigid flat ground with one friction coefficient, and
    where the coefficient comes from."""

    source: str = Field(description="where the coefficient comes from (a handbook table, or 'assumption: ...')")


class DeclaredRates(JobParams):
    """What is known of a dataset folder's logging rates before reading it (a file more than 20 % off is
    refused); the config's declared dataset (real_data.datasets) adds what the report says of it."""

    imu_hz: Positive | None = Field(
        None, description="Hz the IMU is known to log at; a file more than 20 % off is refused"
    )
    commands_hz: Positive | None = Field(
        None, description="Hz the wheel commands are known to log at; a file more than 20 % off is refused"
    )


class SteadyRules(JobParams):
    """When a real log's command is steady and turning: what the turning windows of a replayed run read."""

    tolerance: Positive = Field(description="m/s: both wheel commands within this of constant")
    min_turn: Positive = Field(description="rad/s of kinematic yaw rate above which a segment is turning")


class KindCounts(JobParams):
    """A count per kind of segment."""

    straight: Annotated[int, Field(ge=0)] = Field(description="straight segments kept per terrain class")
    turning: Annotated[int, Field(ge=0)] = Field(description="turning segments kept per terrain class")


class SegmentRules(SteadyRules):
    """How constant-command segments are cut from a real log."""

    min_duration: Positive = Field(description="s of constant command after settling, at least")
    max_duration: Positive = Field(description="s compared at most (bounds the study's simulation time)")
    settle: NonNegative = Field(description="s driven before the compared window, to reach the new speed")
    per_kind: Annotated[int, Field(ge=1)] | KindCounts = Field(
        description="the longest straight and turning segments kept per terrain class: one count for both kinds, "
        "or a count per kind ({straight: N, turning: M})"
    )


# the config's drive_replay section is this model (simpick.config.real.DriveReplay subclasses it): the jobs that
# replay step units are given that section whole, so it also holds which models replay the steps and the verdict's
# unit of pairing, which no replay job reads (leaving them out would change every replay job's params, and Snakemake
# would replay every session again)
class StepReplay(JobParams):
    """How step units (DRIVE's steps) are replayed in the engines: which steps, from how long a warm-up."""

    models: list[str] | None = Field(
        None, description="the engines and reference models that replay the steps; default: every configured one"
    )
    every: Annotated[int, Field(ge=1)] = Field(
        1, description="replay every N-th step of each session, counted from step 1 (1: every step)"
    )
    max_steps_per_session: Annotated[int, Field(ge=1)] | None = Field(
        None, description="at most this many of those steps per session, the earliest (None: no limit)"
    )
    warmup: Annotated[float, Field(gt=0, le=20)] = Field(
        3.0,
        description="s driven at the real robot's wheel speeds before each step (the first 1 s a ramp from rest), "
        "to reach the engine's own steady state for them",
    )
    unit: Literal["step", "session"] = Field(
        "step", description="the verdict's unit of pairing: each step, or each session (its steps averaged)"
    )


__all__ = ["DeclaredRates", "Ground", "SegmentRules", "SteadyRules", "StepReplay", "TerrainClass"]
