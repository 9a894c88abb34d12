"""What every model writer shares: the claims a model states and the world it is written from."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from simpick.engines.base import Scenario


@dataclass(frozen=True)
class TurningClaim:
    """A yaw-rate gain the model claims: ``case`` (a validation case's name) run from the file's pose at rest
    with the command (``v`` m/s, ``w`` rad/s) held for ``duration`` s gave ``gain``: the mean yaw rate about the
    base's own z axis over the second half of the run, over ``w``."""

    case: str
    v: float
    w: float
    duration: float
    gain: float


def flat_scenario(robot, settings: Mapping, ground_mu: float, timestep: float, max_wheel_torque: float) -> Scenario:
    """One robot at rest at the origin, heading 0, on a flat floor of friction ``ground_mu`` and no terrain shape:
    the world of the validation's flat cases (simpick.studies.validation.cases)."""
    terrain = {"schema": "simpick.inputs.terrain/1", "name": "flat", "boxes": [], "spheres": [], "friction": ground_mu}
    return Scenario(
        robot=robot,
        terrain=terrain,
        ground_friction=ground_mu,
        timestep=timestep,
        max_wheel_torque=max_wheel_torque,
        starts=((0.0, 0.0, 0.0),),
        settings=dict(settings),
    )
