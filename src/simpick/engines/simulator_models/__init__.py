"""The robot as a complete model a simulator opens as it is, beside the settings fragment a user pastes into a model
of their own (:mod:`simpick.engines.simulator_files`).

A fragment needs simpick's own model of the robot around it (the wheel geoms its pairs name, the wheel servos simpick
adds); a model holds all of it: the robot, its actuators, its contacts, the ground and the options, as MuJoCo
Menagerie ships a robot, with the commands that drive it and the figures simpick measured on it in its header. One
module per simulator whose engine can write such a model (MuJoCo: :mod:`.mujoco`, from the adapter's own
``MjSpec``; Gazebo: :mod:`.gazebo`, from the adapter's own SDF world); :data:`WRITERS` names them, and rule
simulator_models writes one per profile of those simulators (:mod:`simpick.studies.simulator_models`)."""

from __future__ import annotations

from simpick.engines.simulator_models.common import TurningClaim
from simpick.engines.simulator_models.gazebo import write_gazebo_model
from simpick.engines.simulator_models.mujoco import write_mujoco_model

# engine -> (the model file's suffix, its writer): a profile whose engine is here gets a model of its own
WRITERS = {"mujoco": ("xml", write_mujoco_model), "gzphysics": ("sdf", write_gazebo_model)}

__all__ = ["WRITERS", "TurningClaim", "write_gazebo_model", "write_mujoco_model"]
