"""The robot in the workflow: read at planning time, so a broken description stops
the run before any job (and before Snakemake deletes any output to rerun it); another robot's
study plans no comparison with the Husky's real data."""

from pathlib import Path

import pytest

from conftest import planned_jobs, snakemake, tiny_config, write_config

pytestmark = pytest.mark.workflow  # every test here runs Snakemake

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("dry", [True, False])
def test_a_urdf_that_is_not_xml_stops_the_run_and_deletes_nothing(tmp_path, dry):
    config = tiny_config(tmp_path)
    broken = tmp_path / "robot.urdf"
    broken.write_text("<robot name='x'><link name='a'>\n  not closed")
    config["robot"]["urdf"] = str(broken)
    write_config(tmp_path, config)
    # a previous study's results, which a run that plans jobs would delete before rerunning them
    kept = [
        tmp_path / "results" / "validation" / "pybullet" / "rest_mu0.8.json",
        tmp_path / "results" / "traces" / "lab" / "mujoco" / "grass" / "straight.parquet",
    ]
    for path in kept:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("previous result")
    run = snakemake(tmp_path, *(["-n"] if dry else []))
    text = run.stdout + run.stderr
    assert run.returncode != 0
    assert f"robot.urdf: {broken}: cannot read the robot description: not XML" in text
    assert "Traceback" not in text and "Job " not in text
    assert all(p.read_text() == "previous result" for p in kept)


def test_an_unsupported_layout_is_named_at_planning_time(tmp_path):
    config = tiny_config(tmp_path)
    text = (ROOT / "resources" / "robot" / "husky_a200.urdf").read_text()
    config["robot"]["urdf"] = str(tmp_path / "steered.urdf")
    (tmp_path / "steered.urdf").write_text(
        text.replace(
            '<joint name="front_left_wheel_joint" type="continuous">',
            '<joint name="front_left_wheel_joint" type="revolute">',
        )
    )
    write_config(tmp_path, config)
    run = snakemake(tmp_path, "-n")
    assert run.returncode != 0
    assert "joint 'front_left_wheel_joint': is revolute" in run.stdout + run.stderr


def test_another_robot_plans_no_real_data_and_refuses_resting_on_it(tmp_path):
    config = tiny_config(tmp_path)
    config["robot"].update(
        urdf=str(ROOT / "resources" / "robot" / "jackal.urdf"),
        label="Clearpath Jackal",
        track=0.37559,
        max_wheel_torque=20.0,
    )
    write_config(tmp_path, config)  # accuracy.reference is still 'real': the Husky's data
    run = snakemake(tmp_path, "-n")
    assert run.returncode != 0
    assert (
        "accuracy.reference is 'real', but the real data (real_data.dataset 'borealtc') were recorded on "
        "robot 'husky_a200', not on this study's 'jackal'" in run.stdout + run.stderr
    )
    config["accuracy"]["reference"] = "paper"
    write_config(tmp_path, config)
    jobs = planned_jobs(tmp_path)
    # the lab's simulations alone (a job per engine and terrain): no real-data source is simulated
    simulated = {rule for rule, _ in jobs if rule.startswith("simulate")}
    assert simulated == {"simulate_lab"}, simulated
    assert {"validate", "simulate_lab", "report"} <= {rule for rule, _ in jobs}


def test_own_logs_replay_on_the_robot_the_config_names(tmp_path):
    """A user's log of the diff-drive robot is replayed on that robot (its mirrored right wheel
    commanded backwards, the caster free) by an engine and by both reference models."""
    import numpy as np
    import pandas as pd

    from simpick.simulate.traces import read_trace

    t = np.arange(0.0, 12.0, 0.01)
    v = np.where(t < 6.0, 0.3, 0.2)
    w = np.where(t < 6.0, 0.0, 0.5)
    log = pd.DataFrame(
        {
            "time": t,
            "ax": 0.0,
            "ay": 0.0,
            "az": 9.81,
            "wx": 0.0,
            "wy": 0.0,
            "wz": np.where(t < 6.0, 0.0, 0.45),
            "v": v,
            "w": w,
        }
    )
    log.to_csv(tmp_path / "bot.csv", index=False)
    import yaml

    config = tiny_config(tmp_path)
    robot = yaml.safe_load((ROOT / "config" / "robots" / "diffbot.yaml").read_text())
    for block in ("robot", "baselines", "health"):  # what Snakemake merges from --configfile
        config[block].update(robot[block])
    config["robot"]["urdf"] = str(ROOT / robot["robot"]["urdf"])
    config["engines"] = {"mujoco": config["engines"]["mujoco"] | robot["engines"]["mujoco"]}
    config["own_logs"] = [
        {
            "name": "bot",
            "terrain_class": "flooring",
            "csv": str(tmp_path / "bot.csv"),
            "mapping": {k: k for k in ("time", "ax", "ay", "az", "wx", "wy", "wz", "v", "w")},
        }
    ]
    config["accuracy"]["reference"] = "own"
    write_config(tmp_path, config)
    run = snakemake(tmp_path, "results/metrics/own/summary.csv")
    assert run.returncode == 0, run.stderr[-3000:]
    per_test = pd.read_csv(tmp_path / "results/metrics/own/per_test.csv")
    assert sorted(per_test.engine) == ["coulomb", "kinematic", "mujoco"] and (per_test.status == "ok").all()
    frame, meta = read_trace(tmp_path / "results/traces/own/mujoco/flooring/bot.parquet")
    # forward-signed wheel speeds: both sides at v / r = 6 rad/s while driving straight
    straight = (frame.time > 2.0) & (frame.time < 5.5)
    assert np.allclose(frame.cmd_left[straight], 6.0) and np.allclose(frame.cmd_right[straight], 6.0)
    assert np.allclose(frame.wheel_fr[straight], 6.0, rtol=0.05)
    assert frame.v_forward[straight].mean() == pytest.approx(0.3, rel=0.05)
    # then the turn, at the no-slip rate of a differential drive
    turning = frame.time > 9.0
    assert frame.yaw_rate[turning].mean() == pytest.approx(0.5, rel=0.15)
