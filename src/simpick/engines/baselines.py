"""Two reference models that join the real-data comparison beside the engines.

They are not simulators (no contacts, no suspension, flat rigid ground only, terrain shapes
ignored) and are never scored in the weighted table; they tell a user what a full physics
engine adds over a formula:

``kinematic``  no slip: the body moves at the commanded twist, v = (v_l + v_r) / 2 and
    yaw rate = (v_r - v_l) / track (the paper's Eq. 1 read backwards, so yaw rate = w).
``coulomb``    quasi-static Coulomb skid-steer (:mod:`simpick.coulomb`): the steady twist
    for the commanded rim speeds, from the robot description's contact layout and loads.

Both follow a changing command no faster than friction allows: the twist moves toward its
target so that no wheel contact's velocity changes by more than ``mu g`` per second (the
largest acceleration friction can give a contact point), instead of jumping, which would put
an unbounded spike into the accelerometer. The IMU reading is derived from the planar
motion by :func:`simpick.engines.kinematics.imu_from_kinematics`, as for the engines without an IMU.
"""

from __future__ import annotations

import time
from typing import Annotated, ClassVar

import numpy as np
from pydantic import Field

import simpick
from simpick.engines.base import (
    FRICTION,
    FRICTION_RATIO,
    Calibratable,
    EngineSettings,
    PhysicsRecord,
    Scenario,
    validated_commands,
)
from simpick.engines.kinematics import imu_from_kinematics


class _BaselineSettings(EngineSettings):
    config_block: ClassVar[str] = "baselines"


class CoulombSettings(_BaselineSettings):
    """config ``baselines.coulomb``; the loads and contact layout come from the robot description."""

    # Lateral / longitudinal friction ratio of every wheel contact, in the wheel's frame (elliptic
    # anisotropic Coulomb, simpick.coulomb). 1: isotropic, today's model (gain 0.478 for the Husky).
    # The real Husky's steady gain on hard ground (0.70, notes on BorealTC's 29 runs) is
    # what r ~ 0.63 gives at every (v, w); sandy loam's 0.59 is r ~ 0.78.
    friction_ratio: Annotated[float, Field(gt=0, le=2, allow_inf_nan=False)] = 1.0


class KinematicSettings(_BaselineSettings):
    """config ``baselines.kinematic``."""

    # m: the controller's effective track (config robot.track, the paper's Eq. 1 read backwards)
    track: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 0.555


def _integrate(targets: np.ndarray, points: np.ndarray, max_accel: float, dt: float) -> np.ndarray:
    """Body twists (vx, vy, wz) following ``targets`` with every contact's acceleration <= max_accel."""
    twist = np.zeros(3)
    out = np.empty_like(targets)
    x, y = points[:, 0], points[:, 1]
    for k, target in enumerate(targets):
        delta = target - twist
        # velocity change of each contact point for this twist change
        dx, dy = delta[0] - delta[2] * y, delta[1] + delta[2] * x
        largest = float(np.sqrt(dx * dx + dy * dy).max())
        limit = max_accel * dt
        twist = twist + (delta if largest <= limit else delta * (limit / largest))
        out[k] = twist
    return out


def _record(scenario: Scenario, twists: np.ndarray, wheels: np.ndarray, wall: float, cpu: float) -> PhysicsRecord:
    """Pose by integrating the body twist in the plane at base_link's resting height."""
    dt = scenario.timestep
    n = len(twists)
    x0, y0, yaw0 = scenario.starts[scenario.recorded_robot]
    yaw = yaw0 + np.cumsum(twists[:, 2]) * dt
    c, s = np.cos(yaw), np.sin(yaw)
    vx, vy = c * twists[:, 0] - s * twists[:, 1], s * twists[:, 0] + c * twists[:, 1]
    position = np.stack(
        [x0 + np.cumsum(vx) * dt, y0 + np.cumsum(vy) * dt, np.full(n, scenario.robot.base_height)], axis=1
    )
    quaternion = np.stack([np.cos(yaw / 2), np.zeros(n), np.zeros(n), np.sin(yaw / 2)], axis=1)
    velocity = np.stack([vx, vy, np.zeros(n)], axis=1)
    omega = np.stack([np.zeros(n), np.zeros(n), twists[:, 2]], axis=1)
    specific_force, gyro = imu_from_kinematics(
        quaternion, velocity, omega, scenario.robot.imu_mount, dt, scenario.gravity
    )
    return PhysicsRecord(
        time=dt * np.arange(1, n + 1),
        position=position,
        quaternion=quaternion,
        linear_velocity=velocity,
        angular_velocity=omega,
        wheel_speed=wheels,
        imu_specific_force=specific_force,
        imu_gyro=gyro,
        wall_time=wall,
        cpu_time=cpu,
        steps=n,
    )


class _ReferenceModel:
    name = ""
    settings_model: type[EngineSettings]
    reference_model = True  # not a simulator: kept out of the lab study, validation and scores

    def version(self) -> str:
        return f"simpick {simpick.__version__} {self.name} model"

    def targets(self, scenario: Scenario, settings: EngineSettings, left: np.ndarray, right: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def simulate(self, scenario: Scenario, wheel_commands: np.ndarray) -> PhysicsRecord:
        from simpick.coulomb import contact_layout

        commands = validated_commands(scenario, wheel_commands)[:, 0]
        settings = self.settings_model.of(scenario.settings, self.name)
        radius = scenario.robot.wheel_radius
        cpu0, wall0 = time.process_time(), time.perf_counter()
        left = scenario.robot.side_mean(commands, "left") * radius
        right = scenario.robot.side_mean(commands, "right") * radius
        layout = contact_layout(scenario.robot, points_per_wheel=1)
        mu = float(scenario.ground_friction)
        twists = _integrate(
            self.targets(scenario, settings, left, right),
            layout.points,
            mu * abs(scenario.gravity[2]),
            scenario.timestep,
        )
        wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
        return _record(scenario, twists, commands.copy(), wall, cpu)

    def bare_loop(self, scenario: Scenario, wheel_commands: np.ndarray) -> float:
        start = time.perf_counter()
        self.simulate(scenario, wheel_commands)
        return time.perf_counter() - start


class KinematicModel(_ReferenceModel):
    name = "kinematic"
    settings_model = KinematicSettings
    # The effective track of skid-steer kinematics, the parameter its users calibrate (e.g. Mandow
    # et al. 2007): yaw rate = (v_r - v_l) / track. From the geometric 0.555 m (no slip) to 3 m, a
    # yaw-rate gain of 0.19, below the real Husky's lowest (0.21 on snow, METHOD.md s6).
    calibratable = {"track": Calibratable(0.555, 3.0, why="gain 1 (no slip) down to 0.19, below snow's 0.21")}

    def targets(self, scenario, settings, left, right):
        return np.stack([(left + right) / 2, np.zeros_like(left), (right - left) / settings.track], axis=1)


class CoulombModel(_ReferenceModel):
    name = "coulomb"
    settings_model = CoulombSettings
    # Its one parameter: the friction coefficient, which bounds how fast the twist follows a new
    # command (mu g at every contact); the steady twist does not depend on it (Coulomb's gain is
    # the same for every mu, METHOD.md s6). The loads come from the robot description.
    # The lateral/longitudinal ratio moves the steady gain (0.478 at 1, 0.78 at 0.5, 0.95 at 0.01):
    # base.FRICTION_RATIO, 0.3-1.8 (gain 0.88 to 0).
    calibratable = {"friction": FRICTION, "friction_ratio": FRICTION_RATIO}

    def targets(self, scenario, settings, left, right):
        from simpick.coulomb import CoulombTable, contact_layout

        # Solve each distinct command once (replays hold each wheel-speed sample for many steps).
        pairs, inverse = np.unique(np.stack([left, right], axis=1), axis=0, return_inverse=True)
        layout = contact_layout(scenario.robot, friction_ratio=settings.friction_ratio)
        if len(pairs) <= 64:
            from simpick.coulomb import steady_twist

            solved = np.array([steady_twist(layout, layout.rim_speeds(lft, rgt)) for lft, rgt in pairs])
        else:
            solved = CoulombTable(layout, angles=720).twist(pairs[:, 0], pairs[:, 1])
        return solved[inverse.reshape(-1)]
