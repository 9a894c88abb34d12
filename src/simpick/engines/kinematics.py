"""Rigid-body kinematics shared by the engine runner and the trace code: quaternions and
rotation matrices, Euler angles, and the IMU reading an engine without a sensor gets from its
base's motion (:func:`imu_from_kinematics`)."""

from __future__ import annotations

import numpy as np

from simpick.engines.base import GRAVITY


def rotation_matrices(quaternion: np.ndarray) -> np.ndarray:
    """(n, 4) w, x, y, z unit quaternions -> (n, 3, 3) body-to-world rotations."""
    w, x, y, z = np.moveaxis(np.asarray(quaternion, dtype=float), -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


def matrices_to_quaternions(rot: np.ndarray) -> np.ndarray:
    """(n, 3, 3) rotations -> (n, 4) unit quaternions w, x, y, z with w >= 0."""
    m = rot
    trace = np.trace(m, axis1=1, axis2=2)
    candidates = np.stack(
        [
            np.stack([1 + trace, m[:, 2, 1] - m[:, 1, 2], m[:, 0, 2] - m[:, 2, 0], m[:, 1, 0] - m[:, 0, 1]], -1),
            np.stack(
                [
                    m[:, 2, 1] - m[:, 1, 2],
                    1 + m[:, 0, 0] - m[:, 1, 1] - m[:, 2, 2],
                    m[:, 0, 1] + m[:, 1, 0],
                    m[:, 0, 2] + m[:, 2, 0],
                ],
                -1,
            ),
            np.stack(
                [
                    m[:, 0, 2] - m[:, 2, 0],
                    m[:, 0, 1] + m[:, 1, 0],
                    1 - m[:, 0, 0] + m[:, 1, 1] - m[:, 2, 2],
                    m[:, 1, 2] + m[:, 2, 1],
                ],
                -1,
            ),
            np.stack(
                [
                    m[:, 1, 0] - m[:, 0, 1],
                    m[:, 0, 2] + m[:, 2, 0],
                    m[:, 1, 2] + m[:, 2, 1],
                    1 - m[:, 0, 0] - m[:, 1, 1] + m[:, 2, 2],
                ],
                -1,
            ),
        ],
        1,
    )  # (n, 4 candidates, 4): each is 4 q_i q for the i-th largest-component choice
    diag = np.stack([trace, m[:, 0, 0], m[:, 1, 1], m[:, 2, 2]], -1)
    best = np.argmax(diag, axis=1)  # the numerically safest candidate
    quat = candidates[np.arange(len(m)), best]
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    return quat * np.where(quat[:, :1] < 0, -1.0, 1.0)


def euler_rpy(quaternion: np.ndarray) -> np.ndarray:
    """(n, 4) w, x, y, z -> (n, 3) roll, pitch, yaw (rad, ZYX convention)."""
    w, x, y, z = np.moveaxis(np.asarray(quaternion, dtype=float), -1, 0)
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0))
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return np.stack([roll, pitch, yaw], -1)


def imu_from_kinematics(
    quaternion: np.ndarray,
    linear_velocity: np.ndarray,
    angular_velocity: np.ndarray,
    mount: tuple[float, float, float],
    dt: float,
    gravity=(0.0, 0.0, -GRAVITY),
) -> tuple[np.ndarray, np.ndarray]:
    """Specific force and angular rate at an IMU mounted at ``mount`` (body frame).

    For engines with no IMU: the mount point's velocity is v + w x R r; its acceleration
    over each step is the finite difference of that velocity (the robot starts at rest,
    so the velocity before the first step is zero). Subtracting gravity and rotating
    into the body frame gives the accelerometer's reading.
    """
    rot = rotation_matrices(quaternion)
    lever = rot @ np.asarray(mount, dtype=float)
    v_mount = linear_velocity + np.cross(angular_velocity, lever)
    accel = np.diff(v_mount, axis=0, prepend=np.zeros((1, 3))) / dt
    specific_force_world = accel - np.asarray(gravity, dtype=float)
    to_body = np.transpose(rot, (0, 2, 1))
    specific_force = np.einsum("nij,nj->ni", to_body, specific_force_world)
    gyro = np.einsum("nij,nj->ni", to_body, angular_velocity)
    return specific_force, gyro
