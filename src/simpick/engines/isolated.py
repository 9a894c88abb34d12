"""Engines whose dependencies conflict with the study's pins run in their own virtual environment.

``newton[sim]`` needs ``mujoco~=3.17`` (the study pins MuJoCo 4.0.0) and ``genesis-world`` needs
``pillow<12`` (pinned 13) and a torch wheel: each gets a venv of its own, ``.venv-<engine>`` at the
repository root (``make engine-venvs``; ``SIMPICK_ENGINE_VENVS`` names another folder holding them).

The study's process keeps the engine-neutral work (scenario, commands, IMU, traces); only the
world lives in the engine's interpreter. :class:`RemoteWorld` starts
``<venv>/bin/python -m simpick.engines.isolated`` with simpick's own source on its path, sends
it the pickled :class:`~simpick.engines.base.Scenario` and then one message per call
(set_wheel_targets, step, read) or one for a whole run (:meth:`RemoteWorld.rollout`: the
commands in, every step's state out as arrays), over a pipe pair of its own (an engine that prints
to stdout cannot corrupt it). Pickle needs the same Python on both sides; the venvs are made from
the interpreter that runs the study. Where the engine imports in the study's own interpreter
(a machine whose pins let it in) the world is built in-process, with no subprocess.

A machine without a venv runs the study without that engine: :func:`require_newton` and
:func:`require_genesis` are the registry's availability checks (``simpick.engines.REQUIREMENTS``)
and raise with the command that installs it.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import pickle
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from simpick.engines.base import PhysicsRecord, Scenario, validated_commands

# engine -> (the module it needs, its adapter "module:class"; the adapter's build_here builds the native world)
ISOLATED = {
    "newton": ("newton", "simpick.engines.newton_engine:NewtonEngine"),
    "genesis": ("genesis", "simpick.engines.genesis_engine:GenesisEngine"),
}


def _adapter(engine: str):
    module, cls = ISOLATED[engine][1].split(":")
    return getattr(importlib.import_module(module), cls)()
FIELDS = ("position", "quaternion", "linear_velocity", "angular_velocity", "wheel_speed")
SRC = Path(__file__).resolve().parents[2]  # the folder holding the simpick package


def venv_python(engine: str) -> Path:
    root = Path(os.environ.get("SIMPICK_ENGINE_VENVS") or SRC.parent)
    return root / f".venv-{engine}" / "bin" / "python"


def in_process(engine: str) -> bool:
    """Whether the engine's module imports in this interpreter (no venv needed)."""
    return importlib.util.find_spec(ISOLATED[engine][0]) is not None


def _require(engine: str) -> None:
    if in_process(engine):
        return
    python = venv_python(engine)
    if not python.exists():
        raise RuntimeError(f"{engine} is not installed: its environment {python.parent.parent} is missing; "
                           f"create it with `make engine-venvs`")
    found = subprocess.run([str(python), "-c", f"import importlib.util, sys; "
                            f"sys.exit(importlib.util.find_spec({ISOLATED[engine][0]!r}) is None)"],
                           capture_output=True, timeout=60)
    if found.returncode != 0:
        raise RuntimeError(f"{engine} is not installed in {python.parent.parent}; run `make engine-venvs`")


def version(engine: str, distribution: str) -> str:
    """The installed version of ``distribution``, from the engine's environment where it is not here."""
    import importlib.metadata

    if in_process(engine):
        return importlib.metadata.version(distribution)
    found = subprocess.run([str(venv_python(engine)), "-c", "import importlib.metadata as m, sys; "
                            f"print(m.version({distribution!r}))"], capture_output=True, text=True, timeout=60)
    if found.returncode != 0:
        raise RuntimeError(f"{distribution} not found in {venv_python(engine).parent.parent}: {found.stderr.strip()}")
    return found.stdout.strip()


def require_newton() -> None:
    _require("newton")


def require_genesis() -> None:
    _require("genesis")


def rollout(world, commands: np.ndarray) -> dict[str, np.ndarray | float]:
    """Step ``world`` under (steps, robots, wheels) ``commands``, reading the recorded robot after
    every step: FIELDS as (steps, ...) arrays, with the wall and CPU seconds of the loop."""
    rows = {k: [] for k in FIELDS}
    previous = None
    cpu0, wall0 = time.process_time(), time.perf_counter()
    for command in commands:
        if previous is None or not np.array_equal(command, previous):
            world.set_wheel_targets(command)
            previous = command
        world.step(1)
        state = world.read()
        for k in FIELDS:
            rows[k].append(state[k])
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    return {**{k: np.asarray(v, dtype=float) for k, v in rows.items()}, "wall_time": wall, "cpu_time": cpu}


def bare(world, command: np.ndarray, steps: int) -> float:
    """Wall seconds for ``steps`` steps under one command, reading nothing."""
    world.set_wheel_targets(command)
    start = time.perf_counter()
    world.step(steps)
    return time.perf_counter() - start


class _Worker:
    """One engine process, kept for the study process's life: importing an engine and loading its
    compiled kernels takes 10-80 s, so every world of a job (the validation's cases) is built in it."""

    _running: dict[str, _Worker] = {}

    def __init__(self, engine: str):
        python = venv_python(engine)
        child_read, parent_write = os.pipe()  # os.pipe(): (read end, write end)
        parent_read, child_write = os.pipe()
        env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(SRC), os.environ.get("PYTHONPATH", "")]).rstrip(os.pathsep))
        self.process = subprocess.Popen(
            [str(python), "-m", "simpick.engines.isolated", engine, str(child_read), str(child_write)],
            pass_fds=(child_read, child_write), stdout=sys.stderr, env=env)
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
            raise RuntimeError(f"the {message[0]!r} call's engine process ended (exit {code}); its stderr says why") \
                from exc
        if status == "error":
            raise RuntimeError(f"in the engine's environment: {value}")
        return value


class RemoteWorld:
    """A world built and stepped in the engine's own interpreter (module docstring)."""

    def __init__(self, engine: str, scenario: Scenario):
        self._worker = _Worker.of(engine)
        self.call = self._worker.call
        self.call("build", scenario)

    def set_wheel_targets(self, speeds: np.ndarray) -> None:
        self.call("set_wheel_targets", np.asarray(speeds, dtype=float))

    def step(self, n: int = 1) -> None:
        self.call("step", int(n))

    def read(self) -> dict[str, np.ndarray]:
        return self.call("read")

    def rollout(self, commands: np.ndarray) -> dict:
        return self.call("rollout", np.asarray(commands, dtype=float))

    def bare(self, command: np.ndarray, steps: int) -> float:
        return self.call("bare", np.asarray(command, dtype=float), int(steps))

    def close(self) -> None:
        """Drop the world; the process stays for the next one."""
        if self._worker.process.poll() is None:
            self.call("release")


def build_world(engine: str, scenario: Scenario):
    """The engine's world: in this interpreter where the engine imports here, else a RemoteWorld."""
    if in_process(engine):
        return _adapter(engine).build_here(scenario)
    return RemoteWorld(engine, scenario)


def simulate(engine: str, scenario: Scenario, wheel_commands: np.ndarray) -> PhysicsRecord:
    """The study's run of one scenario: a rollout of the world, the IMU from the base kinematics."""
    from simpick.simulate.imu import imu_from_kinematics

    wheel_commands = validated_commands(scenario, wheel_commands)
    world = build_world(engine, scenario)
    try:
        out = world.rollout(wheel_commands) if isinstance(world, RemoteWorld) else rollout(world, wheel_commands)
    finally:
        if isinstance(world, RemoteWorld):
            world.close()
    force, gyro = imu_from_kinematics(out["quaternion"], out["linear_velocity"], out["angular_velocity"],
                                      scenario.robot.imu_mount, scenario.timestep, scenario.gravity)
    steps = wheel_commands.shape[0]
    return PhysicsRecord(time=scenario.timestep * np.arange(1, steps + 1), position=out["position"],
                         quaternion=out["quaternion"], linear_velocity=out["linear_velocity"],
                         angular_velocity=out["angular_velocity"], wheel_speed=out["wheel_speed"],
                         imu_specific_force=force, imu_gyro=gyro, wall_time=out["wall_time"],
                         cpu_time=out["cpu_time"], steps=steps)


def bare_loop(engine: str, scenario: Scenario, wheel_commands: np.ndarray) -> float:
    world = build_world(engine, scenario)
    try:
        if isinstance(world, RemoteWorld):
            return world.bare(wheel_commands[0], wheel_commands.shape[0])
        return bare(world, wheel_commands[0], wheel_commands.shape[0])
    finally:
        if isinstance(world, RemoteWorld):
            world.close()


def _serve(engine: str, read_fd: int, write_fd: int) -> None:
    """The engine process: build the world, then answer calls until "close" or the pipe ends."""
    receive, send = os.fdopen(read_fd, "rb"), os.fdopen(write_fd, "wb")
    world = None
    while True:
        try:
            name, *args = pickle.load(receive)
        except EOFError:
            return
        try:
            if name in ("close", "release"):
                world, value = None, None
            elif name == "build":
                world = _adapter(engine).build_here(args[0])
                value = None
            elif name == "rollout":
                value = rollout(world, args[0])
            elif name == "bare":
                value = bare(world, *args)
            else:  # set_wheel_targets, step, read
                value = getattr(world, name)(*args)
            reply = ("ok", value)
        except Exception as exc:  # the study's side raises it with this text
            reply = ("error", f"{type(exc).__name__}: {exc}")
        pickle.dump(reply, send, protocol=pickle.HIGHEST_PROTOCOL)
        send.flush()
        if name == "close":
            return


if __name__ == "__main__":
    _serve(sys.argv[1], int(sys.argv[2]), int(sys.argv[3]))
