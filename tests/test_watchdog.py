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
              "imu": config["imu"], "health": health, "seed": 1}
    simulate_job(sys.argv[2], sys.argv[2] + ".json", config["robot"]["urdf"], params)
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


HANGING_REPLAY = textwrap.dedent("""
    import sys, time, yaml
    from pathlib import Path
    from simpick import engines
    from simpick.realdata import import_job, replay_job
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
              "seed": 1}
    replay_job(out + ".log.parquet", config["robot"]["urdf"], out, params)
    print("not reached")
""")


def test_a_hung_replay_is_stopped_and_reported_like_a_run(tmp_path):
    """A replay (a dataset's run or an own log) steps an engine too: the same watchdog, and the
    failed trace names its terrain class and run so replay_metrics lists it."""
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
    assert (meta["engine"], meta["terrain"], meta["run"]) == ("hanging", "flooring", "7")
    assert meta["health"]["status"] == "failed" and "hung: no result after 1 s" in meta["health"]["reasons"][0]
