"""Engines whose dependencies conflict with the study's pins run in their own virtual environment.

``newton[sim]`` needs ``mujoco~=3.17`` (the study pins MuJoCo 4.0.0) and ``genesis-world`` needs
``pillow<12`` (pinned 13) and a torch wheel: each gets a venv of its own, ``.venv-<engine>`` at the
repository root (``make engine-venvs``; ``SIMPICK_ENGINE_VENVS`` names another folder holding them).

The adapter (:class:`IsolatedAdapter`, a :class:`simpick.engines.runner.Adapter`) builds its
native world only where the engine imports. Elsewhere a worker process,
``<venv>/bin/python -m simpick.engines.isolated``, with simpick's own source on its path, holds the
engine: a whole run is one call (the pickled scenario and commands in, the runner's
:class:`~simpick.engines.base.PhysicsRecord` out), so :func:`simpick.engines.runner.simulate`
steps, reads and times the world inside the engine's interpreter, at the engine's own speed, and
its wall and CPU seconds are those of the stepping alone. ``build`` in the study's interpreter
returns a :class:`RemoteWorld` whose primitives are one call each (what the conformance check and
a caller stepping by hand use). The pipes are a pair of their own (an engine that prints to stdout
cannot corrupt them); pickle needs the same Python on both sides, so the venvs are made from the
interpreter that runs the study.

A machine without a venv runs the study without that engine: :func:`require_newton` and
:func:`require_genesis` are the registry's availability checks (``simpick.engines.REQUIREMENTS``)
and raise with the command that installs it.
"""

from __future__ import annotations

import importlib
import importlib.metadata
import importlib.util
import os
import pickle
import subprocess
import sys
from pathlib import Path
from typing import ClassVar

import numpy as np

from simpick.engines import runner
from simpick.engines.base import BaseState, PhysicsRecord, Scenario, validated_commands

# engine -> the Python module it needs
MODULES = {"newton": "newton", "genesis": "genesis"}
SRC = Path(__file__).resolve().parents[2]  # the folder holding the simpick package


def venv_python(engine: str) -> Path:
    root = Path(os.environ.get("SIMPICK_ENGINE_VENVS") or SRC.parent)
    return root / f".venv-{engine}" / "bin" / "python"


def in_process(engine: str) -> bool:
    """Whether the engine's module imports in this interpreter (no venv needed)."""
    return importlib.util.find_spec(MODULES[engine]) is not None


def _require(engine: str) -> None:
    if in_process(engine):
        return
    python = venv_python(engine)
    if not python.exists():
        raise RuntimeError(
            f"{engine} is not installed: its environment {python.parent.parent} is missing; "
            f"create it with `make engine-venvs`"
        )
    check = f"import importlib.util, sys; sys.exit(importlib.util.find_spec({MODULES[engine]!r}) is None)"
    found = subprocess.run([str(python), "-c", check], capture_output=True, timeout=60)
    if found.returncode != 0:
        raise RuntimeError(f"{engine} is not installed in {python.parent.parent}; run `make engine-venvs`")


def require_newton() -> None:
    _require("newton")


def require_genesis() -> None:
    _require("genesis")


def version(engine: str, distribution: str) -> str:
    """The installed version of ``distribution``, from the engine's environment where it is not here."""
    if in_process(engine):
        return importlib.metadata.version(distribution)
    python = venv_python(engine)
    found = subprocess.run(
        [str(python), "-c", f"import importlib.metadata as m; print(m.version({distribution!r}))"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    if found.returncode != 0:
        raise RuntimeError(f"{distribution} not found in {python.parent.parent}: {found.stderr.strip()}")
    return found.stdout.strip()


class _Worker:
    """One engine process, kept for the study process's life: importing an engine and loading its
    compiled kernels takes 10-80 s, so every run of a job (the validation's cases) uses it."""

    _running: ClassVar[dict[str, _Worker]] = {}

    def __init__(self, engine: str):
        python = venv_python(engine)
        child_read, parent_write = os.pipe()  # os.pipe(): (read end, write end)
        parent_read, child_write = os.pipe()
        path = os.pathsep.join([str(SRC), os.environ.get("PYTHONPATH", "")]).rstrip(os.pathsep)
        self.process = subprocess.Popen(
            [str(python), "-m", "simpick.engines.isolated", engine, str(child_read), str(child_write)],
            pass_fds=(child_read, child_write),
            stdout=sys.stderr,
            env=dict(os.environ, PYTHONPATH=path),
        )
        os.close(child_read)
        os.close(child_write)
        self._send = os.fdopen(parent_write, "wb")
        self._receive = os.fdopen(parent_read, "rb")

    @classmethod
    def of(cls, engine: str) -> _Worker:
        worker = cls._running.get(engine)
        if worker is None or worker.process.poll() is not None:
            worker = cls._running[engine] = cls(engine)
        return worker

    def call(self, *message):
        try:
            pickle.dump(message, self._send, protocol=pickle.HIGHEST_PROTOCOL)
            self._send.flush()
            status, value = pickle.load(self._receive)
        except (EOFError, BrokenPipeError, OSError) as exc:
            code = self.process.wait(timeout=30)
            raise RuntimeError(
                f"the {message[0]!r} call's engine process ended (exit {code}); its stderr says why"
            ) from exc
        if status == "error":
            raise RuntimeError(f"in the engine's environment: {value}")
        return value


class RemoteWorld:
    """A world built and stepped in the engine's own interpreter, one call per primitive
    (simpick.engines.base.World)."""

    def __init__(self, engine: str, scenario: Scenario):
        self._worker = _Worker.of(engine)
        self.call = self._worker.call
        self.call("build", scenario)

    def set_wheel_targets(self, speeds: np.ndarray) -> None:
        self.call("set_wheel_targets", np.asarray(speeds, dtype=float))

    def step(self, n: int = 1) -> None:
        self.call("step", int(n))

    def read(self) -> BaseState:
        return self.call("read")

    def close(self) -> None:
        """Drop the world; the process stays for the next one."""
        if self._worker.process.poll() is None:
            self.call("release")


class IsolatedAdapter(runner.Adapter):
    """An adapter whose engine may live in its own venv: ``build_here`` is its native world (the
    subclass writes it); ``build``, ``simulate`` and ``bare_loop`` go to the worker where the engine
    does not import in this interpreter, else to the runner here."""

    distribution: str  # the engine's package on PyPI, for version()

    def version(self) -> str:
        return version(self.name, self.distribution)

    def build_here(self, scenario: Scenario):
        raise NotImplementedError

    def check(self, scenario: Scenario) -> None:
        """Refuse, with :class:`~simpick.errors.InputError`, a scenario the engine's settings cannot run; called
        here before any process starts (a subclass may add to it)."""
        self.settings_model.of(scenario.settings, self.name)

    def build(self, scenario: Scenario):
        self.check(scenario)  # a bad setting fails here, before any process
        if in_process(self.name):
            return self.build_here(scenario)
        return RemoteWorld(self.name, scenario)

    def simulate(self, scenario: Scenario, wheel_commands) -> PhysicsRecord:
        if in_process(self.name):
            return runner.simulate(_Native(self), scenario, wheel_commands)
        return _Worker.of(self.name).call("simulate", scenario, self._checked(scenario, wheel_commands))

    def bare_loop(self, scenario: Scenario, wheel_commands) -> float:
        if in_process(self.name):
            return runner.bare_loop(_Native(self), scenario, wheel_commands)
        return _Worker.of(self.name).call("bare_loop", scenario, self._checked(scenario, wheel_commands))

    def _checked(self, scenario: Scenario, wheel_commands) -> np.ndarray:
        """The commands, with the scenario and settings checked here: bad input is the study's InputError
        (naming the field), not an error text from the engine's process."""
        self.check(scenario)
        return validated_commands(scenario, wheel_commands)


class _Native:
    """The adapter as the runner sees it inside the engine's interpreter: build is the native world."""

    def __init__(self, adapter: IsolatedAdapter):
        self.build = adapter.build_here
        # what the runner's layout check reads (simpick.engines.runner.check_layout)
        self.name, self.simulates_suspension = adapter.name, adapter.simulates_suspension


def _serve(engine: str, read_fd: int, write_fd: int) -> None:
    """The engine process: answer calls until the pipe ends. "simulate" and "bare_loop" are whole
    runs of the runner; "build" then set_wheel_targets / step / read drive one world by hand."""
    from simpick.engines import get_engine

    native = _Native(get_engine(engine))
    receive, send = os.fdopen(read_fd, "rb"), os.fdopen(write_fd, "wb")
    world = None
    while True:
        try:
            name, *args = pickle.load(receive)
        except EOFError:
            return
        try:
            if name == "release":
                world, value = None, None
            elif name == "build":
                world, value = native.build(args[0]), None
            elif name == "simulate":
                value = runner.simulate(native, *args)
            elif name == "bare_loop":
                value = runner.bare_loop(native, *args)
            else:  # set_wheel_targets, step, read
                value = getattr(world, name)(*args)
            reply = ("ok", value)
        except Exception as exc:  # the study's side raises it with this text
            reply = ("error", f"{type(exc).__name__}: {exc}")
        pickle.dump(reply, send, protocol=pickle.HIGHEST_PROTOCOL)
        send.flush()


if __name__ == "__main__":
    _serve(sys.argv[1], int(sys.argv[2]), int(sys.argv[3]))
