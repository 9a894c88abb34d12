"""Real data through the engines: segments, replay and their comparison."""

import numpy as np
import pandas as pd
import pytest
import yaml

from conftest import ROOT, SHARED, study_config
from simpick.real.logs import RealLog
from simpick.real.segments import COLUMNS, find_segments, load_segments
from simpick.simulate.real import replay_log

BOREALTC = SHARED / "data" / "borealtc"
CONFIG = study_config()
needs_borealtc = pytest.mark.skipif(not BOREALTC.is_dir(), reason=f"BorealTC logs not found at {BOREALTC}")


def synthetic_log() -> RealLog:
    """10 s straight at 0.3 m/s, then 10 s turning left (w = 0.4 rad/s) with a yaw gain of 0.6."""
    t = np.arange(0, 20, 0.01)
    turning = t >= 10
    wz = np.where(turning, 0.6 * 0.4, 0.0)
    imu = pd.DataFrame({"time": t, "ax": 0.0, "ay": 0.0, "az": 9.81, "wx": 0.0, "wy": 0.0, "wz": wz})
    tc = np.arange(0, 20, 1 / 6.5)
    w = np.where(tc >= 10, 0.4, 0.0)
    commands = pd.DataFrame({"time": tc, "v_left": 0.3 - w * 0.555 / 2, "v_right": 0.3 + w * 0.555 / 2})
    return RealLog(
        imu=imu,
        commands=commands,
        meta={"dataset": "synthetic", "run_id": "00", "terrain_class": "FLOOR", "name": "synthetic"},
    )


def test_segments_are_found_classified_and_measured():
    rows = find_segments(
        synthetic_log(), tolerance=0.02, min_duration=4.0, max_duration=6.0, settle=1.0, min_turn=0.1, track=0.555
    )
    assert [r["kind"] for r in rows] == ["straight", "turning"]
    straight, turning = rows
    assert straight["duration"] == pytest.approx(6.0, abs=0.2)  # capped at max_duration
    assert turning["w"] == pytest.approx(0.4) and turning["v"] == pytest.approx(0.3)
    assert turning["yaw_rate_gain"] == pytest.approx(0.6)
    assert turning["linear_z_mean"] == pytest.approx(9.81)
    assert set(COLUMNS) - {"segment"} <= set(straight)


def test_committed_segments_table_is_valid_and_covers_every_class():
    table = load_segments(ROOT / CONFIG["real_data"]["segments"])
    # every BorealTC class has segments; the config's other classes (DRIVE's grass and gravel) have none here
    assert set(table.terrain_class) == {"asphalt", "flooring", "ice", "sandy_loam", "snow"}
    assert set(table.terrain_class) <= set(CONFIG["real_data"]["classes"])
    assert table.segment.is_unique
    assert (table.duration > 0).all() and table.notna()[[c for c in COLUMNS if c != "yaw_rate_gain"]].all().all()
    turning = table[table.kind == "turning"]
    assert turning.yaw_rate_gain.between(0.0, 1.2).all()


@needs_borealtc
def test_committed_segments_match_a_fresh_derivation():
    from simpick.real.segments import derive

    rules = CONFIG["real_data"]["segment_rules"]
    fresh, _ = derive(
        BOREALTC,
        tolerance=rules["tolerance"],
        min_duration=rules["min_duration"],
        max_duration=rules["max_duration"],
        settle=rules["settle"],
        min_turn=rules["min_turn"],
        per_kind=rules["per_kind"],
        track=CONFIG["robot"]["track"],
    )
    committed = load_segments(ROOT / CONFIG["real_data"]["segments"])
    pd.testing.assert_frame_equal(
        fresh.reset_index(drop=True), committed[fresh.columns].reset_index(drop=True), check_dtype=False, rtol=1e-5
    )


@needs_borealtc
@pytest.mark.parametrize("engine", ["pybullet", "mujoco"])
def test_replay_of_a_straight_run_covers_the_recorded_distance(engine):
    from simpick.real.logs import borealtc

    log = borealtc.read_run(BOREALTC / "FLOORING" / "imu_07.csv", BOREALTC / "FLOORING" / "pro_07.csv", "FLOORING")
    duration = 30.0
    params = {
        "engine": engine,
        "engine_settings": CONFIG["engines"][engine],
        "physics": CONFIG["physics"],
        "robot": {k: v for k, v in CONFIG["robot"].items() if k != "urdf"},  # the job's input, not a param
        "imu": CONFIG["imu"],
        "health": CONFIG["health"],
        "seed": 1,
        "terrain_class": "flooring",
        "class": {"friction": 0.9, "source": "the test's"},
    }
    frame, meta = replay_log(log, str(ROOT / CONFIG["robot"]["urdf"]), params, duration=duration)
    assert meta["health"]["status"] == "ok", meta["health"]
    cmd = log.wheel_commands()
    t = np.arange(0, duration, 0.001)
    held = np.clip(np.searchsorted(cmd.time, t, side="right") - 1, 0, len(cmd) - 1)
    recorded = np.sum((cmd.v_left.to_numpy()[held] + cmd.v_right.to_numpy()[held]) / 2) * 0.001
    travelled = np.sum(np.hypot(np.diff(frame["x"]), np.diff(frame["y"])))
    assert recorded > 5.0  # the window really drives somewhere
    assert travelled == pytest.approx(recorded, rel=0.04)


@pytest.mark.workflow
@needs_borealtc
def test_own_csv_log_is_imported_replayed_and_compared_by_the_workflow(tmp_path):
    """A user's log in another layout (ms, deg/s, body commands) goes through the same replay."""
    from conftest import snakemake, tiny_config, write_config
    from simpick.real.logs import borealtc, read_canonical

    real = borealtc.read_run(BOREALTC / "FLOORING" / "imu_01.csv", BOREALTC / "FLOORING" / "pro_01.csv", "FLOORING")
    imu = real.imu[real.imu.time < 20.0]  # flooring/01 turns steadily from 12 s
    body = real.body_commands()
    held = np.clip(np.searchsorted(body.time, imu.time, side="right") - 1, 0, len(body) - 1)
    own = pd.DataFrame(
        {
            "t_ms": imu.time * 1000,
            "acc_x": imu.ax,
            "acc_y": imu.ay,
            "acc_z": imu.az,
            "gyro_x": np.degrees(imu.wx),
            "gyro_y": np.degrees(imu.wy),
            "gyro_z": np.degrees(imu.wz),
            "cmd_v": body.v.to_numpy()[held],
            "cmd_w": body.w.to_numpy()[held],
        }
    )
    own.to_csv(tmp_path / "mine.csv", index=False)
    deg = {"unit": "deg/s"}
    config = tiny_config(tmp_path)
    config["engines"] = {k: config["engines"][k] for k in ("mujoco", "pybullet")}
    config["own_logs"] = [
        {
            "name": "mine",
            "terrain_class": "flooring",
            "csv": str(tmp_path / "mine.csv"),
            "mapping": {
                "time": {"column": "t_ms", "unit": "ms"},
                "ax": "acc_x",
                "ay": "acc_y",
                "az": "acc_z",
                "wx": {"column": "gyro_x", **deg},
                "wy": {"column": "gyro_y", **deg},
                "wz": {"column": "gyro_z", **deg},
                "v": "cmd_v",
                "w": "cmd_w",
            },
        }
    ]
    config["accuracy"]["reference"] = "own"
    write_config(tmp_path, config)
    run = snakemake(
        tmp_path,
        "results/metrics/own/summary.csv",
        "results/scores/weighted.csv",
        "results/real/own/turning/windows.csv",
    )
    assert run.returncode == 0, run.stderr[-3000:]
    # the own logs' steady turning windows (what a calibration on them fits), from its (v, w) commands
    from simpick.real.logs.canonical import RealLog
    from simpick.real.turning import WINDOW_COLUMNS, turning_windows

    windows = pd.read_csv(tmp_path / "results/real/own/turning/windows.csv", dtype={"run": str})
    assert list(windows.columns) == WINDOW_COLUMNS and set(windows.run) == {"mine"}
    # the body commands, held at the IMU's samples, give the windows of the recorded wheel commands over the same
    # 20 s (BorealTC's own log): as many, where they are, with the same gain
    rules = config["real_data"]["segment_rules"]  # the study's window rules (rule real_turning's)
    twin = turning_windows(
        RealLog(imu=imu, commands=real.commands[real.commands.time < 20.0]),
        config["robot"]["track"],
        settle=0.5,
        tolerance=rules["tolerance"],
        min_turn=rules["min_turn"],
    )
    assert len(windows) >= 3 and len(windows) == len(twin), (windows, twin)
    assert np.allclose(windows.t_start, twin.t_start, atol=0.1) and windows.t_start.min() >= 12.0
    assert np.allclose(windows.yaw_rate_gain, twin.yaw_rate_gain, atol=0.025)  # commands held at the IMU's rate
    log = read_canonical(tmp_path / "results/real/own/logs/flooring/mine.parquet")
    assert np.allclose(log.imu.wz.to_numpy(), imu.wz.to_numpy(), atol=1e-9)  # deg/s came back as rad/s
    per_test = pd.read_csv(tmp_path / "results/metrics/own/per_test.csv")
    # the reference models are compared beside the engines
    assert sorted(per_test.engine) == ["coulomb", "kinematic", "mujoco", "pybullet"]
    assert (per_test.status == "ok").all()
    assert per_test.error_angular.gt(0).all() and per_test.yaw_rate_gain_real.notna().all()
    errors = pd.read_csv(tmp_path / "results/metrics/own/imu_errors.csv")
    weighted = pd.read_csv(tmp_path / "results/scores/weighted.csv", index_col="engine")
    assert sorted(weighted.index) == ["mujoco", "pybullet"]  # reference models are never scored
    engines = errors[errors.engine.isin(weighted.index)]
    best = engines[engines.quantity == "angular"].set_index("engine").error.idxmin()
    assert weighted.loc[best, "imu_angular"] == 1.0  # the scores rest on the user's log


def test_maintain_segments_replaces_the_committed_files_only_when_the_table_is_sound(tmp_path):
    from simpick.errors import InputError
    from simpick.real.jobs import maintain_segments_job

    committed = {"csv": str(tmp_path / "committed.csv"), "provenance": str(tmp_path / "committed.provenance.yaml")}
    (tmp_path / "committed.csv").write_text("old table\n")
    (tmp_path / "committed.provenance.yaml").write_text("old: provenance\n")
    broken = tmp_path / "broken.csv"
    broken.write_text("segment,dataset\nx,y\n")
    (tmp_path / "derived.provenance.yaml").write_text("new: provenance\n")
    with pytest.raises(InputError, match="columns .* are missing"):
        maintain_segments_job(
            str(broken), str(tmp_path / "derived.provenance.yaml"), committed, str(tmp_path / "receipt.yaml")
        )
    assert (tmp_path / "committed.csv").read_text() == "old table\n"  # a failure leaves it as it was

    derived = tmp_path / "derived.csv"
    derived.write_bytes((ROOT / CONFIG["real_data"]["segments"]).read_bytes())
    maintain_segments_job(
        str(derived), str(tmp_path / "derived.provenance.yaml"), committed, str(tmp_path / "receipt.yaml")
    )
    assert (tmp_path / "committed.csv").read_bytes() == derived.read_bytes()
    assert (tmp_path / "committed.provenance.yaml").read_text() == "new: provenance\n"
    receipt = yaml.safe_load((tmp_path / "receipt.yaml").read_text())
    assert receipt["csv"]["changed"] and receipt["provenance"]["changed"]
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.endswith(".partial")) == []


def _segment_trace(path, engine, segment, wz, status="ok"):
    """A 3 s trace whose window (1, 3] has ax alternating 0.1 / 0.3 (mean 0.2, 1 %-trimmed range
    0.2), az 9.81, constant wz, everything else 0."""
    from simpick.simulate.traces import COLUMNS, write_trace

    t = np.arange(1, 301) / 100.0
    frame = {c: np.zeros(t.size) for c in COLUMNS}
    frame.update(
        time=t,
        ax=np.where(np.arange(t.size) % 2 == 0, 0.1, 0.3),
        az=np.full(t.size, 9.81),
        wz=np.full(t.size, wz),
        v_forward=np.full(t.size, 0.3),
    )
    reasons = [] if status == "ok" else ["slid while parked"]
    write_trace(
        frame,
        {"engine": engine, "segment": segment, "window": [1.0, 3.0], "health": {"status": status, "reasons": reasons}},
        path,
    )
    return str(path)


def test_replay_compare_and_summarise_against_hand_computed_values(tmp_path):
    """One run replayed by one engine, 20 s at 100 Hz, compared in two 10 s windows. Real: yaw
    rate 0.3 + 0.1 sin(2 pi t / 5) (whole periods per window: mean 0.3), forward acceleration 0.2; simulated:
    yaw rate 0.2, no forward acceleration;
    both +9.81 on z, the rest 0. Commands: 0.3 m/s, 0.5 rad/s kinematic."""
    from simpick.compare.jobs import compare_job, summarise_job
    from simpick.real.logs import write_canonical
    from simpick.simulate.traces import write_trace

    track, rate, seconds = 0.555, 100.0, 20.0
    t = np.round(np.arange(1, int(seconds * rate) + 1) / rate, 10)
    zeros = np.zeros(t.size)
    real_imu = pd.DataFrame(
        {
            "time": t,
            "ax": zeros + 0.2,
            "ay": zeros,
            "az": zeros + 9.81,
            "wx": zeros,
            "wy": zeros,
            "wz": 0.3 + 0.1 * np.sin(2 * np.pi * t / 5.0),
        }
    )
    tc = np.arange(0.0, seconds + 1.0, 0.1)
    commands = pd.DataFrame(
        {"time": tc, "v_left": 0.3 - 0.5 * track / 2 + 0 * tc, "v_right": 0.3 + 0.5 * track / 2 + 0 * tc}
    )
    log_path = tmp_path / "logs" / "FLOORING" / "01.parquet"
    write_canonical(
        RealLog(
            imu=real_imu,
            commands=commands,
            meta={"dataset": "test", "run_id": "01", "terrain_class": "FLOORING", "name": "FLOORING_01"},
        ),
        log_path,
    )
    from simpick.simulate.traces import COLUMNS as TRACE_COLUMNS

    sim = pd.DataFrame({c: zeros for c in TRACE_COLUMNS})
    sim["time"], sim["az"], sim["wz"] = t, 9.81, 0.2
    trace = tmp_path / "replay" / "a" / "flooring" / "01.parquet"
    write_trace(
        sim,
        {
            "engine": "a",
            "terrain": "flooring",
            "run": "01",
            "imu_rate_hz": rate,
            "health": {"status": "ok", "reasons": []},
        },
        trace,
    )
    outputs = {
        k: str(tmp_path / f"{k}.csv")
        for k in ("per_test", "detail", "runs", "summary", "pairwise", "imu_errors", "rtf")
    }
    compare_job("replay", [str(trace)], {"logs": [str(log_path)]}, {"track": track, "window": 10.0}, outputs)
    summarise_job(outputs["per_test"], outputs["runs"], {"group": "terrain_class"}, outputs)

    windows = pd.read_csv(outputs["detail"], dtype={"run": str})  # a replay's detail: one row per window
    assert list(windows.window_start) == [0.0, 10.0]
    # Eq. 7 per window: angular |0.2 - 0.3| (z mean) + |0 - 0.2| (z range); linear |0 - 0.2| (x mean)
    # the range is the 1 %-trimmed one (metrics.trimmed_range): the 10 largest of a window's 1 000
    # samples averaged minus the 10 smallest. A window holds two peaks and two troughs; the 10 largest
    # are each peak's sample and its two neighbours either side (t offsets 0, +-0.01, +-0.02 s)
    offsets = np.array([0.0, 0.01, -0.01, 0.02, -0.02] * 2)
    trimmed = 2 * 0.1 * np.mean(np.cos(2 * np.pi * offsets / 5.0))  # peak mean - trough mean
    assert trimmed == pytest.approx(0.2, abs=1e-4)
    np.testing.assert_allclose(windows.error_angular, 0.1 + trimmed, atol=1e-6)  # the CSV keeps 6 significant digits
    np.testing.assert_allclose(windows.error_linear, 0.2, atol=1e-6)  # the CSV keeps 6 significant digits
    # gains: yaw rate over the 0.5 rad/s kinematic one
    np.testing.assert_allclose(windows.yaw_rate_gain_real, 0.6, atol=1e-6)  # the CSV keeps 6 significant digits
    np.testing.assert_allclose(windows.yaw_rate_gain_sim, 0.4, atol=1e-6)  # the CSV keeps 6 significant digits
    # low-passed RMS: ax a constant 0.2 apart; yaw rate 0.1 + 0.1 sin: sqrt(0.1^2 + 0.1^2 / 2), the
    # 0.2 Hz wave kept by the 2 Hz low-pass (1 % for its gain and the filter's ends)
    np.testing.assert_allclose(windows.rmse_ax, 0.2, rtol=1e-3)
    # verdict metrics per window: |0.4 - 0.6| gain; heading |0.2 - 0.3| rad/s x 10 s = 1 rad
    np.testing.assert_allclose(windows.gain_error, 0.2, atol=1e-6)
    np.testing.assert_allclose(windows.heading_error, 1.0, atol=1e-5)
    np.testing.assert_allclose(windows.rmse_yaw_rate, np.sqrt(0.015), rtol=0.01)

    per_test = pd.read_csv(outputs["per_test"], dtype={"run": str}).iloc[0]
    # one test = one run: Eq. 7 summed over its windows, the other figures averaged
    assert per_test.error_angular == pytest.approx(2 * (0.1 + trimmed), abs=1e-5)
    assert per_test.error_linear == pytest.approx(0.4)
    assert per_test.yaw_rate_gain_sim == pytest.approx(0.4) and per_test.segment == "flooring-01"
    totals = pd.read_csv(outputs["imu_errors"]).set_index("quantity")
    assert totals.loc["angular", "error"] == pytest.approx(2 * (0.1 + trimmed), abs=1e-5) and totals.loc[
        "linear", "error"
    ] == pytest.approx(0.4)


def test_segment_compare_and_summarise_against_hand_computed_values(tmp_path):
    """Eq. 7 per segment and per axis, yaw-rate gain, totals over the tests every engine
    completed, and no verdict from two runs."""
    from simpick.compare.jobs import compare_job, summarise_job

    real = {
        "dataset": "test",
        "terrain_class": "flooring",
        "t_start": 0.0,
        "t_end": 3.0,
        "settle": 1.0,
        "duration": 2.0,
        "angular_x_mean": 0.0,
        "angular_x_range": 0.2,
        "angular_y_mean": 0.0,
        "angular_y_range": 0.2,
        "angular_z_range": 0.1,
        "linear_x_mean": 0.5,
        "linear_x_range": 1.0,
        "linear_y_mean": 0.1,
        "linear_y_range": 0.4,
        "linear_z_mean": 9.8,
        "linear_z_range": 2.0,
    }
    rows = [
        dict(
            real,
            segment="flooring-straight",
            run="01",
            kind="straight",
            v_left=0.3,
            v_right=0.3,
            v=0.3,
            w=0.0,
            yaw_rate_gain=float("nan"),
            angular_z_mean=0.0,
        ),
        dict(
            real,
            segment="flooring-turning",
            run="02",
            kind="turning",
            v_left=0.2,
            v_right=0.4,
            v=0.3,
            w=0.4,
            yaw_rate_gain=0.7,
            angular_z_mean=0.3,
        ),
    ]
    pd.DataFrame(rows)[COLUMNS].to_csv(tmp_path / "segments.csv", index=False)
    traces = [
        _segment_trace(tmp_path / "a-s.parquet", "a", "flooring-straight", 0.0),
        _segment_trace(tmp_path / "a-t.parquet", "a", "flooring-turning", 0.25),
        _segment_trace(tmp_path / "b-s.parquet", "b", "flooring-straight", 0.0, status="failed"),
        _segment_trace(tmp_path / "b-t.parquet", "b", "flooring-turning", 0.3),
    ]
    outputs = {
        k: str(tmp_path / f"{k}.csv")
        for k in ("per_test", "detail", "runs", "summary", "pairwise", "imu_errors", "rtf")
    }
    compare_job("segments", traces, {"segments": str(tmp_path / "segments.csv")}, {"track": 0.5}, outputs)
    summarise_job(
        outputs["per_test"],
        outputs["runs"],
        {"group": "terrain_class", "statistics": {"min_runs": 6, "level": 0.95}},
        outputs,
    )

    detail = pd.read_csv(outputs["detail"]).set_index(["engine", "test", "quantity", "axis"])
    x = detail.loc[("a", "flooring-turning", "linear", "x")]
    assert (x.range_error, x.mean_error) == (pytest.approx(0.8), pytest.approx(0.3))  # |0.2-1.0|, |0.2-0.5|
    assert (x.ref_range, x.ref_mean) == (pytest.approx(1.0), pytest.approx(0.5))
    assert np.isnan(detail.loc[("b", "flooring-straight", "linear", "x"), "total_error"])  # failed: no error

    per_test = pd.read_csv(outputs["per_test"], dtype={"run": str}).set_index(["engine", "segment"])
    # linear: |0.2-1.0| + |0.2-0.5| (x) + |0-0.4| + |0-0.1| (y) + |0-2.0| + |9.81-9.8| (z) = 3.61
    assert per_test.loc[("a", "flooring-turning"), "error_linear"] == pytest.approx(3.61)
    assert per_test.loc[("a", "flooring-straight"), "error_linear"] == pytest.approx(3.61)
    # angular: 0.2 (x range) + 0.2 (y range) + 0.1 (z range) + |wz - real mean|
    assert per_test.loc[("a", "flooring-straight"), "error_angular"] == pytest.approx(0.5)
    assert per_test.loc[("a", "flooring-turning"), "error_angular"] == pytest.approx(0.55)
    assert per_test.loc[("b", "flooring-turning"), "error_angular"] == pytest.approx(0.5)
    # gain: wz over (v_right - v_left) / track = 0.25 / 0.4
    assert per_test.loc[("a", "flooring-turning"), "yaw_rate_gain_sim"] == pytest.approx(0.625)
    assert np.isnan(per_test.loc[("a", "flooring-straight"), "yaw_rate_gain_sim"])
    assert per_test.loc[("b", "flooring-straight"), "status"] == "failed"
    assert per_test.loc[("a", "flooring-turning"), "speed_sim"] == pytest.approx(0.3)
    # simpick's verdict metrics: |gain_sim - gain_real| = |0.625 - 0.7|; heading over the 2 s window
    # |0.25 - 0.3| x 2 = 0.1 rad (turning), |0 - 0| x 2 (straight); no gain error where not turning
    assert per_test.loc[("a", "flooring-turning"), "gain_error"] == pytest.approx(0.075)
    assert per_test.loc[("a", "flooring-turning"), "heading_error"] == pytest.approx(0.1)
    assert per_test.loc[("a", "flooring-straight"), "heading_error"] == pytest.approx(0.0)
    assert np.isnan(per_test.loc[("a", "flooring-straight"), "gain_error"])

    totals = pd.read_csv(outputs["imu_errors"]).set_index(["engine", "quantity"])
    # b failed the straight segment: it is left out of both engines' totals, and named
    assert totals.loc[("a", "angular"), "error"] == pytest.approx(0.55)
    assert totals.loc[("b", "angular"), "error"] == pytest.approx(0.5)
    assert totals.loc[("a", "linear"), "error"] == pytest.approx(3.61)
    assert (totals.n_tests == 1).all() and (totals.excluded == "flooring-straight").all()

    summary = pd.read_csv(outputs["summary"]).set_index("engine")
    assert summary.loc["a", "error_angular"] == pytest.approx((0.5 + 0.55) / 2)  # mean over runs 01, 02
    assert summary.loc["a", "n_runs"] == 2 and summary.loc["b", "n_runs"] == 1
    assert summary[["error_angular_low", "error_angular_high"]].isna().all().all()  # 2 runs: no interval
    pairwise = pd.read_csv(outputs["pairwise"])
    assert len(pairwise) == 2 and (pairwise.verdict == "too few runs (1 < 6)").all()
    assert pairwise.set_index("figure").loc["error_angular", "mean_a_minus_b"] == pytest.approx(0.05)


def test_every_real_case_starts_from_its_own_seeded_heading_the_same_for_every_model():
    """No real-data case starts from a fixed heading. The heading derives from the config
    seed and the case's names (not the model), so paired comparisons stay paired."""
    from simpick.simulate.real import start_heading

    cases = [("BorealTC", c, f"{r:02d}", f"{c}-seg{r}") for c in ("asphalt", "ice", "snow") for r in range(20)]
    headings = np.array([start_heading(20220601, *case) for case in cases])
    assert headings.min() >= 0 and headings.max() < 2 * np.pi
    assert start_heading(20220601, *cases[0]) == headings[0]  # deterministic
    assert start_heading(1, *cases[0]) != headings[0]  # the config seed moves it
    assert len(np.unique(headings)) == len(cases)
    # spread over the circle: 60 draws, every quadrant taken, none at the axis-aligned 0 for all
    assert set(np.floor(headings / (np.pi / 2)).astype(int)) == {0, 1, 2, 3}


def test_a_replay_starts_from_its_seeded_heading_and_records_it():
    from simpick.simulate.real import start_heading

    params = {
        "engine": "kinematic",
        "engine_settings": {"track": 0.555},
        "terrain_class": "flooring",
        "class": {"friction": 0.6, "source": "the test's"},
        "physics": {"timestep": 0.002, "ground_friction": 0.6},
        "robot": {"track": 0.555, "max_wheel_torque": 100.0},
        "imu": CONFIG["imu"],
        "health": CONFIG["health"],
        "seed": 7,
    }
    log = synthetic_log()
    frame, meta = replay_log(log, str(ROOT / CONFIG["robot"]["urdf"]), params, duration=2.0)
    expected = start_heading(7, "synthetic", "flooring", "00", "synthetic")
    assert meta["start_heading_deg"] == pytest.approx(np.degrees(expected))
    # the base's yaw at the first sample is the drawn heading (as an angle: mod 2 pi)
    first = float(np.asarray(frame["yaw"])[0])
    assert np.angle(np.exp(1j * (first - expected))) == pytest.approx(0.0, abs=1e-3)


def test_a_source_with_no_case_writes_its_tables_with_their_columns(tmp_path):
    """A source with no cases (or none a model completed) is a normal outcome."""
    from simpick.compare.jobs import compare_job, summarise_job

    for kind, inputs, params in (
        ("segments", {"segments": str(ROOT / CONFIG["real_data"]["segments"])}, {"track": 0.555}),
        ("replay", {"logs": []}, {"track": 0.555, "window": 10.0}),
    ):
        out = {
            k: str(tmp_path / kind / f"{k}.csv")
            for k in ("per_test", "detail", "runs", "summary", "pairwise", "imu_errors", "rtf")
        }
        compare_job(kind, [], inputs, params, out)
        summarise_job(out["per_test"], out["runs"], {"group": "terrain_class"}, out)
        for name, path in out.items():
            frame = pd.read_csv(path)
            assert frame.empty and len(frame.columns) > 3, (kind, name)
        assert {"gain_error", "heading_error", "start_heading_deg"} <= set(pd.read_csv(out["per_test"]).columns)
