"""The full replay of a dataset folder that is not the shared BorealTC one, end to end.

A Husky dataset "recorded elsewhere" is made up here: its own terrain classes (CONCRETE,
declared in the config; FLOORING), runs numbered 1, 12 and 7, the IMU at 50 Hz and the wheel
speeds at 15 Hz. The run must succeed, write its logs and segment table under results/real/<dataset>/,
its traces under results/traces/<dataset>/ and its tables under results/metrics/<dataset>/, and
leave the checkout as it found it: the committed segment table and its provenance
byte-identical, `git status --porcelain` unchanged (empty in a clean checkout) - also when a
job fails on a broken file.
"""

import hashlib
import subprocess

import numpy as np
import pandas as pd
import pytest

from conftest import ROOT, planned_jobs, snakemake, tiny_config, write_config, write_dataset
from simpick.simulate.traces import read_metadata, read_trace

pytestmark = pytest.mark.workflow  # every test here runs Snakemake

COMMITTED = [
    ROOT / "resources" / "real" / "borealtc_segments.csv",
    ROOT / "resources" / "real" / "borealtc_segments.provenance.yaml",
]
NAME = "husky_yard"  # from the folder "Husky Yard"
ENGINES = ("mujoco", "pybullet")
OUT = f"results/real/{NAME}"
TRACES = f"results/traces/{NAME}"
METRICS = f"results/metrics/{NAME}"


def git_status() -> str:
    run = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain"], capture_output=True, text=True)
    if run.returncode != 0:
        pytest.fail(f"this test checks the checkout with git, which failed here: {run.stderr.strip()}")
    return run.stdout


def fingerprints() -> dict:
    return {str(p): hashlib.sha256(p.read_bytes()).hexdigest() for p in COMMITTED}


@pytest.fixture(scope="module")
def replay(tmp_path_factory):
    workdir = tmp_path_factory.mktemp("replay")
    folder = write_dataset(
        workdir / "Husky Yard", {"CONCRETE": ["1", "12"], "FLOORING": ["7"]}, imu_hz=50.0, cmd_hz=15.0
    )
    config = tiny_config()
    config["engines"] = {k: config["engines"][k] for k in ENGINES}
    # what this module checks is the dataset's replay: the lab scenario and the validation are cut to one job each
    config["terrains"] = {"grass": config["terrains"]["grass"]}
    config["validation"]["cases"] = {"rest_mu0.8": config["validation"]["cases"]["rest_mu0.8"]}
    config["real_data"]["segments"] = str(COMMITTED[0])  # the committed table itself, by absolute path
    config["real_data"]["classes"]["concrete"] = {"friction": 0.7, "source": "test: a made-up dataset"}
    config["real_data"]["datasets"][NAME] = {"label": "Husky yard", "imu_hz": 50, "commands_hz": 15}
    config["borealtc_dir"] = str(folder)
    write_config(workdir, config)
    before = (git_status(), fingerprints())
    run = snakemake(workdir)
    return workdir, folder, before, run


def test_replay_of_another_dataset_succeeds_under_its_own_name(replay):
    workdir, _, _, run = replay
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    models = (*ENGINES, *tiny_config()["baselines"])  # the reference models are replayed beside the engines
    out = workdir / OUT
    for path in (
        "dataset.yaml",
        "segments.csv",
        "segments.provenance.yaml",
        "logs/concrete/12.parquet",
        "logs/flooring/7.parquet",
    ):
        assert (out / path).is_file(), path
    for table in ("summary", "imu_errors", "pairwise", "rtf", "detail", "runs"):
        assert (workdir / METRICS / f"{table}.csv").is_file(), table
    per_test = pd.read_csv(workdir / METRICS / "per_test.csv", dtype={"run": str})
    assert sorted(zip(per_test.terrain_class, per_test.run, per_test.engine)) == sorted(
        (c, r, e) for c, r in (("concrete", "1"), ("concrete", "12"), ("flooring", "7")) for e in models
    )
    assert (per_test.status == "ok").all() and per_test.error_angular.gt(0).all()
    # the committed segments were compared too, under their own dataset
    committed = pd.read_csv(ROOT / tiny_config()["real_data"]["segments"])
    assert len(list((workdir / "results/traces/segments").rglob("*.parquet"))) == len(models) * len(committed)
    # and the folder's own segments, a case table known only once the checkpoint wrote it
    derived = pd.read_csv(out / "segments.csv", dtype={"run": str})
    assert len(derived) > 0
    compared = pd.read_csv(workdir / f"results/metrics/{NAME}-segments/per_test.csv", dtype={"run": str})
    assert sorted(zip(compared.segment, compared.engine)) == sorted((s, e) for s in derived.segment for e in models)
    assert (compared.status == "ok").all()


def test_simulated_imu_is_compared_at_the_logs_50_hz(replay):
    workdir, _, _, _ = replay
    frame, meta = read_trace(workdir / TRACES / "mujoco" / "concrete" / "12.parquet")
    assert meta["imu_rate_hz"] == pytest.approx(50.0) and meta["real_imu_rate_hz"] == pytest.approx(50.0)
    assert np.median(np.diff(frame["time"])) == pytest.approx(0.02)
    assert len(frame) == pytest.approx(11.93 * 50, abs=1)  # while both streams last (the 15 Hz one ends first)
    windows = pd.read_csv(workdir / METRICS / "detail.csv")
    assert (windows.imu_rate_hz == 50.0).all()


def test_report_names_the_dataset_and_its_rates(replay):
    workdir, folder, _, _ = replay
    html = (workdir / "results" / "report" / "report.html").read_text()
    table = html[html.index('id="real-datasets"') :]
    table = table[: table.index("</table>")]
    assert "Husky yard" in table and str(folder.resolve()) in table and "3 runs" in table
    assert "50 Hz" in table and "15 Hz" in table and "IMU 50 Hz, wheels 15 Hz" in table
    assert "BorealTC" in table and "IMU 100 Hz, wheels 6.5 Hz" in table
    assert 'id="replay-concrete"' in html and 'id="real-concrete"' in html


def test_checkout_is_left_untouched(replay):
    workdir, _, (status, committed), _ = replay
    assert fingerprints() == committed
    assert git_status() == status
    assert planned_jobs(workdir) == []  # and nothing reruns, nothing would rewrite it


def test_a_failing_job_leaves_every_committed_file_in_place(replay):
    workdir, folder, (status, committed), _ = replay
    imu = folder / "CONCRETE" / "imu_12.csv"
    frame = pd.read_csv(imu)
    frame.loc[4, "az"] = np.nan
    frame.to_csv(imu, index=False)
    run = snakemake(workdir)
    assert run.returncode != 0
    assert f"simpick: {imu}: column 'az': empty or NaN value at row 5 (line 6)" in run.stderr
    assert fingerprints() == committed
    assert git_status() == status
    assert not (workdir / OUT / "logs" / "concrete" / "12.parquet").exists()  # a failed job's output, removed
    assert read_metadata(workdir / TRACES / "mujoco" / "flooring" / "7.parquet")["imu_rate_hz"] == 50.0
