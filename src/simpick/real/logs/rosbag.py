"""ROS 1 (.bag) and ROS 2 (bag folder: sqlite3 or mcap) logs, read with ``rosbags``
(pure Python; no ROS installation needed).

IMU: ``sensor_msgs/msg/Imu`` (angular_velocity rad/s, linear_acceleration m/s^2 specific
force, REP-145: z up, +9.81 at rest). Commands, by message type:

  * ``geometry_msgs/msg/Twist``        linear.x, angular.z  -> v, w   (body)
  * ``geometry_msgs/msg/TwistStamped`` twist.linear.x, twist.angular.z -> v, w
  * ``nav_msgs/msg/Odometry``          twist.twist.linear.x, .angular.z -> v, w
  * ``sensor_msgs/msg/JointState``     wheel velocities (rad/s) x ``wheel_radius`` ->
    v_left, v_right: the mean over the joints whose names match ``left_joints`` /
    ``right_joints`` (regular expressions, case-insensitive; defaults "left", "right").

Time: each message's header stamp; a type without header (Twist) or a zero stamp falls
back to the bag's receive time, per stream (recorded in meta). Both streams are then zeroed
at the first IMU message. Messages are taken in bag order; stamps that are not strictly
increasing are an error naming the message.
"""

from __future__ import annotations

import re
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.errors import InputError
from simpick.real.logs import validate as V
from simpick.real.logs.assemble import finish, source_columns
from simpick.real.logs.canonical import DEFAULT_TRACK, RealLog

IMU_TYPE = "sensor_msgs/msg/Imu"
COMMAND_TYPES = {
    "geometry_msgs/msg/Twist": "twist",
    "geometry_msgs/msg/TwistStamped": "twist_stamped",
    "nav_msgs/msg/Odometry": "odometry",
    "sensor_msgs/msg/JointState": "joint_state",
}
_SHORT = {v: k for k, v in COMMAND_TYPES.items()}


def _normal_type(name: str) -> str:
    """'geometry_msgs/Twist' or 'twist' -> 'geometry_msgs/msg/Twist'."""
    if name in _SHORT:
        return _SHORT[name]
    parts = name.split("/")
    if len(parts) == 2:
        return f"{parts[0]}/msg/{parts[1]}"
    return name


def _stamp(msg) -> int | None:
    header = getattr(msg, "header", None)
    if header is None:
        return None
    t = int(header.stamp.sec) * 1_000_000_000 + int(header.stamp.nanosec)
    return t or None


def _describe(topics: dict) -> str:
    return ", ".join(f"{name} ({info.msgtype})" for name, info in sorted(topics.items())) or "none"


def _rosbags_version() -> str:
    try:
        return version("rosbags")
    except PackageNotFoundError:  # pragma: no cover
        return "unknown"


def read_bag(
    path: str | Path,
    imu_topic: str,
    command_topic: str,
    command_type: str | None = None,
    *,
    wheel_radius: float | None = None,
    left_joints: str = "left",
    right_joints: str = "right",
    frame_z: str = "up",
    imu_rate_hz: float | None = None,
    command_rate_hz: float | None = None,
    track: float = DEFAULT_TRACK,
    meta: dict | None = None,
) -> RealLog:
    """A validated RealLog from a ROS 1 .bag file or a ROS 2 bag folder.

    ``command_type``: None (take the topic's type), a ROS type name or one of "twist",
    "twist_stamped", "odometry", "joint_state". ``frame_z="down"`` turns an x forward,
    y right, z down IMU into z up (180 deg about x: y, z negated; w negated too).
    """
    from rosbags.highlevel import AnyReader, AnyReaderError  # only a bag reads it (the CSV logs do not)
    from rosbags.typesys import Stores, get_typestore

    path = Path(path)
    where = str(path)
    if not path.exists():
        raise InputError(where, "bag not found", "give a ROS 1 .bag file or a ROS 2 bag folder")
    if path.is_file() and path.stat().st_size == 0:
        raise InputError(where, "bag file is empty (0 bytes)")
    if frame_z not in ("up", "down"):
        raise InputError(f"{where}: frame_z", f"must be 'up' or 'down', got {frame_z!r}")

    try:
        reader = AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE))
        reader.open()
    except (AnyReaderError, OSError, ValueError, KeyError) as exc:
        raise InputError(
            where,
            f"not a readable ROS bag: {exc}",
            "ROS 1 bags need the .bag suffix; ROS 2 bags are folders with metadata.yaml",
        ) from None
    try:
        topics = reader.topics
        for topic in (imu_topic, command_topic):
            if topic not in topics:
                raise InputError(
                    f"{where}: topic {topic!r}",
                    f"not in the bag; topics present: {_describe(topics)}",
                    "pass one of the topics present",
                )
        if topics[imu_topic].msgtype != IMU_TYPE:
            raise InputError(
                f"{where}: topic {imu_topic!r}",
                f"has type {topics[imu_topic].msgtype}, expected {IMU_TYPE}; topics present: {_describe(topics)}",
                "pass the IMU topic",
            )
        actual = topics[command_topic].msgtype
        wanted = _normal_type(command_type) if command_type else actual
        if wanted not in COMMAND_TYPES:
            raise InputError(
                f"{where}: topic {command_topic!r}",
                f"command type {wanted} is not supported; use one of {sorted(COMMAND_TYPES)}",
            )
        if actual != wanted:
            raise InputError(
                f"{where}: topic {command_topic!r}",
                f"has type {actual}, expected {wanted}; topics present: {_describe(topics)}",
                "pass the right command topic or command_type",
            )
        kind = COMMAND_TYPES[wanted]
        if kind == "joint_state" and (wheel_radius is None or not wheel_radius > 0):
            raise InputError(
                f"{where}: wheel_radius",
                f"JointState commands need the wheel radius in m (got {wheel_radius!r})",
                "pass wheel_radius=0.1651 for a Husky",
            )
        try:
            left_re, right_re = re.compile(left_joints, re.I), re.compile(right_joints, re.I)
        except re.error as exc:
            raise InputError(f"{where}: left_joints/right_joints", f"bad regular expression: {exc}") from None

        imu_rows, imu_stamps, cmd_rows, cmd_stamps = [], [], [], []
        conns = [c for c in reader.connections if c.topic in (imu_topic, command_topic)]
        for i, (conn, received, raw) in enumerate(reader.messages(connections=conns)):
            try:
                msg = reader.deserialize(raw, conn.msgtype)
            except AnyReaderError as exc:
                raise InputError(
                    f"{where}: topic {conn.topic!r}", f"message {i + 1} cannot be decoded: {exc}"
                ) from None
            if conn.topic == imu_topic:
                a, w = msg.linear_acceleration, msg.angular_velocity
                imu_rows.append((a.x, a.y, a.z, w.x, w.y, w.z))
                imu_stamps.append((_stamp(msg), received))
            else:
                cmd_rows.append(
                    _command(msg, kind, left_re, right_re, wheel_radius, where, command_topic, len(cmd_rows))
                )
                cmd_stamps.append((_stamp(msg), received))
    finally:
        reader.close()

    for topic, rows in ((imu_topic, imu_rows), (command_topic, cmd_rows)):
        if len(rows) < 2:
            raise InputError(f"{where}: topic {topic!r}", f"holds {len(rows)} message(s); at least 2 are needed")

    imu_time, imu_clock = _times(imu_stamps)
    cmd_time, cmd_clock = _times(cmd_stamps)
    t0 = int(imu_time[0])  # zero in integer ns, before float64 could blur epoch stamps
    imu_time, cmd_time = imu_time - t0, cmd_time - t0
    imu_where, cmd_where = f"{where} [topic {imu_topic}]", f"{where} [topic {command_topic}]"
    imu_raw = pd.DataFrame(imu_rows, columns=["ax", "ay", "az", "wx", "wy", "wz"])
    imu_raw.insert(0, "time", imu_time)
    cols = ["v_left", "v_right"] if kind == "joint_state" else ["v", "w"]
    cmd_raw = pd.DataFrame(cmd_rows, columns=cols)
    cmd_raw.insert(0, "time", cmd_time)
    names = {
        "time": "header.stamp" if imu_clock == "header" else "receive time",
        "ax": "linear_acceleration.x",
        "ay": "linear_acceleration.y",
        "az": "linear_acceleration.z",
        "wx": "angular_velocity.x",
        "wy": "angular_velocity.y",
        "wz": "angular_velocity.z",
    }
    cmd_names = {
        "time": "header.stamp" if cmd_clock == "header" else "receive time",
        "v": {"twist": "linear.x", "twist_stamped": "twist.linear.x", "odometry": "twist.twist.linear.x"}.get(
            kind, "v"
        ),
        "w": {"twist": "angular.z", "twist_stamped": "twist.angular.z", "odometry": "twist.twist.angular.z"}.get(
            kind, "w"
        ),
        "v_left": f"velocity[/{left_joints}/] x wheel_radius",
        "v_right": f"velocity[/{right_joints}/] x wheel_radius",
    }
    # message fields play the columns; time in ns (from the first IMU stamp) -> checked, then s
    imu = source_columns(
        imu_raw,
        {k: k for k in imu_raw.columns},
        imu_where,
        V.message_row,
        labels={k: V.Label(f"field {names[k]!r}") for k in imu_raw.columns},
    )
    cmd = source_columns(
        cmd_raw,
        {k: k for k in cmd_raw.columns},
        cmd_where,
        V.message_row,
        labels={k: V.Label(f"field {cmd_names[k]!r}") for k in cmd_raw.columns},
    )
    imu["time"] = imu["time"] * 1e-9
    cmd["time"] = cmd["time"] * 1e-9
    if frame_z == "down":
        for key in ("ay", "az", "wy", "wz"):
            imu[key] = -imu[key]
        if "w" in cmd:
            cmd["w"] = -cmd["w"]

    labels = {k: V.Label(f"field {v!r}") for k, v in {**names, **cmd_names}.items()}
    info = {
        "path": str(path.resolve()),
        "format": "ROS 2 bag" if path.is_dir() else "ROS 1 bag",
        "bytes": sum(f.stat().st_size for f in path.rglob("*") if f.is_file())
        if path.is_dir()
        else path.stat().st_size,
    }
    full = {
        "dataset": None,
        "run_id": path.stem,
        "terrain_class": None,
        **dict(meta or {}),
        "source_files": {"bag": info},
        "source_topics": {
            "imu": {"topic": imu_topic, "type": IMU_TYPE, "clock": imu_clock},
            "commands": {"topic": command_topic, "type": wanted, "clock": cmd_clock},
        },
        "source_frame": {"z": frame_z},
        "frame_conversion": ("none" if frame_z == "up" else "180 deg rotation about x: ay, az, wy, wz (and w) negated"),
    }
    if kind == "joint_state":
        full["wheel"] = {"radius_m": wheel_radius, "left_joints": left_joints, "right_joints": right_joints}
    out = finish(
        imu,
        cmd,
        imu_where=imu_where,
        cmd_where=cmd_where,
        imu_names=labels,
        cmd_names=labels,
        imu_row_label=V.message_row,
        cmd_row_label=V.message_row,
        declared_hz={"imu": imu_rate_hz, "commands": command_rate_hz},
        track=track,
        meta=full,
        reader="simpick.real.logs.rosbag",
    )
    out.meta["reader"]["rosbags"] = _rosbags_version()
    out.meta["time_offset_s"] = t0 * 1e-9
    out.meta["time_offset_ns"] = t0
    return out


def _times(stamps: list[tuple[int | None, int]]) -> tuple[np.ndarray, str]:
    """Header stamps if every message has one, else the bag receive times (ns, int64)."""
    if all(s is not None for s, _ in stamps):
        return np.array([s for s, _ in stamps], dtype=np.int64), "header"
    return np.array([r for _, r in stamps], dtype=np.int64), "receive"


def _command(msg, kind: str, left_re, right_re, radius, where: str, topic: str, index: int):
    if kind == "twist":
        return (msg.linear.x, msg.angular.z)
    if kind == "twist_stamped":
        return (msg.twist.linear.x, msg.twist.angular.z)
    if kind == "odometry":
        return (msg.twist.twist.linear.x, msg.twist.twist.angular.z)
    names = list(msg.name)
    vel = np.asarray(msg.velocity, dtype=float)
    if len(vel) != len(names):
        raise InputError(
            f"{where}: topic {topic!r}", f"message {index + 1} has {len(names)} joint names but {len(vel)} velocities"
        )
    left = [i for i, n in enumerate(names) if left_re.search(n)]
    right = [i for i, n in enumerate(names) if right_re.search(n)]
    if not left or not right or set(left) & set(right):
        raise InputError(
            f"{where}: topic {topic!r}",
            f"message {index + 1}: joints {names} do not split into left "
            f"(/{left_re.pattern}/: {[names[i] for i in left]}) and right "
            f"(/{right_re.pattern}/: {[names[i] for i in right]})",
            "pass left_joints / right_joints patterns that match the wheel joints",
        )
    return (float(vel[left].mean() * radius), float(vel[right].mean() * radius))
