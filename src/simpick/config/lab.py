"""The lab study's cases: terrains, motions, the CPU load measurement, the reference."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field

from simpick.config.base import Strict
from simpick.inputs.terrain import RULES, TILES
from simpick.simulate.settings import CpuLoad, Motion


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


class Reference(Strict):
    published: str = Field(description="the paper's published figures (its Tables 3, 4, 6-11) as YAML")


__all__ = ["CpuLoad", "Motion", "Reference", "Terrain"]
