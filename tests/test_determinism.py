"""Same config and seed -> identical trace content on every engine; another seed -> other gravel."""

import numpy as np
import pandas as pd
import pytest
import yaml

from conftest import ROOT, study_config
from simpick.engines import ADAPTERS
from simpick.engines.base import Scenario
from simpick.inputs.jobs import terrain_job
from simpick.inputs.robot import load_robot
from simpick.inputs.terrain import load
from simpick.simulate.imu import ImuModel
from simpick.simulate.run import Case, Recording, run_case
from simpick.simulate.traces import read_trace, write_trace

CONFIG = study_config()


def gravel(tmp_path, seed):
    """The config's gravel bed, one tile of it (its stones as dense as on the lab's four): the robot drives onto its
    stones within the run, and an engine that builds a world slowly (Genesis: 95 s for the lab's 485 stones) builds
    a quarter of them. The whole strip's build is tests/test_engines.py's."""
    path = tmp_path / f"gravel-{seed}.json"
    terrain_job(str(path), "gravel", seed, dict(CONFIG["terrains"]["gravel"], tiles=1))
    return path


def trace(engine, terrain_file, seed):
    # from 0.3 m before the tile: its front wheels climb the bed and its stones within the second (from the lab's
    # start, 0.8 m before it, the robot would not reach them)
    case = Case(engine=engine, terrain="gravel", motion="straight", v=0.5, w=0.0, duration=1.0, start=(-0.3, 0.0, 0.0))
    scenario = Scenario(
        robot=load_robot(ROOT / CONFIG["robot"]["urdf"]),
        terrain=load(terrain_file),
        ground_friction=0.8,
        timestep=0.001,
        max_wheel_torque=50.0,
        starts=(case.start,),
    )
    frame, meta = run_case(
        case, scenario, 0.555, Recording(imu=ImuModel(accel_noise_std=0.01, gyro_noise_std=0.001), seed=seed)
    )
    return pd.DataFrame(frame), meta


@pytest.mark.parametrize("engine", sorted(ADAPTERS))
def test_same_seed_same_trace_content(engine, tmp_path):
    a, meta_a = trace(engine, gravel(tmp_path, 1), 1)
    b, _ = trace(engine, gravel(tmp_path, 1), 1)
    pd.testing.assert_frame_equal(a, b, check_exact=True)
    # and through a Parquet round trip: content, not bytes, is what must match
    write_trace(a, meta_a, tmp_path / "a.parquet")
    back, meta = read_trace(tmp_path / "a.parquet")
    pd.testing.assert_frame_equal(a, back, check_exact=True)
    assert meta["seed"] == 1 and meta["health"]["status"] == "ok"
    assert a["z"].max() - a["z"].min() > 0.02  # it climbed the bed (2 cm) and its stones: contacts were stepped


def test_other_seed_changes_the_gravel_and_the_noise(tmp_path):
    one, two = gravel(tmp_path, 1), gravel(tmp_path, 2)
    s1 = np.asarray(yaml.safe_load(one.read_text())["spheres"])
    s2 = np.asarray(yaml.safe_load(two.read_text())["spheres"])
    assert s1.shape == s2.shape and not np.allclose(s1, s2)
    a, _ = trace("mujoco", one, 1)
    b, _ = trace("mujoco", one, 2)  # same terrain, other noise seed
    assert not np.array_equal(a["ax"], b["ax"])
    np.testing.assert_array_equal(a["x"], b["x"])  # the physics itself is seed-free
