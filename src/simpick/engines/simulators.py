"""Simulators as rows: the simulators a mobile roboticist picks, each run through the engine it ships.

A simulator is not an engine: Gazebo runs DART with its own defaults, Gazebo Classic and Webots run
ODE with theirs, Isaac Sim runs PhysX. simpick reproduces each through its engine's adapter, in three profiles:

* ``shipped``: the engine with the settings the simulator applies by default and, where the robot's
  maker publishes simulator tags (Clearpath's Gazebo tags for the Husky and the Warthog), those tags;
* ``tuned``: the set-up that passes mechanics and comes closest to the real robots, changing only what
  the simulator lets its users set (SDF tags, PROTO fields, MJCF attributes, PhysX attributes, Drake's
  YAML, Genesis's options).

Each is a *model* of the study, named ``<simulator>-<variant>`` (``gazebo_classic-shipped``): it runs the
validation against mechanics and every real-data source like an engine, and never the lab scenario or
the CPU-load runs, whose figures are its engine's (the simulator's own overhead is not reproduced).
This module is the registry, as :mod:`simpick.engines` is the engines': simulator name -> the engine
adapter that reproduces it. The facts, defaults and sources are data
(``resources/simulators/simulators.yaml``, :mod:`simpick.engines.catalog`).
"""

from __future__ import annotations

VARIANTS = ("shipped", "tuned", "calibrated")
# the variants the catalog writes down; the calibrated profile starts from the tuned one
CATALOG_VARIANTS = ("shipped", "tuned")
SEPARATOR = "-"

# simulator -> the engine adapter (simpick.engines.ADAPTERS, or PROFILE_ADAPTERS) that reproduces its physics; None: a
# simulator whose physics simpick cannot reproduce (it keeps its row, with the reason, in the catalog)
SIMULATORS: dict[str, str | None] = {
    "gazebo": "gzphysics",  # gz-sim: gz-physics' dartsim plugin, its default engine, itself (Fortress's build)
    "gazebo_classic": "ode",  # Gazebo Classic 11: ODE by default (the paper's Gazebo)
    "webots": "ode",  # Webots: its own fork of ODE
    "coppeliasim": "pybullet",  # CoppeliaSim: Bullet 2.78 (the paper's choice) by default
    "morse": "pybullet",  # MORSE: Bullet 2.8x inside the Blender Game Engine, 60 Hz with 2 substeps
    "isaac_sim": "physx",  # Isaac Sim / Isaac Lab 2: PhysX 5
    "isaac_lab_newton": "newton",  # Isaac Lab 3 with its Newton backend
    "mujoco": "mujoco",  # MuJoCo itself (with its ROS 2 control bridge)
    "drake": "drake",  # Drake
    "genesis": "genesis",  # Genesis
}


# Adapter settings that describe the robot model rather than the simulator: the wheels' actuators, which a
# model's author writes for any simulator (an MJCF <intvelocity> and its gain, a PhysX or Drake drive's gain,
# Genesis's kv) and the adapter's geometry stand-ins. A profile takes these from the study's engine block
# (robot-specific: the Warthog's servo is stiffer than the Husky's); the catalog sets everything else.
MODEL_SETTINGS: dict[str, tuple[str, ...]] = {
    "mujoco": ("wheel_servo", "wheel_servo_kp", "wheel_servo_gain"),
    "physx": ("wheel_drive_damping", "wheel_prisms"),
    "drake": ("wheel_drive_damping", "mesh_resolution"),
    "newton": ("wheel_drive", "wheel_drive_damping"),
    "genesis": ("wheel_kv",),
}


def model_name(simulator: str, variant: str) -> str:
    """The study's name of a simulator's profile: ``gazebo_classic-shipped``."""
    return f"{simulator}{SEPARATOR}{variant}"


def split(model: str) -> tuple[str, str] | None:
    """(simulator, variant) of a profile's model name; None for an engine or a reference model."""
    simulator, sep, variant = model.partition(SEPARATOR)
    if sep and simulator in SIMULATORS and variant in VARIANTS:
        return simulator, variant
    return None


def is_profile(model: str) -> bool:
    return split(model) is not None


def engine_of(model: str) -> str:
    """The engine adapter that runs ``model``: a profile's simulator's engine, else the model itself."""
    parts = split(model)
    if parts is None:
        return model
    engine = SIMULATORS[parts[0]]
    if engine is None:
        raise KeyError(f"simulator {parts[0]!r} is not reproduced by any engine here")
    return engine
