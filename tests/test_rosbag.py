"""ROS bags written here with rosbags (ROS 2 folder and ROS 1 .bag), read back by simpick."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from simpick.errors import InputError
from simpick.real.logs import read_canonical, write_canonical
from simpick.real.logs.rosbag import read_bag

pytest.importorskip("rosbags")
from rosbags.rosbag1 import Writer as Writer1  # noqa: E402
from rosbags.rosbag2 import Writer as Writer2  # noqa: E402
from rosbags.typesys import Stores, get_typestore  # noqa: E402

T0 = 1_700_000_000_123_456_789  # ns, an epoch stamp: float64 alone would blur it
N_IMU = 300  # 3 s at 100 Hz


def imu_values(k: int) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """(accel, gyro) of IMU message k: gravity on +z, a left turn of 0.2 rad/s."""
    return (0.01 * k / N_IMU, -0.05, 9.81 + 0.001 * k), (0.002, -0.003, 0.2 + 0.0001 * k)


def write_bag(
    path: Path, ros: int, command: str = "twist", *, imu_stamps: list[int] | None = None, zero_stamps: bool = False
) -> Path:
    ts = get_typestore(Stores.ROS2_HUMBLE if ros == 2 else Stores.ROS1_NOETIC)
    T = ts.types
    Time, Header = T["builtin_interfaces/msg/Time"], T["std_msgs/msg/Header"]
    Vec, Quat = T["geometry_msgs/msg/Vector3"], T["geometry_msgs/msg/Quaternion"]
    Imu, Twist = T["sensor_msgs/msg/Imu"], T["geometry_msgs/msg/Twist"]
    serialize = ts.serialize_cdr if ros == 2 else ts.serialize_ros1

    def header(t: int, k: int, frame: str):
        stamp = Time(sec=0, nanosec=0) if zero_stamps else Time(sec=t // 10**9, nanosec=t % 10**9)
        extra = {} if ros == 2 else {"seq": k}
        return Header(stamp=stamp, frame_id=frame, **extra)

    def vec(x, y, z):
        return Vec(x=float(x), y=float(y), z=float(z))

    writer = Writer2(path, version=9) if ros == 2 else Writer1(path)
    cmd_type = {
        "twist": Twist.__msgtype__,
        "odometry": "nav_msgs/msg/Odometry",
        "joint_state": "sensor_msgs/msg/JointState",
    }[command]
    with writer:
        c_imu = writer.add_connection("/imu/data", Imu.__msgtype__, typestore=ts)
        c_cmd = writer.add_connection("/cmd", cmd_type, typestore=ts)
        c_other = writer.add_connection("/chatter", "std_msgs/msg/String", typestore=ts)
        writer.write(c_other, T0, serialize(T["std_msgs/msg/String"](data="hi"), "std_msgs/msg/String"))
        stamps = imu_stamps or [T0 + k * 10_000_000 for k in range(N_IMU)]
        for k, t in enumerate(stamps):
            acc, gyr = imu_values(k)
            msg = Imu(
                header=header(t, k, "imu_link"),
                orientation=Quat(x=0.0, y=0.0, z=0.0, w=1.0),
                orientation_covariance=np.zeros(9),
                angular_velocity=vec(*gyr),
                angular_velocity_covariance=np.zeros(9),
                linear_acceleration=vec(*acc),
                linear_acceleration_covariance=np.zeros(9),
            )
            writer.write(c_imu, T0 + k * 10_000_000 + 500_000, serialize(msg, Imu.__msgtype__))
            if k % 10 == 5:  # 10 Hz commands, 50 ms after the IMU
                j = k // 10
                t_cmd = T0 + k * 10_000_000
                v, w = 0.3 + 0.01 * j, 0.25
                if command == "twist":
                    msg = Twist(linear=vec(v, 0, 0), angular=vec(0, 0, w))
                elif command == "odometry":
                    Cov = T["geometry_msgs/msg/TwistWithCovariance"]
                    Pose = T["geometry_msgs/msg/PoseWithCovariance"]
                    msg = T["nav_msgs/msg/Odometry"](
                        header=header(t_cmd, j, "odom"),
                        child_frame_id="base_link",
                        pose=Pose(
                            pose=T["geometry_msgs/msg/Pose"](
                                position=T["geometry_msgs/msg/Point"](x=0.0, y=0.0, z=0.0),
                                orientation=Quat(x=0.0, y=0.0, z=0.0, w=1.0),
                            ),
                            covariance=np.zeros(36),
                        ),
                        twist=Cov(twist=Twist(linear=vec(v, 0, 0), angular=vec(0, 0, w)), covariance=np.zeros(36)),
                    )
                else:  # Husky wheel joints, rad/s; radius 0.1651 m
                    left, right = (v - 0.1) / 0.1651, (v + 0.1) / 0.1651
                    msg = T["sensor_msgs/msg/JointState"](
                        header=header(t_cmd, j, ""),
                        name=["front_left_wheel", "front_right_wheel", "rear_left_wheel", "rear_right_wheel"],
                        position=np.zeros(4),
                        velocity=np.array([left, right, left, right]),
                        effort=np.zeros(4),
                    )
                writer.write(c_cmd, t_cmd + 1_000_000, serialize(msg, cmd_type))
    return path


@pytest.fixture(params=[2, 1], ids=["ros2", "ros1"])
def ros(request):
    return request.param


def bag_path(tmp_path: Path, ros: int) -> Path:
    return tmp_path / ("run_ros2" if ros == 2 else "run_ros1.bag")


def test_imu_and_twist_read_back(tmp_path, ros):
    path = write_bag(bag_path(tmp_path, ros), ros)
    log = read_bag(path, "/imu/data", "/cmd", imu_rate_hz=100, command_rate_hz=10)
    assert len(log.imu) == N_IMU and len(log.commands) == N_IMU // 10
    np.testing.assert_allclose(log.imu["time"], np.arange(N_IMU) * 0.01, atol=1e-9)
    for k in (0, 17, N_IMU - 1):
        acc, gyr = imu_values(k)
        np.testing.assert_allclose(log.imu.loc[k, ["ax", "ay", "az"]].to_numpy(float), acc)
        np.testing.assert_allclose(log.imu.loc[k, ["wx", "wy", "wz"]].to_numpy(float), gyr)
    assert log.command_kind == "body"
    np.testing.assert_allclose(log.commands["v"], 0.3 + 0.01 * np.arange(N_IMU // 10))
    np.testing.assert_allclose(log.commands["w"], 0.25)
    # Twist has no header: receive time (IMU stamp + 51 ms), zeroed at the first IMU stamp
    np.testing.assert_allclose(log.commands["time"], 0.051 + 0.1 * np.arange(N_IMU // 10), atol=1e-9)
    assert log.meta["source_topics"]["imu"]["clock"] == "header"
    assert log.meta["source_topics"]["commands"]["clock"] == "receive"
    assert log.meta["time_offset_ns"] == T0
    assert log.meta["checks"]["yaw"]["verdict"] == "consistent"
    assert log.meta["source_files"]["bag"]["format"] == ("ROS 2 bag" if ros == 2 else "ROS 1 bag")
    back = read_canonical(write_canonical(log, tmp_path / "bag.parquet"))
    assert back.meta == log.meta and back.commands.equals(log.commands)


def test_zero_header_stamps_fall_back_to_receive_time(tmp_path):
    path = write_bag(bag_path(tmp_path, 2), 2, zero_stamps=True)
    log = read_bag(path, "/imu/data", "/cmd")
    assert log.meta["source_topics"]["imu"]["clock"] == "receive"
    np.testing.assert_allclose(log.imu["time"], np.arange(N_IMU) * 0.01, atol=1e-9)


def test_odometry_commands(tmp_path, ros):
    path = write_bag(bag_path(tmp_path, ros), ros, "odometry")
    log = read_bag(path, "/imu/data", "/cmd", command_type="nav_msgs/Odometry")
    np.testing.assert_allclose(log.commands["v"], 0.3 + 0.01 * np.arange(N_IMU // 10))
    assert log.meta["source_topics"]["commands"]["clock"] == "header"
    np.testing.assert_allclose(log.commands["time"], 0.05 + 0.1 * np.arange(N_IMU // 10), atol=1e-9)


def test_joint_state_commands(tmp_path, ros):
    path = write_bag(bag_path(tmp_path, ros), ros, "joint_state")
    with pytest.raises(InputError, match="wheel_radius"):
        read_bag(path, "/imu/data", "/cmd")
    log = read_bag(path, "/imu/data", "/cmd", "joint_state", wheel_radius=0.1651)
    v = 0.3 + 0.01 * np.arange(N_IMU // 10)
    np.testing.assert_allclose(log.commands["v_left"], v - 0.1)
    np.testing.assert_allclose(log.commands["v_right"], v + 0.1)
    with pytest.raises(InputError, match=r"do not split into left"):
        read_bag(path, "/imu/data", "/cmd", wheel_radius=0.1651, left_joints="wheel")


def test_missing_topic_lists_the_topics(tmp_path, ros):
    path = write_bag(bag_path(tmp_path, ros), ros)
    with pytest.raises(InputError) as info:
        read_bag(path, "/imu", "/cmd")
    message = str(info.value)
    assert str(path) in message and "'/imu'" in message
    for topic in ("/imu/data (sensor_msgs/msg/Imu)", "/cmd (geometry_msgs/msg/Twist)", "/chatter"):
        assert topic in message


def test_wrong_topic_type(tmp_path, ros):
    path = write_bag(bag_path(tmp_path, ros), ros)
    with pytest.raises(InputError, match=r"'/cmd'.*expected sensor_msgs/msg/Imu.*topics present"):
        read_bag(path, "/cmd", "/cmd")
    with pytest.raises(InputError, match=r"'/cmd'.*has type geometry_msgs/msg/Twist, expected nav_msgs/msg/Odometry"):
        read_bag(path, "/imu/data", "/cmd", command_type="odometry")
    with pytest.raises(InputError, match=r"'/chatter'.*not supported"):
        read_bag(path, "/imu/data", "/chatter")


def test_duplicated_imu_stamp_names_the_message(tmp_path):
    stamps = [T0 + k * 10_000_000 for k in range(N_IMU)]
    stamps[40] = stamps[39]
    path = write_bag(bag_path(tmp_path, 2), 2, imu_stamps=stamps)
    with pytest.raises(InputError, match=r"topic /imu/data.*'header\.stamp'.*message 41"):
        read_bag(path, "/imu/data", "/cmd")


def test_missing_and_unreadable_bags(tmp_path):
    with pytest.raises(InputError, match="bag not found"):
        read_bag(tmp_path / "none.bag", "/imu", "/cmd")
    (tmp_path / "junk.bag").write_bytes(b"#ROSBAG V2.0\n garbage")
    with pytest.raises(InputError, match="junk.bag.*not a readable ROS bag"):
        read_bag(tmp_path / "junk.bag", "/imu", "/cmd")
    (tmp_path / "folder").mkdir()
    with pytest.raises(InputError, match="not a readable ROS bag"):
        read_bag(tmp_path / "folder", "/imu", "/cmd")
