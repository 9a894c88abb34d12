"""The studies beside the flow: validation against mechanics, the timestep sweep, calibration."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field, field_validator, model_validator

from simpick.config.base import NonNegative, Strict
from simpick.engines import ADAPTERS, REFERENCE_MODELS, get_engine
from simpick.studies.calibration.settings import CalibrationBudget, CalibrationWindows
from simpick.studies.validation.settings import ValidationCase


class Validation(Strict):
    """Every engine against analytic mechanics before any real-data comparison."""

    cases: dict[Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")], ValidationCase] = Field(
        description="case name -> its kind and parameters; editing a case reruns every engine's validation job"
    )
    tolerances: dict[str, NonNegative] = Field(
        description="quantity -> tolerance, one per quantity the cases measure; editing one reruns only the "
        "validation summary and the report"
    )

    @model_validator(mode="after")
    def every_quantity(self):
        from simpick.studies.validation.measures import QUANTITIES

        unknown = sorted(set(self.tolerances) - set(QUANTITIES))
        missing = sorted(set(QUANTITIES) - set(self.tolerances))
        if unknown or missing:
            raise ValueError(
                f"unknown tolerance(s) {unknown}, missing tolerance(s) {missing}; "
                f"one per quantity: {sorted(QUANTITIES)}"
            )
        return self


def timestep_label(timestep: float) -> str:
    """0.0005 -> '0.5ms': a sweep timestep's wildcard and file name (rules/sweep.smk)."""
    return f"{timestep * 1000:g}ms"


class Sweep(Strict):
    """The speed-accuracy sweep: the committed segments at several physics steps."""

    name: Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")] = Field(
        description="the sweep's folder under results/sweeps/"
    )
    timesteps: Annotated[list[Annotated[float, Field(gt=0, le=0.02, allow_inf_nan=False)]], Field(min_length=1)] = (
        Field(
            description="s, the physics steps swept; 20 ms at most (a step that long skips whole contact events of "
            "a 0.33 m wheel at 1 m/s)"
        )
    )

    @field_validator("timesteps")
    @classmethod
    def distinct(cls, timesteps):
        labels = [timestep_label(t) for t in timesteps]
        if len(set(labels)) != len(labels):
            raise ValueError(f"timesteps must be distinct (to 6 significant digits in ms), got {timesteps}")
        return timesteps


class CalibrationTarget(Strict):
    """What a calibrated engine must reach on held-out runs to turn like the real robot
    (simpick.studies.calibration.turning.target_table)."""

    classes: list[str] | None = Field(None, description="terrain classes judged together; null: every class calibrated")
    gain_tolerance: Annotated[float, Field(gt=0, lt=1, allow_inf_nan=False)] = Field(
        0.10, description="the calibrated mean yaw-rate gain within this fraction of the real robot's, per class"
    )
    reference: str = Field(
        "coulomb",
        description="the model whose as-configured yaw-rate error the calibrated "
        "engine must beat (paired test over runs)",
    )


# the fields a calibration job reads are defined once, with its models (simpick.studies.calibration.settings)
class Calibration(CalibrationWindows, CalibrationBudget):
    """Calibrate every real-data model on training runs and judge it on held-out runs: what a user who
    tunes an engine to their robot and ground can expect."""

    enabled: bool = Field(
        False,
        description="true: the default target and the report include the calibration; "
        "`snakemake calibration` runs it either way",
    )
    test_fraction: Annotated[float, Field(gt=0, lt=1, allow_inf_nan=False)] = Field(
        description="share of each terrain class's runs held out (split by run, never within one)"
    )
    models: list[str] | None = Field(
        None,
        description="engines and reference models to calibrate; null: every one "
        "of the study's that declares parameters",
    )
    target: CalibrationTarget = Field(
        CalibrationTarget(), description="what a calibrated engine must reach on held-out runs"
    )

    @model_validator(mode="after")
    def known_parameters(self):
        for engine, params in self.bounds.items():
            if engine not in ADAPTERS and engine not in REFERENCE_MODELS:
                raise ValueError(f"bounds.{engine}: unknown engine; available: {sorted(ADAPTERS | REFERENCE_MODELS)}")
            declared = get_engine(engine).calibratable
            for name, (low, high) in params.items():
                if name not in declared:
                    raise ValueError(
                        f"bounds.{engine}.{name}: {engine} declares no calibratable parameter "
                        f"{name!r}; it declares {sorted(declared)}"
                    )
                if not low < high:
                    raise ValueError(f"bounds.{engine}.{name}: low {low} must be below high {high}")
                if declared[name].log and low <= 0:
                    raise ValueError(f"bounds.{engine}.{name}: searched on a log scale, low must be > 0")
        return self
