"""The robot as a complete model a simulator opens as it is, beside the settings fragment a user pastes into a model
of their own (:mod:`simpick.engines.simulator_files`).

A fragment needs simpick's own model of the robot around it (the wheel geoms its pairs name, the wheel servos simpick
adds); a model holds all of it: the robot, its actuators, its contacts, the ground and the options, as MuJoCo
Menagerie ships a robot, with the commands that drive it and the figures simpick measured on it in its header. One
module per simulator whose engine can write such a model (MuJoCo: :mod:`.mujoco`, one MJCF file from the adapter's
own ``MjSpec``; Gazebo: :mod:`.gazebo`, one SDF world from the adapter's own; Drake: :mod:`.drake`, a URDF with
Drake's tags, the ground's SDFormat file and the plant's YAML; Newton: :mod:`.newton_script` and Genesis:
:mod:`.genesis_script`, a Python script that builds the robot with the simulator's own API, beside the URDF it
loads); :data:`WRITERS` names them, and rule simulator_models writes one model per profile of those simulators
(:mod:`simpick.studies.simulator_models`), where the profile's engine is configured."""

from __future__ import annotations

from simpick.engines.simulator_models.common import TurningClaim
from simpick.engines.simulator_models.drake import write_drake_model
from simpick.engines.simulator_models.gazebo import write_gazebo_model
from simpick.engines.simulator_models.genesis_script import write_genesis_model
from simpick.engines.simulator_models.mujoco import write_mujoco_model
from simpick.engines.simulator_models.newton_script import write_newton_model


def _mujoco_files(*args, stem: str, **kwargs) -> dict[str, str]:
    """MuJoCo's model is one file."""
    return {"xml": write_mujoco_model(*args, **kwargs)}


def _gazebo_files(*args, stem: str, **kwargs) -> dict[str, str]:
    """Gazebo's model is one SDF world."""
    return {"sdf": write_gazebo_model(*args, **kwargs)}


# engine -> (the suffix of the model's file that opens it, its writer): a profile whose engine is here gets a model
# of its own. A writer returns {suffix: text}, one file per suffix, each named <stem>.<suffix> (``stem``: the
# profile's name, by which a model's files name each other)
WRITERS = {
    "mujoco": ("xml", _mujoco_files),
    "gzphysics": ("sdf", _gazebo_files),
    "drake": ("urdf", write_drake_model),
    "newton": ("py", write_newton_model),
    "genesis": ("py", write_genesis_model),
}

__all__ = [
    "WRITERS",
    "TurningClaim",
    "write_drake_model",
    "write_gazebo_model",
    "write_genesis_model",
    "write_mujoco_model",
    "write_newton_model",
]
