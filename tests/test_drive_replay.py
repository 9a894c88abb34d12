"""DRIVE steps replayed in an engine (simpick.simulate.steps) and compared with the real robot
(simpick.compare.steps).

Sessions are cut at test time from the shared DRIVE files (a few steps under tmp_path; nothing of DRIVE is
committed). The robot is the Warthog with its rockers fixed to the chassis (written to tmp_path from the
committed description): every engine runs it today, while the rockers' suspension is another piece of work;
the code under test reads whatever robot the config names. One fast engine (MuJoCo).
"""

import re
import subprocess

import numpy as np
import pandas as pd
import pytest

from conftest import ROOT, SHARED, study_config
from simpick.errors import InputError
from simpick.simulate import steps as SD
from simpick.sources import drive as DS

CALIB = SHARED / "data" / "drive" / "calib_data"
ASPHALT = "warthog_wheels_asphalt"
GRASS = "warthog_wheels_grass_2024_8_8_16h19s23"
pytestmark = pytest.mark.skipif(
    not CALIB.is_dir(), reason=f"DRIVE sessions not present at {CALIB} (the shared data folder; see its README)"
)


def fixed_rocker_warthog(folder):
    """The committed Warthog with its two rocker joints fixed (no suspension): a plain four-wheel robot."""
    text = (ROOT / "resources" / "robot" / "warthog.urdf").read_text()
    text = text.replace('type="revolute"', 'type="fixed"')
    text = re.sub(r"\s*<(mimic|limit|dynamics)[^>]*/>", "", text)
    path = folder / "warthog_fixed.urdf"
    path.write_text(text)
    return path


def warthog_config(tmp_path, engines=("mujoco",)):
    from conftest import tiny_config

    config = tiny_config(tmp_path)
    config["engines"] = {e: config["engines"][e] for e in engines}
    config["baselines"] = {"coulomb": {}}
    config["robot"] = {
        "urdf": str(fixed_rocker_warthog(tmp_path)),
        "label": "Clearpath Warthog (rockers fixed)",
        "track": 1.08,  # DRIVE's wheel_baseline (its _warthog.config.yaml)
        "max_wheel_torque": 400.0,  # assumption for the test: above what the steps need
    }
    # the Husky's 0.5 rad/s tracking limit is 0.08 m/s at its rim; the Warthog's measured wheel speeds change
    # by several rad/s within a quarter second at a step's start, which a servo follows with a lag
    config["health"]["wheel_tracking"] = 1.5
    config["real_data"]["robot"] = None
    return config


def params_of(config, engine, terrain):
    from simpick.config import plain, validate_or_exit
    from simpick.sources.base import model_settings, real_params

    study = validate_or_exit(config)
    return real_params(study, engine, model_settings(plain(study, config), engine), terrain)


@pytest.fixture(scope="module")
def asphalt(tmp_path_factory):
    from simpick.real.drive import open_drive, replay_cases, step_table, wheel_table
    from test_drive import cut

    root = tmp_path_factory.mktemp("drive")
    folder = cut(root / "calib_data", ASPHALT, steps=25)
    data = open_drive(folder)
    return {
        "root": root,
        "folder": folder,
        "session": data.sessions[0],
        "wheels": wheel_table(data.sessions[0]),
        "cases": replay_cases(data),
        "steps": step_table(data),
    }


def test_subsets_are_deterministic_and_skip_the_zero_command():
    cases = pd.DataFrame({"session": ["b"] * 12 + ["a"] * 7, "step": list(range(12)) + list(range(7))})
    one = SD.select_steps(cases.sample(frac=1, random_state=1), every=3, max_steps_per_session=3)
    two = SD.select_steps(cases.sample(frac=1, random_state=2), every=3, max_steps_per_session=3)
    assert one.to_dict("records") == two.to_dict("records")
    assert [(r["session"], r["step"]) for r in one.to_dict("records")] == [
        ("a", 1),
        ("a", 4),
        ("b", 1),
        ("b", 4),
        ("b", 7),
    ]
    assert len(SD.select_steps(cases)) == 11 + 6  # every step but each session's step 0
    with pytest.raises(ValueError):
        SD.select_steps(cases, every=0)


def test_a_missing_session_gives_one_clear_error():
    cases = pd.DataFrame({"session": ["s1"], "step": [1]})
    with pytest.raises(InputError) as err:
        SD.session_cases(cases, "s2", "results/drive/drive/cases.csv")
    text = str(err.value)
    assert "cases.csv" in text and "'s2'" in text and "s1" in text


def test_models_not_configured_are_refused():
    assert DS.models(None, ["mujoco", "coulomb"]) == ["mujoco", "coulomb"]
    assert DS.models(["coulomb", "mujoco"], ["mujoco", "coulomb"]) == ["mujoco", "coulomb"]
    assert DS.models(["mujoco", "dart"], ["mujoco"], {"dart": "not installed"}) == ["mujoco"]
    with pytest.raises(InputError, match="drive_replay.models"):
        DS.models(["bullet"], ["mujoco"])


def test_the_warm_up_holds_the_start_wheels_then_follows_the_measured_ones(asphalt):
    case = asphalt["cases"][asphalt["cases"].step == 5].iloc[0]
    samples = SD.step_samples(asphalt["wheels"], ASPHALT, 5)
    # the wheels table the reader writes holds what the session gives an engine to replay, exactly
    assert samples[["time", "v_left", "v_right"]].reset_index(drop=True).equals(asphalt["session"].wheel_commands(5))
    left, right, end = SD.step_wheels(samples, case, warmup=3.0, dt=0.001)
    r = asphalt["session"].meta["geometry"]["wheel_radius"]
    assert len(left) == int(round((3.0 + end) / 0.001))
    assert left[0] == pytest.approx(0.001 * r * case.start_wheel_left, abs=1e-9)  # ramp from rest
    assert left[2500] == pytest.approx(r * case.start_wheel_left)  # held after the 1 s ramp
    measured = asphalt["session"].wheel_commands(5)
    steady = (measured.time > case.steady_start).to_numpy()
    t = np.arange(1, len(left) + 1) * 0.001 - 3.0
    inside = t > case.steady_start
    # the interpolated speeds keep the steady part's mean of the measured ones (within the hold's quantisation)
    assert right[inside].mean() == pytest.approx(measured.v_right[steady].mean(), abs=0.05)


@pytest.fixture(scope="module")
def replayed(asphalt):
    cases = SD.select_steps(asphalt["cases"], every=2, max_steps_per_session=12)
    config = warthog_config(asphalt["root"])
    urdf = config["robot"]["urdf"]
    out = {}
    for label, friction in (("asphalt", None), ("ice", 0.08)):
        p = params_of(config, "mujoco", "asphalt")
        if friction is not None:
            p["class"] = {"friction": friction, "source": "a deliberately wrong friction, for the test"}
        out[label] = SD.replay_session(asphalt["wheels"], cases, urdf, p, warmup=3.0)
    return out


def test_a_replay_reproduces_the_lidar_speed_and_a_wrong_friction_does_not(asphalt, replayed):
    from simpick.compare.steps import step_errors

    trace, rows = replayed["asphalt"]
    assert len(rows) == 12 and set(trace.step) == set(rows.step)
    errors = step_errors(asphalt["cases"], asphalt["steps"], rows)
    ok = errors[errors.status == "ok"]
    assert len(ok) >= 9, errors[["step", "reasons"]]
    # MuJoCo's Warthog on asphalt friction, driven by the measured wheels from the previous step's state: its
    # steady forward speed within 0.4 m/s of the lidar's (measured: 0.22) on the median step (the real robot
    # drives at 0.5-4 m/s here; its ICP speed reads below the kinematic one, and more so while it turns)
    assert ok.speed_error.median() < 0.4, ok[["step", "v_real", "v_sim"]]
    # and it starts each step near the real robot's state (the warm-up)
    assert ok.start_dv.abs().median() < 0.3 and ok.start_dwz.abs().median() < 0.2
    wrong = step_errors(asphalt["cases"], asphalt["steps"], replayed["ice"][1])
    assert wrong.speed_error.median() > 2 * ok.speed_error.median()  # measured: 0.69 on ice-like 0.08


def test_replays_are_deterministic(asphalt, replayed):
    cases = SD.select_steps(asphalt["cases"], every=2, max_steps_per_session=2)
    config = warthog_config(asphalt["root"])
    _, rows = SD.replay_session(
        asphalt["wheels"], cases, config["robot"]["urdf"], params_of(config, "mujoco", "asphalt"), warmup=3.0
    )
    first = replayed["asphalt"][1].head(2)
    for column in ("sim_v", "sim_yaw_rate", "sim_start_vx"):
        assert rows[column].to_numpy() == pytest.approx(first[column].to_numpy(), abs=0, rel=0)


def test_a_step_is_a_case_of_the_generic_simulate_and_compare_jobs(tmp_path, asphalt, replayed):
    """The steps kind (simpick.simulate.jobs.PREPARE, simpick.compare.kinds.BY_KIND) drives and compares a step
    unit as the session job does: one trace per step, the same step rows to the last bit, the same errors."""
    from simpick.compare.kinds import BY_KIND
    from simpick.compare.steps import step_errors
    from simpick.simulate.jobs import PREPARE, simulate_job

    assert PREPARE["steps"] == "simpick.simulate.steps:prepare_step"
    cases = SD.select_steps(asphalt["cases"], every=2, max_steps_per_session=2)
    config = warthog_config(asphalt["root"])
    p = params_of(config, "mujoco", "asphalt")
    files = {"cases": str(tmp_path / "cases.csv"), "steps": str(tmp_path / "steps.csv")}
    asphalt["cases"].to_csv(files["cases"], index=False)
    asphalt["steps"].to_csv(files["steps"], index=False)
    asphalt["wheels"].to_parquet(tmp_path / "wheels.parquet")
    # a steps unit's params (simpick.simulate.steps.StepUnitParams): every class's ground, none of its own
    params = {k: v for k, v in p.items() if k not in ("terrain_class", "class")} | {
        "classes": {"asphalt": p["class"]},
        "replay": {"warmup": 3.0},
        "kind": "steps",
        "source": "drive",
        "cases": list(cases.case),
    }
    traces = [str(tmp_path / f"{n}.parquet") for n in range(len(cases))]
    simulate_job(traces, config["robot"]["urdf"], {**files, "wheels": str(tmp_path / "wheels.parquet")}, params)
    per_test, detail, runs = BY_KIND["steps"](traces, files, {})
    first = replayed["asphalt"][1].head(2)
    assert list(detail.case) == list(first.case) and list(runs.test) == list(first.case)
    for column in ("sim_v", "sim_yaw_rate", "sim_heading", "sim_start_vx", "sim_start_wz", "start_heading_deg"):
        assert detail[column].to_numpy() == pytest.approx(first[column].to_numpy(), abs=0, rel=0), column
    expected = step_errors(asphalt["cases"], asphalt["steps"], first)
    for column in ("gain_error", "heading_error", "speed_error", "start_dv"):
        assert per_test[column].to_numpy() == pytest.approx(expected[column].to_numpy(), abs=0, rel=0, nan_ok=True)


def test_the_comparison_reports_failures_and_pairs_by_step(asphalt, replayed):
    from simpick.compare.steps import step_errors, summary_table
    from simpick.score.steps import outcomes

    rows = replayed["asphalt"][1].copy()
    # a second "engine": the same steps with a slower speed, one step diverged
    other = rows.assign(engine="slow", sim_v=rows.sim_v * 0.7)
    other.loc[other.index[0], ["status", "reasons"]] = ["failed", "non-finite position (simulation diverged)"]
    errors = step_errors(asphalt["cases"], asphalt["steps"], pd.concat([rows, other]))
    assert errors[(errors.engine == "slow") & (errors.status != "ok")].speed_error.isna().all()
    summary = summary_table(errors, asphalt["steps"], 1.0)
    slow = summary[(summary.engine == "slow") & (summary.session == "all") & (summary.terrain_class == "all")].iloc[0]
    assert slow.failed == 1 and "diverged" in slow.failed_reasons
    assert slow.steps == 12

    verdict = study_config()["verdict"]
    table = outcomes(errors, asphalt["steps"], ["mujoco", "slow"], verdict, 1.0)
    speed = table[(table.metric == "speed_error") & (table.scope == "all")].set_index("engine")
    assert speed.loc["mujoco", "outcome"] in ("best", "too few runs")
    # the diverged step is averaged for no engine: both are judged on the 11 steps both completed, and the
    # failure is the slow engine's, with its reason
    assert speed.loc["slow", "n_runs"] == speed.loc["mujoco", "n_runs"] == 11
    assert speed.loc["slow", "runs_failed"] == 1 and "diverged" in speed.loc["slow", "failed_runs"]
    assert (table.paired_by == "step").all()
    # the metric's own unit is kept beside it (the decision tree prints it after each value)
    assert set(table.unit.fillna("")) == {"", "rad", "m/s"}, set(table.unit)


@pytest.mark.workflow
def test_the_workflow_replays_a_named_folder_and_writes_the_verdict(tmp_path):
    from conftest import snakemake, write_config
    from test_drive import _git_status, cut

    data = tmp_path / "calib_data"
    cut(data, ASPHALT, steps=8)
    cut(data, GRASS, steps=8)
    config = warthog_config(tmp_path)
    config["validation"]["cases"] = {"rest_mu0.8": config["validation"]["cases"]["rest_mu0.8"]}
    config["drive_dir"] = str(data)
    config["drive_replay"] = {"every": 3, "max_steps_per_session": 2}
    write_config(tmp_path, config)
    before = _git_status()
    targets = [f"results/drive/drive/{t}.csv" for t in ("errors", "summary", "outcomes")]
    run = snakemake(tmp_path, "--cores", "2", *targets)
    assert run.returncode == 0, run.stderr[-3000:]
    errors = pd.read_csv(tmp_path / targets[0])
    assert set(errors.engine) == {"mujoco", "coulomb"}
    assert sorted(set(zip(errors.session, errors.step))) == [(ASPHALT, 1), (ASPHALT, 4), (GRASS, 1), (GRASS, 4)]
    assert (tmp_path / "results/drive/drive/replay/mujoco" / f"{GRASS}.parquet").is_file()
    outcomes = pd.read_csv(tmp_path / targets[2])
    assert set(outcomes.engine) == {"mujoco"}  # reference models are shown, never judged
    assert _git_status() == before
    # the calibration calibrates the models calibration.models names, and no other
    config["calibration"] = {**config["calibration"], "models": ["coulomb"]}
    write_config(tmp_path, config)
    run = snakemake(tmp_path, "-n", "drive_calibration")
    assert run.returncode == 0, run.stderr[-3000:]
    planned = run.stdout + run.stderr
    assert "model=coulomb" in planned and "model=mujoco" not in planned
    # a model the study does not configure: one line, no job
    config["drive_replay"] = {"models": ["dart"]}
    write_config(tmp_path, config)
    run = snakemake(tmp_path, "-n", *targets)
    assert run.returncode != 0 and "drive_replay.models" in run.stderr
    assert subprocess.run(["git", "status", "--porcelain"], cwd=ROOT, capture_output=True, text=True).stdout == before


def test_the_report_section_is_titled_from_the_robot_and_absent_without_outputs(tmp_path, asphalt, replayed):

    from simpick.compare.steps import step_errors, summary_table
    from simpick.report.steps import render_drive_section
    from simpick.score.steps import outcomes

    assert render_drive_section(tmp_path, "Clearpath Warthog") is None
    errors = step_errors(asphalt["cases"], asphalt["steps"], replayed["asphalt"][1])
    verdict = study_config()["verdict"]
    errors.to_csv(tmp_path / "errors.csv", index=False)
    summary_table(errors, asphalt["steps"], 1.0).to_csv(tmp_path / "summary.csv", index=False)
    outcomes(errors, asphalt["steps"], ["mujoco"], verdict, 1.0).to_csv(tmp_path / "outcomes.csv", index=False)
    from simpick.real.drive import turning_table

    turning_table(asphalt["steps"]).to_csv(tmp_path / "turning.csv", index=False)
    html = render_drive_section(tmp_path, "Clearpath Warthog")
    assert "Against the real Clearpath Warthog" in html and "mujoco" in html and "asphalt" in html
    # the asphalt session's step 18 has a steady window whose ICP moved against the wheels (test_drive.py)
    assert "1 step had a\nsteady window whose ICP moved against the driven wheels" in html
    assert "wheel_separation_multiplier" not in html  # no calibration named: no calibration table
    # the calibration's held-out table (simpick.studies.calibration.steps.TURNING_COLUMNS), both variants
    from simpick.studies.calibration.steps import TURNING_COLUMNS

    rows = [
        ["asphalt", "mujoco", v, 8, 0.559, g, 1.08 / (0.559 * 1.12), 1.08 / (g * 1.12)]
        for v, g in (("configured", 0.619), ("calibrated", 0.571))
    ]
    pd.DataFrame(rows, columns=TURNING_COLUMNS).to_csv(tmp_path / "cal.csv", index=False)
    html = render_drive_section(tmp_path, "Clearpath Warthog", tmp_path / "cal.csv")
    assert "wheel_separation_multiplier" in html and "<td>1.73</td>" in html and "1.56 -&gt; 1.69" in html


def test_calibration_on_drive_steps_splits_searches_and_gives_the_multiplier(tmp_path, asphalt):
    import yaml

    from simpick.config import plain, validate_or_exit
    from simpick.real.drive import open_drive, write_tables
    from simpick.sources.base import model_settings, simulation_params
    from simpick.studies.calibration import steps as DC

    tables = {k: str(tmp_path / f"{k}.csv") for k in ("cases", "steps", "sessions")} | {
        "wheels": str(tmp_path / "wheels.parquet")
    }
    write_tables(open_drive(asphalt["folder"]), tables)
    config = warthog_config(tmp_path)
    study = validate_or_exit(config)
    pc = plain(study, config)
    settings = {
        "source": "drive",
        "scales": pc["calibration"]["scales"],
        "n_trials": 2,
        "startup_trials": 1,
        "seed": 11,
        "bounds": {},
        "test_fraction": 0.5,
    }
    params = {
        "engine": "mujoco",
        "terrain_class": "asphalt",
        "calibration": settings,
        "replay": {"every": 3, "max_steps_per_session": 6, "warmup": 3.0},
        "case": simulation_params(study, "mujoco", model_settings(pc, "mujoco")),
        "classes": pc["real_data"]["classes"],
    }
    out = {
        k: str(tmp_path / "cal" / f"{k}.{'yaml' if k == 'best' else 'csv'}")
        for k in ("best", "trials", "evals", "split")
    }
    DC.calibrate_job({**tables, "urdf": config["robot"]["urdf"]}, params, out, 600)
    split = pd.read_csv(out["split"])
    assert set(split.set) == {"train", "test"} and len(split) == 6
    best = yaml.safe_load(open(out["best"]))
    assert best["status"] == "ok" and set(best["train_units"]) == set(split[split.set == "train"].unit)
    evals = pd.read_csv(out["evals"])
    assert set(evals.variant) == {"configured", "calibrated"} and len(evals) == 12
    result = {k: str(tmp_path / f"cal_{k}.csv") for k in ("summary", "turning")}
    DC.summary_job(
        {"evals": [out["evals"]], "bests": [out["best"]], **tables, "urdf": config["robot"]["urdf"]},
        {"statistics": pc["statistics"]},
        result,
    )
    turning = pd.read_csv(result["turning"])
    row = turning[turning.variant == "configured"].iloc[0]
    # DRIVE's baseline 1.08 m over the gain times the description's wheel separation (1.12 m)
    assert row.multiplier_real == pytest.approx(1.08 / (row.gain_real * 1.12))
    assert 0.5 < row.gain_real < 0.7 and 1.3 < row.multiplier_real < 1.9
    summary = pd.read_csv(result["summary"])
    assert {"test", "train"} == set(summary.set) and "change_verdict" in summary


def session_job(tmp_path, asphalt, classes: dict):
    """(inputs, params) of rule drive_replay's job on the asphalt session's tables: a session's params
    (simpick.simulate.steps.SessionReplayParams) with ``classes`` as every class's ground, none of its own."""
    from simpick.real.drive import open_drive, write_tables

    tables = {"cases": str(tmp_path / "cases.csv"), "wheels": str(tmp_path / "wheels.parquet")}
    write_tables(open_drive(asphalt["folder"]), tables)
    config = warthog_config(tmp_path)
    params = {k: v for k, v in params_of(config, "mujoco", "asphalt").items() if k not in ("terrain_class", "class")}
    params |= {
        "classes": classes,
        "replay": {"every": 5, "max_steps_per_session": 1, "warmup": 3.0},
        "session": ASPHALT,
    }
    return {**tables, "urdf": config["robot"]["urdf"]}, params


def test_a_session_on_a_terrain_without_a_ground_model_is_refused_in_one_line(tmp_path, asphalt):
    inputs, params = session_job(tmp_path, asphalt, {"snow": {"friction": 0.2, "source": "x"}})
    outputs = {"trace": str(tmp_path / "r.parquet"), "steps": str(tmp_path / "r.csv")}
    with pytest.raises(InputError, match="real_data.classes.*'asphalt'"):
        SD.replay_job(inputs, params, outputs, 60)
    assert not (tmp_path / "r.csv").exists()


def test_a_calibrated_profile_s_replay_merges_its_fit_over_its_settings(tmp_path, asphalt, monkeypatch):
    """Rule drive_replay gives a calibrated profile's job its fit's file: the steps are replayed with the fitted
    settings over the plan-time (tuned) ones, and without the file with the plan's."""
    inputs, params = session_job(tmp_path, asphalt, {"asphalt": {"friction": 0.75, "source": "x"}})
    seen = []

    def replay_session(wheels, chosen, urdf, case_params, warmup, where):
        seen.append(dict(case_params.engine_settings))
        return pd.DataFrame(columns=SD.TRACE_COLUMNS), pd.DataFrame({"case": []})

    monkeypatch.setattr(SD, "replay_session", replay_session)
    fit = tmp_path / "mujoco.yaml"
    fit.write_text("settings:\n  friction_ratio: 0.81\n")
    outputs = {"trace": str(tmp_path / "r.parquet"), "steps": str(tmp_path / "r.csv")}
    SD.replay_job({**inputs, "calibrated": str(fit)}, params, outputs, 60)
    SD.replay_job(inputs, params, outputs, 60)
    assert seen[0]["friction_ratio"] == 0.81
    assert seen[1].get("friction_ratio") == params["engine_settings"].get("friction_ratio") != 0.81
