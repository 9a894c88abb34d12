"""Every config mistake is caught before any job runs, naming the key, the value and what is allowed."""

import copy

import pytest

from conftest import ROOT, snakemake, study_config, tiny_config, write_config
from simpick.config import duplicate_keys, problems

CONFIG = study_config()


def broken(edit):
    config = copy.deepcopy(CONFIG)
    edit(config)
    return "\n".join(problems(config))


def test_the_shipped_config_is_valid():
    assert problems(CONFIG) == []


@pytest.mark.parametrize(
    "edit, expected",
    [
        (
            lambda c: c["engines"].update(gazebo={}),
            "unknown engine(s) ['gazebo']; available: "
            "['dart', 'drake', 'genesis', 'mujoco', 'newton', 'ode', 'physx', 'pybullet']",
        ),
        (
            lambda c: c["engines"]["mujoco"].update(iterationz=3),
            "engines.mujoco: unknown setting(s) ['iterationz']; "
            "accepted: ['cone', 'friction_ratio', 'integrator', 'solver_iterations',",
        ),
        (
            lambda c: c["engines"]["ode"].update(stepper="rk4"),
            "engines.ode.stepper: Input should be 'world' or 'quick' (got 'rk4')",
        ),
        (
            lambda c: c["engines"]["pybullet"].update(contact_stiffness="stiff"),
            "engines.pybullet.contact_stiffness: Input should be a valid number, unable to parse string as a number "
            "(got 'stiff')",
        ),
        (
            lambda c: c["engines"]["dart"].update(solver_sweeps=0),
            "engines.dart.solver_sweeps: Input should be greater than or equal to 1 (got 0)",
        ),
        (
            lambda c: c["engines"]["mujoco"].update(wheel_contact_impedance=1.0),
            "engines.mujoco.wheel_contact_impedance: Input should be less than 1 (got 1.0)",
        ),
        (
            lambda c: c["baselines"]["kinematic"].update(track=0),
            "baselines.kinematic.track: Input should be greater than 0 (got 0)",
        ),
        (lambda c: c["baselines"].update(unicycle={}), "baselines: unknown reference model 'unicycle'"),
        (lambda c: c["terrains"]["grass"].update(rule="lava"), "terrains.grass.rule"),
        (
            lambda c: c["motions"]["straight"].update(duration=-1),
            "motions.straight.duration: Input should be greater than 0 (got -1)",
        ),
        (lambda c: c["physics"].update(timestep=0), "physics.timestep: Input should be greater than 0 (got 0)"),
        (lambda c: c["physics"].update(timestep=0.003), "does not divide the IMU period"),
        (lambda c: c["weights"].update(ui=-2), "weights.ui: Input should be greater than or equal to 0 (got -2)"),
        (lambda c: c["weights"].update(ui=float("inf")), "weights.ui: Input should be a finite number"),
        (lambda c: c["weights"].pop("ui"), "missing weight(s) ['ui']"),
        (lambda c: c["weights"].update(speed=1), "unknown weight(s) ['speed']"),
        (lambda c: c["robot"].update(urdf="nowhere.urdf"), "robot.urdf: file 'nowhere.urdf' does not exist"),
        (lambda c: c["robot"].update(track="wide"), "robot.track: Input should be a valid number"),
        (lambda c: c["cpu_load"].update(terrain="moon"), "cpu_load.terrain 'moon' is not one of terrains"),
        (lambda c: c.update(borealtc_dir="/no/such/folder"), "borealtc_dir: '/no/such/folder' is not a folder"),
        (
            lambda c: c.update(real_dataset="yard"),
            "real_dataset 'yard' names the dataset folder given as borealtc_dir, but borealtc_dir is not set",
        ),
        (lambda c: c.update(real_dataset="my yard", borealtc_dir="."), "real_dataset: String should match pattern"),
        (
            lambda c: c["real_data"]["datasets"].update(yard={"imu_hz": 0}),
            "real_data.datasets.yard.imu_hz: Input should be greater than 0 (got 0)",
        ),
        (
            lambda c: c["real_data"]["datasets"].update(yard={"imu_rate": 50}),
            "real_data.datasets.yard.imu_rate: Extra inputs are not permitted",
        ),
        (
            lambda c: c["real_data"].update(segments="gone.csv"),
            "real_data.segments: 'gone.csv' does not exist; restore it",
        ),
        (lambda c: c["imu"].update(rate_hz="fast"), "imu.rate_hz: Input should be a valid number"),
        (lambda c: c.update(sede=1), "sede: Extra inputs are not permitted"),
        (
            lambda c: c["validation"]["cases"].update(short={"kind": "rest", "mu": 0.8, "duration": 0.9}),
            "validation.cases.short: a rest case measures after 1 s of settling: its duration must be at "
            "least 1.1 s, got 0.9",
        ),
        (
            lambda c: c["accuracy"].update(reference="vibes"),
            "accuracy.reference: Input should be 'real', 'paper' or 'own' (got 'vibes')",
        ),
        (
            lambda c: c.update(
                own_logs=[{"name": "x", "terrain_class": "moon", "csv": "config.yaml", "mapping": {"a": 1}}]
            ),
            "own_logs: terrain classes ['moon'] are not under real_data.classes",
        ),
        (
            lambda c: c.update(
                own_logs=[
                    {
                        "name": "x",
                        "terrain_class": "ice",
                        "rosbag": "missing.bag",
                        "imu_topic": "/imu",
                        "command_topic": "/cmd",
                    }
                ]
            ),
            "own log 'x': rosbag 'missing.bag' does not exist",
        ),
    ],
)
def test_each_mistake_is_named(edit, expected):
    assert expected in broken(edit)


def test_a_key_given_twice_is_refused(tmp_path):
    path = tmp_path / "c.yaml"
    path.write_text("weights:\n  ui: 1\n  free: 4\n  ui: 2\n")
    assert duplicate_keys(path) == [
        f"{path}, line 4: key 'ui' appears twice in the same block (YAML would silently keep the last one)"
    ]


@pytest.mark.workflow
def test_snakemake_stops_with_the_message_and_no_traceback(tmp_path):
    config = tiny_config(tmp_path)
    config["motions"]["straight"]["duration"] = 0
    write_config(tmp_path, config)
    text = (tmp_path / "config.yaml").read_text() + "seed: 3\n"  # and a duplicated top-level key
    (tmp_path / "config.yaml").write_text(text)
    run = snakemake(tmp_path, "-n")
    out = run.stdout + run.stderr
    assert run.returncode != 0
    assert "motions.straight.duration: Input should be greater than 0 (got 0)" in out
    assert "key 'seed' appears twice" in out
    assert "Traceback" not in out


def test_read_study_merges_files_as_snakemake_does_and_refuses_what_the_workflow_refuses(tmp_path, capsys):
    """Every entry point reads a config through one loader: a second file updates the first key by key at
    every depth (a robot's file keeps the rest of the default robot block), and a duplicate key or a bad value
    stops with the file and line, as the Snakefile does."""
    from simpick.config import read_study

    over = tmp_path / "over.yaml"
    over.write_text("physics:\n  timestep: 0.002\nweights:\n  ui: 7\n")
    study, config = read_study([ROOT / "config.yaml", over])
    assert study.physics.timestep == 0.002 and config["weights"]["ui"] == 7
    assert config["weights"]["ros"] == CONFIG["weights"]["ros"]  # the rest of the block kept
    assert config["robot"] == CONFIG["robot"]

    bad = tmp_path / "bad.yaml"
    bad.write_text("weights:\n  ui: 1\nweights:\n  ui: 2\n")
    with pytest.raises(SystemExit):
        read_study([ROOT / "config.yaml", bad])
    assert f"{bad}, line 3: key 'weights' appears twice" in capsys.readouterr().err


def test_the_validation_helper_reads_the_config_as_the_workflow_does(tmp_path, capsys):
    """``python -m simpick.cli.validation``: a case runs on an engine with the merged config's timestep; an
    engine the config does not configure is refused by name."""
    from simpick.cli.validation import main

    main(["mujoco", "rest_mu0.8", "--config", str(ROOT / "config.yaml")])
    out = capsys.readouterr().out
    assert "rest_mu0.8" in out and "creep_distance" in out and "False" not in out
    with pytest.raises(SystemExit):
        main(["no_such_engine", "--config", str(ROOT / "config.yaml")])
    assert "'no_such_engine' is not an engine of the config" in capsys.readouterr().err
