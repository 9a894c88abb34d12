"""The one interface every physics engine adapter implements.

An adapter builds a world from a :class:`Scenario` (robot URDF, engine-neutral terrain,
timestep, start poses) and steps it under open-loop wheel-speed commands, returning a
:class:`PhysicsRecord` at the physics rate. Everything after that (IMU filtering, noise,
health checks, trace files, metrics) is shared code, so adding an engine means writing one
module and one registry line.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

from simpick.robot import RobotSpec

GRAVITY = 9.81  # m/s^2, the value every engine is given


@dataclass(frozen=True)
class Scenario:
    robot: RobotSpec
    terrain: dict
    ground_friction: float
    timestep: float  # s
    max_wheel_torque: float  # N m, per wheel
    starts: tuple[tuple[float, float, float], ...]  # (x, y, yaw) per robot
    settings: dict[str, Any] = field(default_factory=dict)  # engine-specific, from config
    # World gravity, m/s^2. Tilted only by the validation's incline case: tilting gravity by
    # theta about y is the same mechanics as a plane inclined by theta, with no sloped geometry.
    gravity: tuple[float, float, float] = (0.0, 0.0, -GRAVITY)
    # Index into ``starts`` of the robot the record follows (0: the lead robot, as the study
    # records). The world is built the same whichever it is, so running one scenario once per
    # index gives every robot's state at the same steps (the multi-robot conformance tests).
    recorded_robot: int = 0


@dataclass
class PhysicsRecord:
    """The recorded robot (``Scenario.recorded_robot``, robot 0 unless told otherwise) at every
    physics step; quantities in the world frame unless noted.

    ``imu_specific_force`` and ``imu_gyro`` are in the IMU (= body) frame. An engine with a
    native IMU fills them itself; others fill them with
    :func:`simpick.imu.imu_from_kinematics` from the base kinematics.
    """

    time: np.ndarray  # (n,) s, time at the end of each step
    position: np.ndarray  # (n, 3) base_link origin
    quaternion: np.ndarray  # (n, 4) w, x, y, z of base_link
    linear_velocity: np.ndarray  # (n, 3) of the base_link origin
    angular_velocity: np.ndarray  # (n, 3)
    wheel_speed: np.ndarray  # (n, 4) rad/s, measured (an adapter may read it every few steps and hold it)
    imu_specific_force: np.ndarray  # (n, 3) m/s^2, body frame, +g on z at rest
    imu_gyro: np.ndarray  # (n, 3) rad/s, body frame
    wall_time: float  # s spent stepping (no model build, no I/O)
    cpu_time: float  # s of process CPU while stepping
    steps: int


def validated_commands(scenario: Scenario, wheel_commands) -> np.ndarray:
    """(steps, robots, 4) float array matching the scenario's robots, or a clear error."""
    from simpick.errors import InputError

    wheel_commands = np.asarray(wheel_commands, dtype=float)
    if wheel_commands.ndim != 3 or wheel_commands.shape[1:] != (len(scenario.starts), 4):
        raise InputError("wheel_commands", f"shape {wheel_commands.shape} does not fit "
                         f"{len(scenario.starts)} robots x 4 wheels")
    if not 0 <= scenario.recorded_robot < len(scenario.starts):
        raise InputError("recorded_robot", f"{scenario.recorded_robot} is not one of the "
                         f"{len(scenario.starts)} robots")
    return wheel_commands


@dataclass(frozen=True)
class Calibratable:
    """A contact parameter a user tunes, with the bounds calibration searches (simpick.calibration).

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


class Engine(Protocol):
    name: str
    # parameter name -> bounds: what calibration may tune on this engine (simpick.calibration)
    calibratable: dict[str, Calibratable]

    def version(self) -> str:
        """The engine's own version string, for provenance."""

    def simulate(self, scenario: Scenario, wheel_commands: np.ndarray) -> PhysicsRecord:
        """Step the world; ``wheel_commands`` is (steps, robots, 4) wheel speeds in rad/s."""

    def bare_loop(self, scenario: Scenario, wheel_commands: np.ndarray) -> float:
        """Wall seconds to step the same world the same number of steps under the first
        command, recording nothing: the engine's own speed limit, for the benchmark."""
