"""Real robot logs (the ground truth) in one canonical form.

Readers: ``borealtc`` (the BorealTC CSV layout), ``csvlog`` (any CSV with a column and
unit mapping), ``rosbag`` (ROS 1 / ROS 2 bags through the ``rosbags`` library). Each
returns a validated :class:`RealLog`; every problem with the input is an
``simpick.errors.InputError`` naming the file, the column and the row.
``write_canonical`` / ``read_canonical`` store a log as one self-describing Parquet file.
"""

from simpick.real.logs.canonical import (
    DEFAULT_TRACK,
    RealLog,
    body_to_wheels,
    read_canonical,
    read_canonical_meta,
    wheels_to_body,
    write_canonical,
)

__all__ = [
    "DEFAULT_TRACK",
    "RealLog",
    "body_to_wheels",
    "read_canonical",
    "read_canonical_meta",
    "wheels_to_body",
    "write_canonical",
]
