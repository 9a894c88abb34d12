"""Real-robot reference statistics, mapped into simpick's frame before any comparison.

The lab study's only published real IMU statistics are the paper's Tables 6 and 7
(gravel, straight). The paper's sensor reads about -11.5 m/s^2 on z, so its z points down;
``resources/published/farley2022.yaml`` declares that frame as a rotation matrix and this
module applies it. Per-axis mean and range survive a frame change only when the
rotation is a signed axis permutation, so anything else is refused.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from simpick.errors import InputError
from simpick.imustats import AXES


def to_simpick_frame(
    stats: Mapping[str, Mapping[str, float]], rotation: list[list[float]], where: str
) -> dict[str, dict[str, float]]:
    """Per-axis {'mean','range'} in a sensor frame -> simpick's frame.

    ``rotation`` maps simpick vectors to the sensor frame (v_sensor = R v_simpick).
    """
    r = np.asarray(rotation, dtype=float)
    signed_permutation = (
        r.shape == (3, 3)
        and np.all(np.isin(r, (-1.0, 0.0, 1.0)))
        and np.all(np.abs(r).sum(axis=0) == 1)
        and np.all(np.abs(r).sum(axis=1) == 1)
    )
    if not signed_permutation:
        raise InputError(
            where,
            "rotation_matrix must be a signed axis permutation "
            "(per-axis means and ranges do not survive a general rotation)",
        )
    out = {}
    for i, axis in enumerate(AXES):  # simpick axis i = sum_j R[j, i] * sensor axis j
        j = int(np.flatnonzero(r[:, i])[0])
        sensor_axis = AXES[j]
        out[axis] = {"mean": float(r[j, i] * stats[sensor_axis]["mean"]), "range": float(stats[sensor_axis]["range"])}
    return out


def lab_reference(published: Mapping) -> dict[tuple[str, str], dict]:
    """{(terrain, motion): {'angular': stats, 'linear': stats, 'source': text}} from the paper."""
    example = published["worked_example"]
    rotation = example["sensor_frame"]["rotation_matrix"]
    test = example["test"]
    where = "resources/published/farley2022.yaml: worked_example"
    return {
        (test["terrain"], test["motion"]): {
            "angular": to_simpick_frame(example["table6"]["real"], rotation, where),
            "linear": to_simpick_frame(example["table7"]["real"], rotation, where),
            "source": "Farley et al. 2022, Tables 6-7 (real Husky, gravel, straight); "
            "sensor frame x "
            + ", y ".join(example["sensor_frame"]["axes"][a] for a in "xy")
            + f", z {example['sensor_frame']['axes']['z']} (inferred) mapped to x forward, y left, z up",
        }
    }
