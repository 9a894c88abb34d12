"""The interface every physics engine adapter implements, and the types it works with.

An adapter (one module per engine) provides *primitives*: it builds a :class:`World` from a
:class:`Scenario` (robot, engine-neutral :class:`~simpick.inputs.terrain.Terrain`, timestep, start
poses, its settings), sets wheel-speed targets, steps and reads the recorded robot's base state.
The one run loop over those primitives, :mod:`simpick.engines.runner`, does everything else for
every engine: command validation, command changes, timing, recording, the IMU from kinematics, the
:class:`PhysicsRecord` and the bare loop of the benchmark. Adding an engine means one module with
its settings model, ``build`` and a world class, and one registry line (:mod:`simpick.engines`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar, NamedTuple, Protocol, Self, runtime_checkable

import numpy as np
from pydantic import BaseModel, ConfigDict, ValidationError, model_validator

from simpick.inputs.robot import RobotSpec
from simpick.inputs.terrain import Terrain

GRAVITY = 9.81  # m/s^2, the value every engine is given


@dataclass(frozen=True)
class Scenario:
    # The robot, read once by simpick.inputs.robot.load_robot: an adapter loads ``robot.urdf`` (the file
    # to load, already normalised where needed), drives ``robot.wheel_joints`` (the driven wheels,
    # in command order) with velocity servos of at most ``max_wheel_torque``, leaves
    # ``robot.passive_joints`` (casters and their swivels) free, spawns ``robot.base_link`` at
    # ``robot.base_height`` and reports that link's pose. See RobotSpec for every field.
    robot: RobotSpec
    # static shapes with the terrain's friction; a terrain file's dict is read into one on creation
    terrain: Terrain
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

    def __post_init__(self) -> None:
        if not isinstance(self.terrain, Terrain):
            object.__setattr__(self, "terrain", Terrain.of(self.terrain))


def engine_step_multiple(time_step: float | None, timestep: float) -> int:
    """Physics steps (``scenario.timestep``) per step of an engine with its own ``time_step`` setting: the
    nearest whole number, at least 1 (None: 1, the engine steps at the run's timestep). The run still has a
    sample per physics step; between two engine steps the engine's state is held, and each engine step
    reads the command of the physics step it starts on. So a timestep sweep (physics.timestep) still moves
    the engine's step where the sweep's is the larger."""
    return 1 if time_step is None else max(1, round(time_step / timestep))


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
            raise InputError(
                f"{cls.config_block}.{engine}", "; ".join(f"{key}: {problem}" for key, problem in found)
            ) from None


@dataclass
class PhysicsRecord:
    """The recorded robot (``Scenario.recorded_robot``, robot 0 unless told otherwise) at every
    physics step; quantities in the world frame unless noted.

    ``imu_specific_force`` and ``imu_gyro`` are in the IMU (= body) frame: the engine's own sensor
    where its world reads one (:attr:`BaseStates.specific_force`), else
    :func:`simpick.engines.kinematics.imu_from_kinematics` of the base kinematics (the runner).
    """

    time: np.ndarray  # (n,) s, time at the end of each step
    position: np.ndarray  # (n, 3) base_link origin
    quaternion: np.ndarray  # (n, 4) w, x, y, z of base_link
    linear_velocity: np.ndarray  # (n, 3) of the base_link origin
    angular_velocity: np.ndarray  # (n, 3)
    # (n, len(robot.driven)) rad/s, joint speeds of the driven wheels in command order, measured (an adapter
    # may read it every few steps and hold it)
    wheel_speed: np.ndarray
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
        raise InputError(
            "wheel_commands",
            f"shape {wheel_commands.shape} does not fit {len(scenario.starts)} robots x {wheels} driven wheels",
        )
    if not 0 <= scenario.recorded_robot < len(scenario.starts):
        raise InputError("recorded_robot", f"{scenario.recorded_robot} is not one of the {len(scenario.starts)} robots")
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

# The wheels' lateral/longitudinal friction ratio, the parameter that moves a skid-steer
# robot's turning (rigid Coulomb's gain does not depend on mu): for the Husky the anisotropic
# Coulomb gain runs from 0.88 at 0.3 through 0.36 at 1.2 and 0.03 at 1.7 to none at 1.8 (the lateral
# friction then outweighs the wheels' turning moment), around every real class's steady gain (0.70
# hard ground: r 0.64; sandy loam 0.59: 0.82; snow's moving turns 0.38: 1.17, its spins 0.04: 1.68).
FRICTION_RATIO = Calibratable(0.3, 1.8, why="anisotropic Coulomb gain 0.88 (r 0.3) to 0 (r 1.8), Husky loads")


class BaseState(NamedTuple):
    """The recorded robot after one step (world frame): what :meth:`World.read` may return."""

    position: Any  # (3,) base_link origin, m
    quaternion: Any  # (4,) w, x, y, z of base_link
    linear_velocity: Any  # (3,) of base_link's origin, m/s
    angular_velocity: Any  # (3,) rad/s
    wheel_speed: Any  # (driven wheels,) joint speeds, rad/s, in command order


@dataclass
class BaseStates:
    """The recorded robot at every step of a run, arrays of :class:`BaseState`'s fields with a
    leading step axis; ``specific_force`` and ``gyro`` (body frame) only from an engine's own IMU."""

    position: np.ndarray  # (n, 3)
    quaternion: np.ndarray  # (n, 4) unit, w x y z
    linear_velocity: np.ndarray  # (n, 3)
    angular_velocity: np.ndarray  # (n, 3)
    wheel_speed: np.ndarray  # (n, driven wheels)
    specific_force: np.ndarray | None = None  # (n, 3) m/s^2, +g on z at rest
    gyro: np.ndarray | None = None  # (n, 3) rad/s

    @classmethod
    def stacked(cls, states: list[BaseState]) -> BaseStates:
        """The arrays of per-step :class:`BaseState` samples."""
        return cls(*(np.array([s[i] for s in states], dtype=float).reshape(len(states), -1) for i in range(5)))


@runtime_checkable
class World(Protocol):
    """One built world (:meth:`Adapter.build`): terrain and ``len(scenario.starts)`` robots, every
    wheel target 0, nothing stepped yet. The runner (:mod:`simpick.engines.runner`) drives it:

    - ``set_wheel_targets(speeds)``: (robots, driven wheels) joint speeds, rad/s, in the order of
      ``scenario.robot.wheel_joints``, held until the next call (called when the command changes);
    - ``step(n)``: ``n`` physics steps of ``scenario.timestep``;
    - ``read()``: the recorded robot (``scenario.recorded_robot``) after the last step, cheaply:
      a :class:`BaseState`, or any sample the world's own ``states`` turns into arrays;
    - ``states(samples) -> BaseStates`` (optional; without it the samples must be BaseStates):
      the arrays of the run from the samples ``read`` returned, one per step, so conversions
      (a centre of mass back to base_link, a rotation matrix to a quaternion) run once, vectorised.

    Optional fast paths: a world whose ``logs_states`` is True records its own state every step
    (Drake's logger): the runner then steps each span of one command with one ``step(n)``, never
    calls ``read``, and asks ``states([])`` at the end. A world with ``rollout(commands) ->
    BaseStates`` steps the whole (steps, robots, wheels) command array itself (MuJoCo's rollout in C,
    its accelerometer and gyro in the result). ``close()`` (optional) frees the engine's objects.
    """

    def set_wheel_targets(self, speeds: np.ndarray) -> None: ...

    def step(self, n: int = 1) -> None: ...

    def read(self) -> Any: ...


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

    # An engine adapter (simpick.engines.runner.Adapter) also has build(scenario) -> World, and
    # its simulate and bare_loop are the runner's; a reference model computes its record itself.

    def simulate(self, scenario: Scenario, wheel_commands: np.ndarray) -> PhysicsRecord:
        """Step the world; ``wheel_commands`` is (steps, robots, driven wheels) joint speeds in
        rad/s, in the order of ``scenario.robot.wheel_joints``."""

    def bare_loop(self, scenario: Scenario, wheel_commands: np.ndarray) -> float:
        """Wall seconds to step the same world the same number of steps under the first
        command, recording nothing: the engine's own speed limit, for the benchmark."""
