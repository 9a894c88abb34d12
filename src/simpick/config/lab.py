"""The lab study's cases: terrains, motions, the CPU load measurement, the reference."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field

from simpick.config.base import Finite, Positive, Strict
from simpick.inputs.terrain import RULES, TILES


class Terrain(BaseModel):
    """A lab terrain strip; the keys beyond these are its rule's own parameters (simpick.inputs.terrain)."""

    model_config = ConfigDict(extra="allow")  # the rule's own parameters
    rule: Literal[tuple(RULES)] = Field(
        description="how the strip is built: flat tiles, plywood layers or a "  # type: ignore[valid-type]
        "gravel bed"
    )
    friction: Annotated[float, Field(ge=0, le=10, allow_inf_nan=False)] = Field(
        description="Coulomb coefficient of the strip's surface (the paper's values)"
    )
    tiles: Annotated[int, Field(ge=1, le=100)] = Field(TILES, description="the strip's length in 1 m x 1 m tiles")


class Motion(Strict):
    """An open-loop command held for the whole run, as the paper's controller drove it."""

    v: Finite = Field(description="m/s, commanded forward speed")
    w: Finite = Field(description="rad/s, commanded yaw rate (positive: left)")
    duration: Positive = Field(description="s simulated")
    start: tuple[Finite, Finite, Finite] = Field(
        description="x (m), y (m), yaw (rad) of the start, relative to the strip (which spans x 0..tiles m)"
    )


class CpuLoad(Strict):
    """The paper's CPU-load scenarios: CPU seconds per simulated second, % of one core."""

    terrain: str = Field(description="the lab terrain driven (one of terrains)")
    motion: str = Field(description="the motion driven (one of motions)")
    duration: Positive = Field(description="s simulated per repeat")
    repeats: Annotated[int, Field(ge=1)] = Field(description="repeats per scenario; the median is reported")
    robots_average: Annotated[int, Field(ge=1)] = Field(description="robots in one world, the paper's Scenario 1")
    robots_intense: Annotated[int, Field(ge=1)] = Field(description="robots in one world, the paper's Scenario 2")
    spacing: Positive = Field(description="m between robots in the convoy")


class Reference(Strict):
    published: str = Field(description="the paper's published figures (its Tables 3, 4, 6-11) as YAML")
