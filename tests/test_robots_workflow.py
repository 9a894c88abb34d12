"""The benchmark across robots as a workflow (rules/robots.smk): two robots' tiny studies as modules of
the one Snakefile, each with its own config and plan, their results apart, and the page from their
answers; a robot entry that names a missing config file, or a robot with no real data, stops the run
before any job with the file, field and fix."""

import subprocess
import sys

import pandas as pd
import pytest
import yaml

from conftest import ROOT, tiny_config, write_config

pytestmark = [pytest.mark.workflow, pytest.mark.slow]  # two tiny studies: about 2-3 minutes on 2 cores


def robots(workdir, *args):
    cmd = [sys.executable, "-m", "snakemake", "--snakefile", str(ROOT / "rules" / "robots.smk")]
    cmd += ["--directory", str(workdir), "--cores", "2", *args]
    return subprocess.run(cmd, capture_output=True, text=True, cwd=workdir)


def tiny_benchmark(workdir, entries: dict) -> None:
    """config.yaml: the tiny study on two engines and no simulator profile; config/robots.yaml: ``entries``."""
    config = tiny_config(workdir)
    config["engines"] = {k: config["engines"][k] for k in ("mujoco", "pybullet")}
    config["terrains"] = {"grass": config["terrains"]["grass"]}
    config["validation"]["cases"] = {"rest_mu0.8": {"kind": "rest", "mu": 0.8, "duration": 1.5}}
    write_config(workdir, config)
    (workdir / "config").mkdir(exist_ok=True)
    (workdir / "config" / "robots.yaml").write_text(yaml.safe_dump({"robots": entries, "pooling": {"min_robots": 2}}))


def test_two_robots_run_as_modules_and_meet_on_one_page(tmp_path):
    # the second robot: the same Husky with PyBullet's contacts twice as stiff, from a config file of its own
    (tmp_path / "config" / "robots").mkdir(parents=True)
    stiff = {"engines": {"pybullet": {"contact_stiffness": 2.0e6}}, "robot": {"label": "Stiff Husky"}}
    (tmp_path / "config" / "robots" / "stiff.yaml").write_text(yaml.safe_dump(stiff))
    tiny_benchmark(tmp_path, {"husky": {}, "stiff": {"configfiles": ["config/robots/stiff.yaml"]}})
    run = robots(tmp_path)
    assert run.returncode == 0, run.stderr[-3000:]
    out = tmp_path / "results" / "robots"
    # each study wrote its own results/ under results/robots/<robot>/, from its own config
    for robot in ("husky", "stiff"):
        assert (out / robot / "verdict" / "answer.csv").is_file()
        assert (out / robot / "simulators" / "table.csv").is_file()
    assert not (tmp_path / "results" / "verdict").exists()
    # each module planned from its own config: its answer names its own robot
    said = {r: yaml.safe_load((out / r / "verdict" / "answer.yaml").read_text())["robot"] for r in ("husky", "stiff")}
    assert said == {"husky": "Clearpath Husky A200", "stiff": "Stiff Husky"}, said
    # the page and its tables: every engine on both robots, in the robots' order
    side = pd.read_csv(out / "benchmark.csv")
    assert list(dict.fromkeys(side.robot)) == ["husky", "stiff"]
    assert set(side[side.kind == "engine"].subject) == {"mujoco", "pybullet"}
    # no profile ran (tiny_config: simulators.run []): the catalogue's rows marked not run are not subjects
    assert set(side.kind) == {"engine"}
    agree = pd.read_csv(out / "agreement.csv")
    assert set(agree.metric) == {"gain_error", "heading_error", "speed_error"}
    html = (out / "benchmark.html").read_text()
    assert "Stiff Husky" in html and "--configfile config/robots/stiff.yaml" in html
    assert (out / "benchmark.pdf").read_bytes()[:4] == b"%PDF"
    # nothing edited: nothing runs
    again = robots(tmp_path, "-n")
    assert again.returncode == 0 and "Nothing to be done" in again.stdout + again.stderr


@pytest.mark.parametrize(
    "entries, message",
    [
        (
            {"husky": {}, "warthog": {"configfiles": ["config/robots/nope.yaml"]}},
            "config/robots.yaml, robots.warthog.configfiles[0]: config/robots/nope.yaml does not exist",
        ),
        (
            {"husky": {}, "jackal": {"config": {"robot": {"urdf": str(ROOT / "resources/robot/jackal.urdf")},
                                                "accuracy": {"reference": "paper"}}}},
            "config/robots.yaml, robots.jackal: its study has no real data of this robot",
        ),
    ],
)  # fmt: skip
def test_a_bad_robot_entry_stops_before_any_job(tmp_path, entries, message):
    tiny_benchmark(tmp_path, entries)
    run = robots(tmp_path, "-n")
    assert run.returncode != 0
    assert message in run.stdout + run.stderr
    assert "Job stats" not in run.stdout + run.stderr
