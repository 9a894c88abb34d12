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


def add_sdf_claims(model, base_link: str, command_track: float, wheel_track: float, ground_mu: float, claims) -> None:
    """The SDF custom elements a Gazebo or Gazebo Classic world carries for its reader (namespace simpick, which
    sdformat keeps and no physics reads): ``simpick:drive`` (the base link the claims are about, the command and
    wheel tracks, the ground's friction) and a ``simpick:yaw_rate_gain`` per claim, on the ``model`` element."""
    import xml.etree.ElementTree as ET

    ET.SubElement(
        model,
        "simpick:drive",
        base_link=base_link,
        command_track=repr(float(command_track)),
        wheel_track=repr(float(wheel_track)),
        ground_friction=repr(float(ground_mu)),
    )
    for c in claims:
        ET.SubElement(
            model,
            "simpick:yaw_rate_gain",
            case=c.case,
            v=repr(float(c.v)),
            w=repr(float(c.w)),
            duration=repr(float(c.duration)),
            gain=repr(float(c.gain)),
        )
