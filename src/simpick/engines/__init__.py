"""Registry of physics engine adapters, keyed by the name used in config and paths.

Adapters are imported only when asked for, so a job that runs MuJoCo never imports
PyBullet. Adding an engine: one module with a subclass of :class:`simpick.engines.runner.Adapter`
(its settings model, ``calibratable``, ``version()`` and ``build(scenario)`` returning a world with the
primitives of :class:`simpick.engines.base.World`; the config check takes the settings model from
there, the runner does the rest) and a line here and in ``REQUIREMENTS``; tests/conformance.py
checks it.
"""

from __future__ import annotations

import importlib
import importlib.util

from simpick.engines.base import Engine

ADAPTERS = {
    "pybullet": "simpick.engines.pybullet_engine:PyBulletEngine",
    "mujoco": "simpick.engines.mujoco_engine:MujocoEngine",
    "ode": "simpick.engines.ode_engine:OdeEngine",
    "dart": "simpick.engines.dart_engine:DartEngine",
    "physx": "simpick.engines.physx_engine:PhysxEngine",
    "drake": "simpick.engines.drake_engine:DrakeEngine",
    # in their own environments (simpick.engines.isolated), opt-in: config/engines/newton_genesis.yaml
    "newton": "simpick.engines.newton_engine:NewtonEngine",
    "genesis": "simpick.engines.genesis_engine:GenesisEngine",
}

# Engines that run only behind simulators' profiles (simpick.engines.simulators), never as engines of the study:
# not in the config's engines: block, the lab scenario or the CPU-load runs. gz-physics is DART under Gazebo's
# own settings, a compiled program (make gzphysics), and the study already measures DART as an engine (dartpy),
# so the Gazebo (gz-sim) profiles are its only rows. A study runs them wherever the engine can run.
PROFILE_ADAPTERS = {
    "gzphysics": "simpick.engines.gzphysics_engine:GzPhysicsEngine",
}

# Reference models (simpick.engines.baselines): same interface, but formulas, not simulators.
# They join the real-data comparison (config ``baselines``) and are never scored.
REFERENCE_MODELS = {
    "kinematic": "simpick.engines.baselines:KinematicModel",
    "coulomb": "simpick.engines.baselines:CoulombModel",
}


# What each adapter needs beyond simpick itself, checked at planning time (unavailable()): a Python
# module found on the path, or "module:function" called to load a shared library. Found, not
# imported: importing pydrake or sapien takes 0.7-0.9 s, too long for every plan; an install that
# is found but broken fails in its first job, with the import error.
REQUIREMENTS = {
    "pybullet": "pybullet",
    "mujoco": "mujoco",
    "ode": "simpick.engines._ode:load",
    "dart": "dartpy",
    "physx": "sapien",
    "drake": "pydrake",
    "gzphysics": "simpick.engines.gzphysics_engine:require_program",
    # their own venvs (make engine-venvs): found there, or importable here
    "newton": "simpick.engines.isolated:require_newton",
    "genesis": "simpick.engines.isolated:require_genesis",
}
# the engines installed as extras of pyproject.toml (their wheels do not fit every machine)
EXTRAS = ("physx", "drake")


def unavailable(names) -> dict[str, str]:
    """Engine name -> why it cannot run on this machine, for the engines among ``names`` that
    cannot (an empty dict when all can). The study runs without them and its report says so."""
    from simpick.engines.simulators import engine_of

    found = {}
    for name in names:
        need = REQUIREMENTS.get(engine_of(name))
        if need is None:
            continue
        module, _, function = need.partition(":")
        if function:
            try:
                getattr(importlib.import_module(module), function)()
            except Exception as exc:  # the loader's own message says what is missing
                found[name] = f"{type(exc).__name__}: {exc}"
        elif importlib.util.find_spec(module) is None:
            extra = f".[{engine_of(name)}]" if engine_of(name) in EXTRAS else "."
            found[name] = (
                f"Python module {module!r} is not installed; install it with "
                f"pip install -c constraints.txt -e '{extra}'"
            )
    return found


def get_engine(name: str) -> Engine:
    """The adapter of an engine, a reference model or a simulator's profile (``gazebo-shipped``:
    its simulator's engine, simpick.engines.simulators); the profile's settings come with the scenario."""
    from simpick.engines.simulators import engine_of

    name = engine_of(name)
    known = {**ADAPTERS, **PROFILE_ADAPTERS, **REFERENCE_MODELS}
    if name not in known:
        raise KeyError(
            f"unknown engine {name!r}; known engines: {sorted(ADAPTERS)}, profiles' engines: "
            f"{sorted(PROFILE_ADAPTERS)}, reference models: {sorted(REFERENCE_MODELS)}"
        )
    module, cls = known[name].split(":")
    return getattr(importlib.import_module(module), cls)()
