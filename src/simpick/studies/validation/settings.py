"""A validation case as the config declares it and the validation job reads it: one model, defined here
beside the cases it runs (:mod:`simpick.studies.validation.cases`), which the config's ``validation``
section uses (:mod:`simpick.config.studies`)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from simpick.params import Finite, JobParams, Positive
from simpick.studies.validation.measures import DEFAULT_HEADING, MIN_MEASURED_S, SETTLE_S


class ValidationCase(JobParams):
    """A case with a known mechanical answer (simpick.studies.validation documents the kinds)."""

    kind: Literal["yaw_gain", "straight", "slide", "incline", "rest", "rest_pose", "articulation"] = Field(
        description="yaw_gain: steady yaw rate / w against the Coulomb gain; straight: speed = wheel speed x "
        "radius; slide: locked-wheel deceleration mu g; incline: parked inside the friction ellipse, sliding "
        "by the anisotropic Coulomb law outside it; rest: accelerometer g, gyro 0, no creep; a robot on a "
        "suspension (skipped on others): rest_pose: the chassis level at its resting height; articulation: "
        "coupled rockers twisted on two diagonal blocks h high, the chassis' pitch, roll and height as the "
        "coupling sets them"
    )
    h: Annotated[float, Field(gt=0, le=0.5, allow_inf_nan=False)] | None = Field(
        None, description="m, articulation: the blocks' height (below half the wheel radius)"
    )
    v: Finite | None = Field(None, description="m/s, commanded forward speed (yaw_gain, straight, slide)")
    w: Finite | None = Field(None, description="rad/s, commanded yaw rate (yaw_gain; positive: left)")
    mu: Annotated[float, Field(gt=0, le=10, allow_inf_nan=False)] = Field(
        description="Coulomb coefficient of the flat rigid ground"
    )
    angle_factor: Positive | None = Field(
        None,
        description="incline: the slope as a multiple of atan(mu); whether it must hold or slide follows the "
        "friction ellipse of the set-up's own friction_ratio at the case's heading (ratio 1: it holds below 1)",
    )
    heading: Annotated[float, Field(ge=-180, le=180, allow_inf_nan=False)] = Field(
        DEFAULT_HEADING,
        description="deg; yaw_gain, straight, slide: the robot's start heading; incline: the "
        "downhill direction from the robot's back (the robot starts at heading 0); "
        "rest: refused (it would change nothing)",
    )
    duration: Positive | None = Field(None, description="s simulated; default: the kind's own")
    cruise: Positive | None = Field(None, description="slide: s driven before the wheels lock; default: the kind's")
    friction_ratio: Annotated[float, Field(gt=0, le=2, allow_inf_nan=False)] | None = Field(
        None,
        description="yaw_gain only: the wheels' lateral/longitudinal friction ratio given to the engine's "
        "friction_ratio setting; the analytic gain is then the anisotropic Coulomb one (an "
        "engine without that setting skips the case)",
    )

    @model_validator(mode="after")
    def needed(self):
        need = {
            "yaw_gain": ("v", "w"),
            "straight": ("v",),
            "slide": ("v",),
            "incline": ("angle_factor",),
            "rest": (),
            "rest_pose": (),
            "articulation": ("h",),
        }[self.kind]
        missing = [k for k in need if getattr(self, k) is None]
        if missing:
            raise ValueError(f"a {self.kind} case needs {missing}")
        if self.kind == "yaw_gain" and self.w == 0:
            raise ValueError("a yaw_gain case needs w != 0 (the gain is yaw rate / w)")
        if self.friction_ratio is not None and self.kind != "yaw_gain":
            raise ValueError("friction_ratio is a yaw_gain case's parameter only")
        if self.kind == "rest" and self.heading != 0:
            raise ValueError("a rest case takes no heading (parked on level ground, it would change nothing)")
        if self.kind in ("incline", "rest") and self.duration is not None and self.duration < SETTLE_S + MIN_MEASURED_S:
            raise ValueError(
                f"a {self.kind} case measures after {SETTLE_S:g} s of settling: its duration must be "
                f"at least {SETTLE_S + MIN_MEASURED_S:g} s, got {self.duration:g}"
            )
        return self


__all__ = ["ValidationCase"]
