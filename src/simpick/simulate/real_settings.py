"""What a real-data case on one model reads, as a typed model: the model's simulation settings
(:class:`simpick.simulate.settings.SimulationParams`) and its terrain class's ground. Apart from
:mod:`simpick.simulate.settings` so that a lab job, which reads no real data, does not depend on the real
data's settings (the rules' code versions follow imports)."""

from __future__ import annotations

from pydantic import ConfigDict, Field

from simpick.real.settings import TerrainClass
from simpick.simulate.settings import SimulationParams


class RealCaseParams(SimulationParams):
    """What a real-data case on one model reads (the plan's simpick.sources.base.real_params): the model's
    simulation settings and its terrain class's ground, under the params' key ``class``."""

    model_config = ConfigDict(populate_by_name=True)

    terrain_class: str
    ground: TerrainClass = Field(alias="class", description="the terrain class's ground and its source")
