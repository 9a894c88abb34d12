"""The one run loop of every engine, over the primitives of its adapter (simpick.engines.base.World).

:func:`simulate` checks the commands, builds the world, sets the wheel targets whenever the command
changes, steps, reads the recorded robot after every step, times the stepping alone (wall and process
CPU: no model build, no conversion, no I/O), derives the IMU from the base's kinematics where the
engine has none, and returns the :class:`~simpick.engines.base.PhysicsRecord`. :func:`bare_loop` steps
the same world under the first command recording nothing: the engine's own speed limit. An adapter
subclasses :class:`Adapter` and writes ``build`` (and its world class); the reference models
(simpick.engines.baselines) compute their record from formulas and have no world.
"""

from __future__ import annotations

import gc
import time
from typing import Any

import numpy as np

from simpick.engines.base import BaseStates, Calibratable, EngineSettings, PhysicsRecord, Scenario, validated_commands
from simpick.engines.kinematics import imu_from_kinematics


def command_spans(commands: np.ndarray) -> list[tuple[int, int]]:
    """(first step, end step) of each run of equal commands, in order: a command is set once per span."""
    changes = np.flatnonzero(np.any(np.diff(commands, axis=0, prepend=np.nan) != 0, axis=(1, 2))).tolist()
    return list(zip(changes, changes[1:] + [commands.shape[0]]))


def _close(world: Any) -> None:
    close = getattr(world, "close", None)
    if close is not None:
        close()


def check_layout(adapter: Any, scenario: Scenario) -> None:
    """Refuse, in one line, a robot layout the adapter does not simulate: passive suspension
    (rockers, couplings) needs an adapter whose ``simulates_suspension`` is True."""
    from simpick.errors import InputError

    robot = scenario.robot
    if robot.suspension and not getattr(adapter, "simulates_suspension", False):
        raise InputError(
            f"engines.{adapter.name}",
            f"does not simulate passive suspension, and {robot.name} has {[s.joint for s in robot.suspension]}",
            "leave this engine out of the study for this robot (engines:)",
        )


def simulate(adapter: Any, scenario: Scenario, wheel_commands) -> PhysicsRecord:
    """Step ``adapter``'s world under ``wheel_commands`` (steps, robots, driven wheels), rad/s."""
    commands = validated_commands(scenario, wheel_commands)
    steps = commands.shape[0]
    check_layout(adapter, scenario)
    world = adapter.build(scenario)
    try:
        rollout = getattr(world, "rollout", None)
        samples: list = []
        if rollout is not None:  # the engine steps the whole run itself
            cpu0, wall0 = time.process_time(), time.perf_counter()
            states = rollout(commands)
            wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
        else:
            targets, step, read, keep = world.set_wheel_targets, world.step, world.read, samples.append
            logs = getattr(world, "logs_states", False)
            spans = command_spans(commands)
            # no cyclic garbage collection while stepping (as timeit): the loop makes no reference cycles,
            # and every sample it keeps (a few tuples a step) would otherwise be traversed again and again
            # by the collector's passes over the growing list
            collecting = gc.isenabled()
            gc.disable()
            try:
                cpu0, wall0 = time.process_time(), time.perf_counter()
                for first, end in spans:
                    targets(commands[first])
                    if logs:
                        step(end - first)
                    else:
                        for _ in range(end - first):
                            step()
                            keep(read())
                wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
            finally:
                if collecting:
                    gc.enable()
            finish = getattr(world, "states", None)
            states = finish(samples) if finish is not None else BaseStates.stacked(samples)
    finally:
        _close(world)
    dt = scenario.timestep
    if states.specific_force is None:
        specific_force, gyro = imu_from_kinematics(
            states.quaternion,
            states.linear_velocity,
            states.angular_velocity,
            scenario.robot.imu_mount,
            dt,
            scenario.gravity,
        )
    else:
        specific_force, gyro = states.specific_force, states.gyro
    return PhysicsRecord(
        time=dt * np.arange(1, steps + 1),
        position=states.position,
        quaternion=states.quaternion,
        linear_velocity=states.linear_velocity,
        angular_velocity=states.angular_velocity,
        wheel_speed=states.wheel_speed,
        imu_specific_force=specific_force,
        imu_gyro=gyro,
        wall_time=wall,
        cpu_time=cpu,
        steps=steps,
    )


def bare_loop(adapter: Any, scenario: Scenario, wheel_commands) -> float:
    """Wall seconds to step the world as many steps as ``wheel_commands`` has, under its first
    command, recording nothing (the benchmark's engine speed)."""
    commands = validated_commands(scenario, wheel_commands)
    check_layout(adapter, scenario)
    world = adapter.build(scenario)
    try:
        world.set_wheel_targets(commands[0])
        step = world.step
        start = time.perf_counter()
        step(commands.shape[0])
        return time.perf_counter() - start
    finally:
        _close(world)


class Adapter:
    """Base of every engine adapter: ``simulate`` and ``bare_loop`` are the runner's.

    A subclass sets ``name`` (its registry key), ``settings_model`` (its settings, each field with
    the measurement or source behind it), ``calibratable`` and writes ``version()`` and
    ``build(scenario) -> World`` (simpick.engines.base.World)."""

    name: str
    settings_model: type[EngineSettings]
    calibratable: dict[str, Calibratable]
    # True once build() models RobotSpec.suspension (limits, damping, friction) and RobotSpec.couplings
    simulates_suspension: bool = False

    def version(self) -> str:
        raise NotImplementedError

    def build(self, scenario: Scenario) -> Any:
        raise NotImplementedError

    def simulate(self, scenario: Scenario, wheel_commands) -> PhysicsRecord:
        return simulate(self, scenario, wheel_commands)

    def bare_loop(self, scenario: Scenario, wheel_commands) -> float:
        return bare_loop(self, scenario, wheel_commands)
