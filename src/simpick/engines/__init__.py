"""Registry of physics engine adapters, keyed by the name used in config and paths.

Adapters are imported only when asked for, so a job that runs MuJoCo never imports
PyBullet. Adding an engine: one module implementing :class:`~simpick.engines.base.Engine`
(its settings model included: the config check takes it from there) and one line here.
"""

from __future__ import annotations

import importlib

from simpick.engines.base import Engine

ADAPTERS = {
    "pybullet": "simpick.engines.pybullet_engine:PyBulletEngine",
    "mujoco": "simpick.engines.mujoco_engine:MujocoEngine",
    "ode": "simpick.engines.ode_engine:OdeEngine",
    "dart": "simpick.engines.dart_engine:DartEngine",
    "physx": "simpick.engines.physx_engine:PhysxEngine",
    "drake": "simpick.engines.drake_engine:DrakeEngine",
}

# Reference models (simpick.engines.baselines): same interface, but formulas, not simulators.
# They join the real-data comparison (config ``baselines``) and are never scored.
REFERENCE_MODELS = {
    "kinematic": "simpick.engines.baselines:KinematicModel",
    "coulomb": "simpick.engines.baselines:CoulombModel",
}


def get_engine(name: str) -> Engine:
    known = {**ADAPTERS, **REFERENCE_MODELS}
    if name not in known:
        raise KeyError(f"unknown engine {name!r}; known engines: {sorted(ADAPTERS)}, "
                       f"reference models: {sorted(REFERENCE_MODELS)}")
    module, cls = known[name].split(":")
    return getattr(importlib.import_module(module), cls)()

