"""The robot as a complete model a simulator opens as it is, beside the settings fragment a user pastes into a model
of their own (:mod:`simpick.engines.simulator_files`).

A fragment needs simpick's own model of the robot around it (the wheel geoms its pairs name, the wheel servos simpick
adds); a model holds all of it: the robot, its actuators, its contacts, the ground and the options, as MuJoCo
Menagerie ships a robot, with the commands that drive it and the figures simpick measured on it in its header. One
module per simulator whose engine can write such a model (MuJoCo: :mod:`.mujoco`, one MJCF file from the adapter's
own ``MjSpec``; Gazebo: :mod:`.gazebo`, one SDF world from the adapter's own; Drake: :mod:`.drake`, a URDF with
Drake's tags, the ground's SDFormat file and the plant's YAML; Gazebo Classic: :mod:`.gazebo_classic`, an SDF 1.7
world; Webots: :mod:`.webots`, a .wbt world; Newton: :mod:`.newton_script` and Genesis: :mod:`.genesis_script`, a
Python script that builds the robot with the simulator's own API, beside the URDF it loads; Isaac Sim:
:mod:`.isaac_lab`, a script of Isaac Lab's configuration classes, CoppeliaSim: :mod:`.coppeliasim`, a ZeroMQ
remote-API script, and MORSE: :mod:`.morse`, a ``morse.builder`` script that builds the robot from its parts, none
of the three opened here); each writer takes one :class:`ModelRequest` (what a model is written from), and
:data:`WRITERS` names them by simulator (Gazebo Classic and Webots share the ODE adapter, each with a format of its
own), and rule simulator_models writes one model per profile of those simulators
(:mod:`simpick.studies.simulator_models`), where the profile's engine is configured."""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

from simpick.engines import gzphysics_engine
from simpick.engines.simulator_models.common import ModelRequest, TurningClaim
from simpick.engines.simulator_models.coppeliasim import write_coppeliasim_model
from simpick.engines.simulator_models.drake import write_drake_model
from simpick.engines.simulator_models.gazebo import write_gazebo_model
from simpick.engines.simulator_models.gazebo_classic import write_gazebo_classic_model
from simpick.engines.simulator_models.genesis_script import write_genesis_model
from simpick.engines.simulator_models.isaac_lab import write_isaac_lab_model
from simpick.engines.simulator_models.morse import write_morse_model, writes_morse
from simpick.engines.simulator_models.mujoco import write_mujoco_model
from simpick.engines.simulator_models.newton_script import write_newton_model
from simpick.engines.simulator_models.webots import write_webots_model


def _always(robot) -> bool:
    return True


def _converts(robot) -> bool:
    """sdformat's URDF conversion runs here (the gzphysics program, read at call time) and the robot has no
    coupled joints, which an SDF world cannot hold without a plugin."""
    return gzphysics_engine.PROGRAM.is_file() and not robot.couplings


def _diff_drive(robot) -> bool:
    """A differential drive's plugin (gz-sim's DiffDrive, Gazebo Classic's gazebo_ros_diff_drive) drives the robot:
    each side's joints at one speed, (v -+ w s / 2) / r, so every driven joint rolls it forward at a positive speed,
    with one wheel radius and as many wheels on each side."""
    driven = robot.driven
    sides = [sum(w.side == s for w in driven) for s in ("left", "right")]
    return (
        bool(driven)
        and all(w.axis_sign == 1 for w in driven)
        and len({w.radius for w in driven}) == 1
        and sides[0] == sides[1]
    )


def _gazebo_classic(robot) -> bool:
    """What the Gazebo Classic writer builds: sdformat's URDF conversion here, no casters, a differential drive."""
    return _converts(robot) and not robot.casters and _diff_drive(robot)


def _unsuspended(robot) -> bool:
    """No passive suspension nor coupling: what the Newton, Genesis, Isaac Lab and CoppeliaSim scripts build (the
    adapters' joint friction and couplings have no counterpart there)."""
    return not (robot.suspension or robot.couplings)


def _plain_wheels(robot) -> bool:
    """The robot's moving joints are its driven wheels on its base (what the Webots writer builds)."""
    return not (robot.suspension or robot.casters or robot.couplings)


class ModelWriter(NamedTuple):
    """How a simulator's model is written: ``suffix``, that of the file that opens it; ``writer``, the simulator's
    writer, which takes a :class:`ModelRequest` and returns its model's one file's text (that file's suffix:
    ``suffix``) or {suffix: text}, a model of several files (:meth:`write` calls it); ``opened_here``, whether the
    tests open it with the simulator's own loader (False: no loader of the simulator installs here, so its fields
    are checked against the catalog's quoted values instead, and the report says so beside its link); ``writes``,
    whether it can write the study's robot (a :class:`~simpick.inputs.robot.RobotSpec`)."""

    suffix: str
    writer: Callable[[ModelRequest], str | dict[str, str]]
    opened_here: bool
    writes: Callable[..., bool] = _always

    def write(self, *args, **kwargs) -> dict[str, str]:
        """The model of ``ModelRequest(*args, **kwargs)`` (robot_urdf, settings, ground_mu, header_lines; robot,
        timestep, claims, name, stem) as {suffix: text}, one file per suffix, each named <stem>.<suffix> (``stem``:
        the profile's name, by which a model's files name each other)."""
        request = ModelRequest(*args, **kwargs)
        files = self.writer(request)
        return {self.suffix: files} if isinstance(files, str) else files


# simulator -> its model's writer: each profile of a simulator here gets a model of its own, keyed by simulator
# because two simulators share an engine (Gazebo Classic's and Webots' profiles both run on the ODE adapter)
WRITERS = {
    "mujoco": ModelWriter("xml", write_mujoco_model, opened_here=True),
    "gazebo": ModelWriter("sdf", write_gazebo_model, opened_here=True, writes=_diff_drive),
    "drake": ModelWriter("urdf", write_drake_model, opened_here=True),
    "gazebo_classic": ModelWriter("world", write_gazebo_classic_model, opened_here=False, writes=_gazebo_classic),
    "webots": ModelWriter("wbt", write_webots_model, opened_here=False, writes=_plain_wheels),
    "isaac_lab_newton": ModelWriter("py", write_newton_model, opened_here=True, writes=_unsuspended),
    "genesis": ModelWriter("py", write_genesis_model, opened_here=True, writes=_unsuspended),
    "isaac_sim": ModelWriter("py", write_isaac_lab_model, opened_here=False, writes=_unsuspended),
    "coppeliasim": ModelWriter("py", write_coppeliasim_model, opened_here=False, writes=_unsuspended),
    # MORSE's wheeled robot: two or four driven cylinder wheels on a box chassis, no casters, suspension or couplings
    "morse": ModelWriter("py", write_morse_model, opened_here=False, writes=writes_morse),
}


def not_opened_note(label: str) -> str:
    """The words beside the link of a model whose simulator has no loader here (``label``: the catalog's name)."""
    return f"fields checked; not opened in {label} here"


__all__ = [
    "WRITERS",
    "ModelRequest",
    "ModelWriter",
    "TurningClaim",
    "not_opened_note",
    "write_coppeliasim_model",
    "write_drake_model",
    "write_gazebo_classic_model",
    "write_gazebo_model",
    "write_genesis_model",
    "write_isaac_lab_model",
    "write_morse_model",
    "write_mujoco_model",
    "write_newton_model",
    "write_webots_model",
]
