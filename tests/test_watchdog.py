"""A hung engine is stopped at its time limit and its run recorded as failed."""

import os
import subprocess
import sys
import textwrap

import yaml

from conftest import ROOT, study_config
from simpick.simulate.traces import read_trace

# A calibratable model (the Coulomb baseline's friction parameter) whose simulate never returns, and
# the parameters of a flooring job with it; each test adds the job it stops.
HANGING_MODEL = textwrap.dedent("""
    import sys, time, yaml
    from simpick import engines
    from simpick.engines.baselines import CoulombModel

    class Hanging(CoulombModel):
        name = "hanging"
        def simulate(self, scenario, commands):
            while True:
                time.sleep(0.01)

    sys.modules["hanging_engine"] = sys.modules[__name__]
    engines.ADAPTERS["hanging"] = "hanging_engine:Hanging"
    config = yaml.safe_load(open(sys.argv[1]))
    out = sys.argv[2]
    # what every simulation job reads (simpick.simulate.settings.SimulationParams), and a real case's ground
    sim = {"engine": "hanging", "engine_settings": {}, "physics": config["physics"],
           "robot": {k: v for k, v in config["robot"].items() if k != "urdf"}, "imu": config["imu"],
           "health": config["health"], "seed": 1}
    real = {**sim, "terrain_class": "flooring", "class": config["real_data"]["classes"]["flooring"]}
    calibration = {"source": "segments", "scales": config["calibration"]["scales"], "segment_seconds": 1.0,
                   "n_trials": 2, "startup_trials": 1, "seed": 1, "bounds": {}}
""")


def _run_hanging(tmp_path, name: str, job: str, output):
    """Run ``job`` (after HANGING_MODEL) in a process of its own: the watchdog ends the process."""
    script = tmp_path / f"{name}.py"
    script.write_text(HANGING_MODEL + textwrap.dedent(job) + '\nprint("not reached")\n')
    run = subprocess.run(
        [sys.executable, str(script), str(ROOT / "config.yaml"), str(output)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
        # this tree's package and conftest's helpers
        env={**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT / "src"), str(ROOT / "tests")])},
    )
    assert run.returncode == 0, run.stderr
    assert "not reached" not in run.stdout
    assert "hung: no result after 1 s" in run.stderr  # the job's log says why it stopped


# --- simulate_job: a lab case, a replay, a batch of segments --------------------------------------


def test_a_hung_engine_is_stopped_and_reported(tmp_path):
    output = tmp_path / "trace.parquet"
    _run_hanging(
        tmp_path,
        "hang",
        """
        from simpick.inputs.jobs import terrain_job
        from simpick.simulate.jobs import simulate_job
        terrain_job(out + ".json", "grass", 1, config["terrains"]["grass"])
        params = {**sim, "terrain": "grass", "motions": {"straight": config["motions"]["straight"]},
                  "health": dict(config["health"], timeout=1.0), "kind": "lab", "source": "lab",
                  "cases": ["straight"]}
        simulate_job([out], config["robot"]["urdf"], {"terrain": out + ".json"}, params)
    """,
        output,
    )
    frame, meta = read_trace(output)
    assert len(frame) == 0
    assert meta["health"]["status"] == "failed"
    assert "hung: no result after 1 s" in meta["health"]["reasons"][0]
    assert (meta["source"], meta["test"], meta["terrain"], meta["motion"]) == (
        "lab",
        "grass/straight",
        "grass",
        "straight",
    )


def test_a_hung_replay_is_stopped_and_reported_like_a_run(tmp_path):
    """A replay (a dataset's run or an own log) steps an engine too: the same watchdog, and the
    failed trace names its terrain class and run so the source's compare job lists it."""
    output = tmp_path / "replay.parquet"
    _run_hanging(
        tmp_path,
        "hang_replay",
        """
        from pathlib import Path
        from simpick.real.jobs import import_job
        from simpick.simulate.jobs import simulate_job
        from conftest import write_dataset
        folder = write_dataset(Path(out + ".d"), {"FLOORING": ["7"]}, seconds=3.0)
        import_job(str(folder / "FLOORING" / "imu_7.csv"), str(folder / "FLOORING" / "pro_7.csv"), "FLOORING",
                   out + ".log.parquet", {"track": config["robot"]["track"], "declared": {}, "dataset": "yard",
                                          "label": "yard"})
        params = {**real, "health": dict(config["health"], timeout=1.0), "kind": "replay", "source": "yard",
                  "cases": ["7"]}
        simulate_job([out], config["robot"]["urdf"], {"logs": [out + ".log.parquet"]}, params)
    """,
        output,
    )
    frame, meta = read_trace(output)
    assert len(frame) == 0
    assert (meta["engine"], meta["terrain"], meta["run"], meta["source"]) == ("hanging", "flooring", "7", "yard")
    assert meta["health"]["status"] == "failed" and "hung: no result after 1 s" in meta["health"]["reasons"][0]


def test_a_hung_case_of_a_batch_fails_it_and_the_cases_after_it(tmp_path):
    """The committed segments run a model's segments per job: when one case hangs, the watchdog ends the
    process, so the cases after it are written as failed (not run) traces, never left missing."""
    _run_hanging(
        tmp_path,
        "hang_batch",
        """
        classes = config["real_data"]["classes"]
        params = {**sim, "classes": {c: classes[c] for c in ("flooring", "ice")},
                  "health": dict(config["health"], timeout=1.0), "kind": "segments", "source": "segments",
                  "cases": ["ice-straight-02-0020p23s", "flooring-turning-01-0012p69s"]}
        from simpick.simulate.jobs import simulate_job
        simulate_job([out + "-a.parquet", out + "-b.parquet"], config["robot"]["urdf"],
                     {"segments": config["real_data"]["segments"]}, params)
    """,
        tmp_path / "t",
    )
    (_, first), (_, second) = read_trace(tmp_path / "t-a.parquet"), read_trace(tmp_path / "t-b.parquet")
    assert (first["source"], first["segment"], first["terrain"]) == ("segments", "ice-straight-02-0020p23s", "ice")
    assert "hung: no result after 1 s" in first["health"]["reasons"][0]
    assert second["segment"] == "flooring-turning-01-0012p69s" and second["health"]["status"] == "failed"
    assert second["terrain"] == "flooring"
    assert second["health"]["reasons"] == ["not run: ice-straight-02-0020p23s hung before it"]
    assert sorted(first) == sorted(second)  # the same metadata layout


def test_a_hung_validation_case_fails_it_and_the_cases_after_it(tmp_path):
    """An engine's validation cases run in one job, each under the watchdog with its share of the
    job's limit: the case that hangs and the ones after it are recorded failed, the ones before it
    keep their results, and the summary lists every case."""
    import json

    from simpick.score.mechanics import failures
    from simpick.studies.validation.judge import summarise

    names = ["a_rest", "b_slide", "c_rest"]
    _run_hanging(
        tmp_path,
        "validate",
        """
        from simpick.studies.validation import cases, job
        def hang(setup, params):
            while True:
                time.sleep(0.01)
        cases.RUNNERS["slide"] = hang
        rest = {"kind": "rest", "mu": 0.8, "duration": 1.2}
        cases = {"a_rest": rest, "b_slide": {"kind": "slide", "v": 0.5, "mu": 0.3}, "c_rest": rest}
        params = {"engine": "pybullet", "engine_settings": config["engines"]["pybullet"], "cases": cases,
                  "physics": {"timestep": config["physics"]["timestep"]}, "robot": sim["robot"]}
        # three cases in a 3 s job: 1 s each
        job.validate_job([f"{out}/{name}.json" for name in cases], config["robot"]["urdf"], params,
                                timeout=3.0)
    """,
        tmp_path / "records",
    )
    records = [json.loads((tmp_path / "records" / f"{name}.json").read_text()) for name in names]
    assert [r["status"] for r in records] == ["ok", "failed", "failed"]
    assert records[1]["reasons"][0].startswith("hung: no result after 1 s") and records[1]["kind"] == "slide"
    assert records[2]["reasons"] == ["not run: b_slide hung before it"]
    tolerances = study_config()["validation"]["tolerances"]
    summary = summarise(records, tolerances)
    assert set(summary.case) == set(names)
    assert failures(summary) == {"pybullet": ["b_slide", "c_rest"]}


# --- the other jobs that step an engine: CPU load, a sweep point, calibration -----------------------


def test_a_hung_cpu_load_job_is_recorded_failed_and_left_out_of_the_scores(tmp_path):
    import json

    from simpick.score.jobs import score_provenance

    output = tmp_path / "cpu" / "hanging.json"
    _run_hanging(
        tmp_path,
        "cpu",
        """
        from simpick.inputs.jobs import terrain_job
        from simpick.simulate.jobs import cpu_job
        terrain_job(out + ".terrain.json", "grass", 1, config["terrains"]["grass"])
        params = {**sim, "terrain": "grass", "motion_name": "straight", "motion": config["motions"]["straight"],
                  "cpu_load": config["cpu_load"]}
        cpu_job(out, out + ".terrain.json", config["robot"]["urdf"], params, timeout=1.0)
    """,
        output,
    )
    record = json.loads(output.read_text())
    assert record["health"]["status"] == "failed"
    assert "hung: no result after 1 s" in record["health"]["reasons"][0]
    assert record["average"]["load_percent"] is None and record["intense"]["load_percent"] is None
    # the scores' provenance lists it among the failed CPU runs, not among the scored engines
    (tmp_path / "errors.csv").write_text("engine,quantity,tests,excluded\n")
    (tmp_path / "rtf.csv").write_text("engine,tests,excluded\n")
    cpu = score_provenance(["hanging"], str(tmp_path / "errors.csv"), str(tmp_path / "rtf.csv"), [str(output)], {})[
        "cpu"
    ]
    assert cpu["engines"] == [] and cpu["excluded"][0]["engine"] == "hanging"
    assert "hung: no result after 1 s" in cpu["excluded"][0]["why"]


def test_a_hung_sweep_point_records_every_segment_failed(tmp_path):
    import pandas as pd

    from simpick.studies.sweep import summarise

    output = tmp_path / "sweep.csv"
    _run_hanging(
        tmp_path,
        "sweep",
        """
        import pandas as pd
        from simpick.studies.sweep import sweep_job
        segments = pd.read_csv(config["real_data"]["segments"])
        params = {**sim, "classes": {"flooring": config["real_data"]["classes"]["flooring"]},
                  "health": dict(config["health"], timeout=1.0), "kind": "segments", "source": "segments",
                  "cases": list(segments.segment[segments.terrain_class == "flooring"])}
        sweep_job({"segments": config["real_data"]["segments"], "urdf": config["robot"]["urdf"]}, params,
                  {"track": config["robot"]["track"]}, out)
    """,
        output,
    )
    runs = pd.read_csv(output, dtype={"run": str})
    config = study_config()
    segments = pd.read_csv(ROOT / config["real_data"]["segments"])
    assert len(runs) == (segments.terrain_class == "flooring").sum() > 1
    # the first case hung; the simulate job's watchdog writes the cases after it as not run
    assert (runs.status == "failed").all() and runs.reasons.iloc[0].startswith("hung: no result after 1 s")
    assert runs.reasons.iloc[1:].str.startswith("not run: ").all()
    # the summary counts them as failed and averages none of them
    summary = summarise(runs).iloc[0]
    assert summary.n_failed == summary.n_segments == len(runs) and summary.n_compared == 0
    assert pd.isna(summary.error_angular)


def test_a_hung_calibration_and_its_evaluation_are_recorded_failed(tmp_path):
    import pandas as pd

    from simpick.studies.calibration.summary import summarise

    best, trials, evaluation = tmp_path / "best.yaml", tmp_path / "trials.csv", tmp_path / "evaluation.csv"
    setup = """
        import pandas as pd
        from simpick.studies.calibration.split import split_job
        segments = config["real_data"]["segments"]
        units = pd.read_csv(segments, dtype={"run": str})
        units = units[units.terrain_class == "flooring"]
        split = out + ".split.csv"
        split_job([[r.terrain_class, r.run, r.segment] for r in units.itertuples()], 0.5, 1, split)
        inputs = {"split": split, "segments": segments, "urdf": config["robot"]["urdf"]}
    """
    _run_hanging(
        tmp_path,
        "calibrate",
        setup
        + f"""
        from simpick.studies.calibration.search import calibrate_job
        calibrate_job(inputs, real, calibration, {{"best": out, "trials": {str(trials)!r}}}, timeout=1.0)
    """,
        best,
    )
    record = yaml.safe_load(best.read_text())
    assert record["status"] == "failed" and record["parameters"] == {}
    assert "hung: no result after 1 s" in record["reasons"][0]
    assert trials.is_file()

    _run_hanging(
        tmp_path,
        "evaluate",
        setup
        + f"""
        from simpick.studies.calibration.search import evaluate_job
        inputs["best"] = {str(best)!r}
        # the evaluation's settings: the search's less its budget, seed and bounds (the plan's search=False)
        evaluation = {{k: calibration[k] for k in ("source", "scales", "segment_seconds")}}
        evaluate_job(inputs, real, evaluation, out, timeout=1.0)
    """,
        evaluation,
    )
    rows = pd.read_csv(evaluation, dtype={"run": str, "unit": str})
    assert (rows.status == "failed").all()
    assert set(rows.variant) == {"configured", "calibrated"}
    configured, calibrated = rows[rows.variant == "configured"], rows[rows.variant == "calibrated"]
    assert configured.reasons.str.startswith("hung: no result after 1 s").all()
    assert calibrated.reasons.str.startswith("no calibrated parameters: hung").all()
    summary = summarise(rows, {("hanging", "flooring"): record})
    assert (summary.n_failed_configured == summary.n_units).all()
    assert (summary.n_failed_calibrated == summary.n_units).all() and (summary.parameters == "").all()


def test_after_a_hung_case_a_fresh_process_runs_the_cases_after_it(tmp_path):
    """A simulate job given its log (the workflow's) does not give up the cases after a hung one: its process
    is replaced by a fresh one that runs them (simpick.simulate.jobs.resume), appending to the log. Here every
    case hangs, so each is recorded hung by the process that ran it, none "not run"; the job's hand-over file
    is gone once read."""
    # the hanging model, registered in every Python this test starts (the fresh process included)
    site = tmp_path / "site"
    site.mkdir()
    (site / "sitecustomize.py").write_text(
        "from simpick import engines\nengines.ADAPTERS['hanging'] = 'hanging_model:Hanging'\n"
    )
    (site / "hanging_model.py").write_text(
        "import time\nfrom simpick.engines.baselines import CoulombModel\n\n\n"
        "class Hanging(CoulombModel):\n    name = 'hanging'\n\n    def simulate(self, scenario, commands):\n"
        "        while True:\n            time.sleep(0.01)\n"
    )
    log = tmp_path / "job.log"
    job = f"""
        classes = config["real_data"]["classes"]
        params = {{**sim, "classes": {{c: classes[c] for c in ("flooring", "ice")}},
                  "health": dict(config["health"], timeout=1.0), "kind": "segments", "source": "segments",
                  "cases": ["ice-straight-02-0020p23s", "flooring-turning-01-0012p69s"]}}
        from simpick.joblog import logged
        from simpick.simulate.jobs import simulate_job
        with logged({str(log)!r}):
            simulate_job([out + "-a.parquet", out + "-b.parquet"], config["robot"]["urdf"],
                         {{"segments": config["real_data"]["segments"]}}, params, log={str(log)!r})
    """
    script = tmp_path / "resume.py"
    script.write_text(HANGING_MODEL + textwrap.dedent(job) + '\nprint("not reached")\n')
    path = os.pathsep.join([str(site), str(ROOT / "src"), str(ROOT / "tests")])
    run = subprocess.run(
        [sys.executable, str(script), str(ROOT / "config.yaml"), str(tmp_path / "t")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "PYTHONPATH": path},
    )
    assert run.returncode == 0, run.stderr
    assert "not reached" not in run.stdout
    (_, first), (_, second) = read_trace(tmp_path / "t-a.parquet"), read_trace(tmp_path / "t-b.parquet")
    assert first["segment"] == "ice-straight-02-0020p23s" and second["segment"] == "flooring-turning-01-0012p69s"
    for meta in (first, second):
        assert meta["health"]["status"] == "failed" and "hung: no result after 1 s" in meta["health"]["reasons"][0]
    text = log.read_text()
    assert "the 1 case(s) after it go on in a fresh process" in text and text.count("hung: no result after 1 s") == 2
    assert not (tmp_path / "job.log.resume.json").exists()
