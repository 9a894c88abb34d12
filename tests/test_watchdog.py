"""A hung engine is stopped at its time limit and its run recorded as failed."""

import os
import subprocess
import sys
import textwrap


from conftest import ROOT
from simpick.traces import read_trace

HANGING_JOB = textwrap.dedent("""
    import sys, time, yaml
    from simpick import engines
    from simpick.workflow import simulate_job, terrain_job

    class Hanging:
        name = "hanging"
        def version(self):
            return "0"
        def simulate(self, scenario, commands):
            while True:
                time.sleep(0.01)

    sys.modules["hanging_engine"] = sys.modules[__name__]
    engines.ADAPTERS["hanging"] = "hanging_engine:Hanging"
    config = yaml.safe_load(open(sys.argv[1]))
    terrain_job(sys.argv[2] + ".json", "grass", 1, config["terrains"]["grass"])
    health = dict(config["health"], timeout=1.0)
    params = {"engine": "hanging", "engine_settings": {}, "terrain": "grass", "motion_name": "straight",
              "motion": config["motions"]["straight"], "physics": config["physics"], "robot": config["robot"],
              "imu": config["imu"], "health": health, "seed": 1, "kind": "lab", "source": "lab",
              "cases": ["straight"]}
    simulate_job([sys.argv[2]], config["robot"]["urdf"], {"terrain": sys.argv[2] + ".json"}, params)
    print("not reached")
""")


def test_a_hung_engine_is_stopped_and_reported(tmp_path):
    script = tmp_path / "hang.py"
    script.write_text(HANGING_JOB)
    output = tmp_path / "trace.parquet"
    run = subprocess.run([sys.executable, str(script), str(ROOT / "config.yaml"), str(output)], cwd=ROOT,
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    assert "not reached" not in run.stdout
    frame, meta = read_trace(output)
    assert len(frame) == 0
    assert meta["health"]["status"] == "failed"
    assert "hung: no result after 1 s" in meta["health"]["reasons"][0]
    assert (meta["source"], meta["test"], meta["terrain"], meta["motion"]) == ("lab", "grass/straight", "grass", "straight")


HANGING_REPLAY = textwrap.dedent("""
    import sys, time, yaml
    from pathlib import Path
    from simpick import engines
    from simpick.realdata import import_job
    from simpick.workflow import simulate_job
    from conftest import write_dataset

    class Hanging:
        name = "hanging"
        def version(self):
            return "0"
        def simulate(self, scenario, commands):
            while True:
                time.sleep(0.01)

    sys.modules["hanging_engine"] = sys.modules[__name__]
    engines.ADAPTERS["hanging"] = "hanging_engine:Hanging"
    config = yaml.safe_load(open(sys.argv[1]))
    out = sys.argv[2]
    folder = write_dataset(Path(out + ".d"), {"FLOORING": ["7"]}, seconds=3.0)
    import_job(str(folder / "FLOORING" / "imu_7.csv"), str(folder / "FLOORING" / "pro_7.csv"), "FLOORING",
               out + ".log.parquet", {"track": config["robot"]["track"], "declared": {}, "dataset": "yard",
                                      "label": "yard"})
    params = {"engine": "hanging", "engine_settings": {}, "terrain_class": "flooring",
              "class": config["real_data"]["classes"]["flooring"], "physics": config["physics"],
              "robot": config["robot"], "imu": config["imu"], "health": dict(config["health"], timeout=1.0),
              "seed": 1, "kind": "replay", "source": "yard", "cases": ["7"]}
    simulate_job([out], config["robot"]["urdf"], {"log": out + ".log.parquet"}, params)
    print("not reached")
""")


def test_a_hung_replay_is_stopped_and_reported_like_a_run(tmp_path):
    """A replay (a dataset's run or an own log) steps an engine too: the same watchdog, and the
    failed trace names its terrain class and run so the source's compare job lists it."""
    script = tmp_path / "hang_replay.py"
    script.write_text(HANGING_REPLAY)
    output = tmp_path / "replay.parquet"
    run = subprocess.run([sys.executable, str(script), str(ROOT / "config.yaml"), str(output)], cwd=ROOT,
                         capture_output=True, text=True, timeout=120,
                         env={**os.environ, "PYTHONPATH": str(ROOT / "tests")})
    assert run.returncode == 0, run.stderr
    assert "not reached" not in run.stdout
    frame, meta = read_trace(output)
    assert len(frame) == 0
    assert (meta["engine"], meta["terrain"], meta["run"], meta["source"]) == ("hanging", "flooring", "7", "yard")
    assert meta["health"]["status"] == "failed" and "hung: no result after 1 s" in meta["health"]["reasons"][0]


HANGING_BATCH = textwrap.dedent("""
    import sys, time, yaml
    from simpick import engines
    from simpick.workflow import simulate_job

    class Hanging:
        name = "hanging"
        def version(self):
            return "0"
        def simulate(self, scenario, commands):
            while True:
                time.sleep(0.01)

    sys.modules["hanging_engine"] = sys.modules[__name__]
    engines.ADAPTERS["hanging"] = "hanging_engine:Hanging"
    config = yaml.safe_load(open(sys.argv[1]))
    params = {"engine": "hanging", "engine_settings": {}, "terrain_class": "ice",
              "class": config["real_data"]["classes"]["ice"], "physics": config["physics"],
              "robot": config["robot"], "imu": config["imu"], "health": dict(config["health"], timeout=1.0),
              "seed": 1, "kind": "segments", "source": "segments",
              "cases": ["ice-straight-02-0020p23s", "ice-turning-02-0009p46s"]}
    simulate_job([sys.argv[2] + "-a.parquet", sys.argv[2] + "-b.parquet"], config["robot"]["urdf"],
                 {"segments": config["real_data"]["segments"]}, params)
    print("not reached")
""")


def test_a_hung_case_of_a_batch_fails_it_and_the_cases_after_it(tmp_path):
    """The committed segments run a class per job: when one case hangs, the watchdog ends the
    process, so the cases after it are written as failed (not run) traces, never left missing."""
    script = tmp_path / "hang_batch.py"
    script.write_text(HANGING_BATCH)
    run = subprocess.run([sys.executable, str(script), str(ROOT / "config.yaml"), str(tmp_path / "t")], cwd=ROOT,
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    assert "not reached" not in run.stdout
    (_, first), (_, second) = read_trace(tmp_path / "t-a.parquet"), read_trace(tmp_path / "t-b.parquet")
    assert (first["source"], first["segment"], first["terrain"]) == ("segments", "ice-straight-02-0020p23s", "ice")
    assert "hung: no result after 1 s" in first["health"]["reasons"][0]
    assert second["segment"] == "ice-turning-02-0009p46s" and second["health"]["status"] == "failed"
    assert second["health"]["reasons"] == ["not run: ice-straight-02-0020p23s hung before it"]
    assert sorted(first) == sorted(second)  # the same metadata layout
