"""The one interface every physics engine adapter implements.

An adapter builds a world from a :class:`Scenario` (robot URDF, engine-neutral terrain,
timestep, start poses) and steps it under open-loop wheel-speed commands, returning a
:class:`PhysicsRecord` at the physics rate. Everything after that (IMU filtering, noise,
health checks, trace files, metrics) is shared code, so adding an engine means writing one
module and one registry line.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar, Protocol, Self, runtime_checkable

import numpy as np
from pydantic import BaseModel, ConfigDict, ValidationError, model_validator

from simpick.inputs.robot import RobotSpec

GRAVITY = 9.81  # m/s^2, the value every engine is given


@dataclass(frozen=True)
class Scenario:
    # The robot, read once by simpick.inputs.robot.load_robot: an adapter loads ``robot.urdf`` (the file
    # to load, already normalised where needed), drives ``robot.wheel_joints`` (the driven wheels,
    # in command order) with velocity servos of at most ``max_wheel_torque``, leaves
    # ``robot.passive_joints`` (casters and their swivels) free, spawns ``robot.base_link`` at
    # ``robot.base_height`` and reports that link's pose. See RobotSpec for every field.
    robot: RobotSpec
    terrain: dict
    ground_friction: float
    timestep: float  # s
    max_wheel_torque: float  # N m, per wheel
    starts: tuple[tuple[float, float, float], ...]  # (x, y, yaw) per robot
    # engine-specific: the config's block for this engine (only the settings it changes), or the
    # adapter's settings model itself; the adapter reads it through EngineSettings.of
    settings: Mapping[str, Any] | EngineSettings = field(default_factory=dict)
    # World gravity, m/s^2. Tilted only by the validation's incline case: tilting gravity by
    # theta about y is the same mechanics as a plane inclined by theta, with no sloped geometry.
    gravity: tuple[float, float, float] = (0.0, 0.0, -GRAVITY)
    # Index into ``starts`` of the robot the record follows (0: the lead robot, as the study
    # records). The world is built the same whichever it is, so running one scenario once per
    # index gives every robot's state at the same steps (the multi-robot conformance tests).
    recorded_robot: int = 0


class EngineSettings(BaseModel):
    """An adapter's settings: each a typed field with its default, allowed values and range.

    Each adapter subclasses this (its ``settings_model``) and documents every field where it is
    declared, with the measurement or source behind its default. The config check
    (:mod:`simpick.config`) and the adapter build the same model from the same mapping, so both
    refuse the same values with the same message, naming ``engines.<engine>.<setting>``, the value
    and what is allowed; adapters read typed attributes, with no checks or casts of their own.
    Numbers may come as strings:
    YAML 1.1 reads ``1.0e6`` (no exponent sign) as text, and pydantic's lax mode parses it.
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    config_block: ClassVar[str] = "engines"  # the config section holding these settings

    @model_validator(mode="before")
    @classmethod
    def _known_settings(cls, data: Any) -> Any:
        # one line naming every unknown key and every accepted one (pydantic's own extra check
        # gives a line per key, none of them listing what is accepted)
        if isinstance(data, Mapping):
            unknown = sorted(set(data) - set(cls.model_fields))
            if unknown:
                raise ValueError(f"unknown setting(s) {unknown}; accepted: {sorted(cls.model_fields)}")
        return data

    @classmethod
    def of(cls, settings: Mapping[str, Any] | EngineSettings | None, engine: str) -> Self:
        """The model for ``settings`` (a config block, or the model itself); a bad value raises
        :class:`~simpick.errors.InputError` naming ``<block>.<engine>.<setting>`` and the value."""
        from simpick.errors import InputError, validation_problems

        if isinstance(settings, cls):
            return settings
        try:
            return cls.model_validate(dict(settings or {}))
        except ValidationError as exc:
            found = validation_problems(exc, (cls.config_block, engine))
            if len(found) == 1:
                raise InputError(*found[0]) from None
            raise InputError(f"{cls.config_block}.{engine}",
                             "; ".join(f"{key}: {problem}" for key, problem in found)) from None


@dataclass
class PhysicsRecord:
    """The recorded robot (``Scenario.recorded_robot``, robot 0 unless told otherwise) at every
    physics step; quantities in the world frame unless noted.

    ``imu_specific_force`` and ``imu_gyro`` are in the IMU (= body) frame. An engine with a
    native IMU fills them itself; others fill them with
    :func:`simpick.simulate.imu.imu_from_kinematics` from the base kinematics.
    """

    time: np.ndarray  # (n,) s, time at the end of each step
    position: np.ndarray  # (n, 3) base_link origin
    quaternion: np.ndarray  # (n, 4) w, x, y, z of base_link
    linear_velocity: np.ndarray  # (n, 3) of the base_link origin
    angular_velocity: np.ndarray  # (n, 3)
    wheel_speed: np.ndarray  # (n, len(robot.driven)) rad/s, joint speeds of the driven wheels in command order, measured (an adapter may read it every few steps and hold it)
    imu_specific_force: np.ndarray  # (n, 3) m/s^2, body frame, +g on z at rest
    imu_gyro: np.ndarray  # (n, 3) rad/s, body frame
    wall_time: float  # s spent stepping (no model build, no I/O)
    cpu_time: float  # s of process CPU while stepping
    steps: int


def validated_commands(scenario: Scenario, wheel_commands) -> np.ndarray:
    """(steps, robots, driven wheels) float array matching the scenario, or a clear error."""
    from simpick.errors import InputError

    wheel_commands = np.asarray(wheel_commands, dtype=float)
    wheels = len(scenario.robot.wheel_joints)
    if wheel_commands.ndim != 3 or wheel_commands.shape[1:] != (len(scenario.starts), wheels):
        raise InputError("wheel_commands", f"shape {wheel_commands.shape} does not fit "
                         f"{len(scenario.starts)} robots x {wheels} driven wheels")
    if not 0 <= scenario.recorded_robot < len(scenario.starts):
        raise InputError("recorded_robot", f"{scenario.recorded_robot} is not one of the "
                         f"{len(scenario.starts)} robots")
    return wheel_commands


@dataclass(frozen=True)
class Calibratable:
    """A contact parameter a user tunes, with the bounds calibration searches (simpick.studies.calibration).

    The name ``friction`` is the ground's Coulomb coefficient (``real_data.classes.<c>.friction``);
    any other name is one of the adapter's own settings. ``why`` gives the source of the bounds."""

    low: float
    high: float
    log: bool = False  # search on a log scale (parameters spanning decades)
    why: str = ""


# The ground's Coulomb coefficient, the parameter every engine exposes: from ice (0.05, below
# Wong's 0.1 peak for a tyre on ice) to 1.5, above any dry tyre-road peak (Wong, Theory of Ground
# Vehicles, Table 1.4: 0.8-0.9); log scale, as the classes span a decade.
FRICTION = Calibratable(0.05, 1.5, log=True, why="tyre on ice (Wong Table 1.4: 0.1) to above dry asphalt (0.9)")

# The wheels' lateral/longitudinal friction ratio (issue 20), the parameter that moves a skid-steer
# robot's turning (rigid Coulomb's gain does not depend on mu): for the Husky the anisotropic
# Coulomb gain runs from 0.88 at 0.3 through 0.36 at 1.2 and 0.03 at 1.7 to none at 1.8 (the lateral
# friction then outweighs the wheels' turning moment), around every real class's steady gain (0.70
# hard ground: r 0.64; sandy loam 0.59: 0.82; snow's moving turns 0.38: 1.17, its spins 0.04: 1.68).
FRICTION_RATIO = Calibratable(0.3, 1.8, why="anisotropic Coulomb gain 0.88 (r 0.3) to 0 (r 1.8), Husky loads")


@runtime_checkable
class Engine(Protocol):
    """What the workflow and the shared code use of an adapter (or a reference model).

    tests/test_engines.py checks every registered engine and reference model against it."""

    name: str  # its registry key (simpick.engines), the name in config and result paths
    # Its settings: the config's engines.<name> block (baselines.<name> for a reference model) is
    # validated into this model by simpick.config, and simulate / bare_loop read
    # settings_model.of(scenario.settings, name)
    settings_model: type[EngineSettings]
    # parameter name -> bounds: what calibration may tune on this engine (simpick.studies.calibration);
    # "friction" is the ground's coefficient, every other name a float field of settings_model
    calibratable: dict[str, Calibratable]

    def version(self) -> str:
        """The engine's own version string, for provenance."""

    def simulate(self, scenario: Scenario, wheel_commands: np.ndarray) -> PhysicsRecord:
        """Step the world; ``wheel_commands`` is (steps, robots, driven wheels) joint speeds in
        rad/s, in the order of ``scenario.robot.wheel_joints``."""

    def bare_loop(self, scenario: Scenario, wheel_commands: np.ndarray) -> float:
        """Wall seconds to step the same world the same number of steps under the first
        command, recording nothing: the engine's own speed limit, for the benchmark."""
