"""What every model writer shares: the request it writes from, the claims a model states and the world it is
written from."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from simpick.engines.base import Scenario
from simpick.inputs.robot.settings import RobotParams


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


@dataclass(frozen=True)
class ModelRequest:
    """What a model writer writes from (every writer of :mod:`simpick.engines.simulator_models` takes one):

    ``robot_urdf``: the robot's description, read with ``robot``'s settings (the robot the model holds);
    ``settings``: the profile's adapter settings in full (MuJoCo's, Gazebo's, Drake's, Newton's or Genesis'
    adapter's; the ODE adapter's for Gazebo Classic and Webots, the PhysX adapter's for Isaac Lab, the PyBullet
    adapter's for CoppeliaSim and MORSE); ``ground_mu``: the friction of the ground the robot stands on (a plane,
    Drake's half space, a ground object); ``header_lines``: what the file is and where its values come from, heading
    it before the lines the writer knows (what drives it, its ground, its claims); ``robot``: the study's robot
    settings (the URDF's reading, the command track, the wheels' torque bound); ``timestep``: the study's step
    (Drake's plant steps at the adapter's own, a whole multiple of it); ``claims``: the yaw-rate gains the model
    claims; ``name``: the model's name, as each format holds one: MuJoCo's <mujoco model> ("": the robot's), the
    Gazebo world's name ("": the adapter's) and Gazebo Classic's ("": ``simpick``), each with its characters outside
    [A-Za-z0-9_] made ``_`` (gz-sim puts it in topic names), the Webots world's title and info ("": the robot's), a
    line of Drake's headers ("": none), the first line of a script's docstring ("": the robot's); ``stem``: the
    shared name of a model of several files, each <stem>.<suffix>, by which they name each other ("": the writer's
    simulator's name; a one-file model names no other file and ignores it)."""

    robot_urdf: str | Path
    settings: Mapping
    ground_mu: float
    header_lines: Sequence[str]
    robot: RobotParams
    timestep: float
    claims: Sequence[TurningClaim] = ()
    name: str = ""
    stem: str = ""

    def flat_world(self, robot, settings: Mapping) -> Scenario:
        """:func:`flat_scenario` of ``robot`` (the description read) with the adapter's ``settings`` (validated, as
        a dict) on this request's ground, step and wheel torque bound."""
        return flat_scenario(robot, settings, self.ground_mu, self.timestep, self.robot.max_wheel_torque)


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
