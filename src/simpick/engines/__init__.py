"""Registry of physics engine adapters, keyed by the name used in config and paths.

Adapters are imported only when asked for, so a job that runs MuJoCo never imports
PyBullet. Adding an engine: one module implementing :class:`~simpick.engines.base.Engine`
and one line here.
"""

from __future__ import annotations

import importlib

from simpick.engines.base import Engine

ADAPTERS = {
    "pybullet": "simpick.engines.pybullet_engine:PyBulletEngine",
    "mujoco": "simpick.engines.mujoco_engine:MujocoEngine",
    "ode": "simpick.engines.ode_engine:OdeEngine",
    "dart": "simpick.engines.dart_engine:DartEngine",
}


def get_engine(name: str) -> Engine:
    if name not in ADAPTERS:
        raise KeyError(f"unknown engine {name!r}; known engines: {sorted(ADAPTERS)}")
    module, cls = ADAPTERS[name].split(":")
    return getattr(importlib.import_module(module), cls)()


def engine_defaults(name: str) -> dict:
    """The settings an engine accepts, with their defaults (``DEFAULTS`` of its module)."""
    module, _ = ADAPTERS[name].split(":")
    return dict(importlib.import_module(module).DEFAULTS)
