"""A hung engine is stopped at its time limit and its run recorded as failed."""

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
