"""The speed-accuracy sweep: its config, the IMU at a timestep that does not divide the IMU period,
the equal-comparison summary, the report section and a tiny sweep through the workflow."""

import copy

import numpy as np
import pandas as pd
import pytest
import yaml

from conftest import ROOT, snakemake, study_config, tiny_config, write_config
from simpick.config import problems, timestep_label
from simpick.simulate.imu import block_average, interval_average
from simpick.studies.sweep import summarise

CONFIG = study_config()
SWEEP = yaml.safe_load((ROOT / "config" / "sweeps" / "timestep.yaml").read_text())


def with_sweep(sweep):
    config = copy.deepcopy(CONFIG)
    config["sweep"] = sweep
    return "\n".join(problems(config))


def test_the_shipped_sweep_config_is_valid():
    assert with_sweep(SWEEP["sweep"]) == ""
    assert SWEEP["sweep"]["timesteps"] == [0.0005, 0.001, 0.002, 0.004]


@pytest.mark.parametrize(
    "sweep, expected",
    [
        ({"name": "t", "timesteps": [0.001, 0.001]}, "timesteps must be distinct"),
        ({"name": "t", "timesteps": [0.05]}, "sweep.timesteps.0: Input should be less than or equal to 0.02"),
        ({"name": "t", "timesteps": [0]}, "sweep.timesteps.0: Input should be greater than 0"),
        ({"name": "t", "timesteps": []}, "sweep.timesteps: List should have at least 1 item"),
        ({"name": "my sweep", "timesteps": [0.001]}, "sweep.name: String should match pattern"),
        ({"timesteps": [0.001]}, "sweep.name: Field required"),
    ],
)
def test_a_bad_sweep_is_named(sweep, expected):
    assert expected in with_sweep(sweep)


def test_labels_name_the_sweep_files():
    assert [timestep_label(dt) for dt in SWEEP["sweep"]["timesteps"]] == ["0.5ms", "1ms", "2ms", "4ms"]
    assert timestep_label(0.0005) == "0.5ms"


# ------------------------------------------------------------ the IMU at any timestep


def test_interval_average_is_the_block_average_where_the_period_is_whole_steps():
    x = np.random.default_rng(1).normal(size=(1000, 3))
    np.testing.assert_allclose(interval_average(x, 0.001, 0.01), block_average(x, 10), atol=1e-12)


def test_interval_average_weighs_a_straddling_step_by_its_time():
    # 4 ms steps holding 0, 1, 2, ...: the first 10 ms are 4 ms of 0, 4 ms of 1 and 2 ms of 2
    out = interval_average(np.arange(10.0)[:, None], 0.004, 0.01).ravel()
    np.testing.assert_allclose(out, [0.8, 3.2, 5.8, 8.2])
    # a constant stays exactly that constant, whatever the ratio
    np.testing.assert_allclose(interval_average(np.full((997, 2), 9.81), 0.0007, 0.01), 9.81)


def test_a_4ms_step_gives_a_100hz_imu_at_rest(robot):
    """At rest the IMU reads g on z and nothing else; its samples are 10 ms apart although
    2.5 physics steps make one sample."""
    from simpick.engines.base import Scenario
    from simpick.inputs.robot import load_robot
    from simpick.simulate.health import HealthLimits
    from simpick.simulate.imu import ImuModel
    from simpick.simulate.run import Case, Recording, run_case

    case = Case(engine="mujoco", terrain="flat", motion="rest", v=0.0, w=0.0, duration=2.0, start=(0.0, 0.0, 0.0))
    terrain = {"schema": "simpick.inputs.terrain/1", "name": "flat", "boxes": [], "spheres": [], "friction": 0.8}
    scenario = Scenario(
        robot=load_robot(ROOT / "resources/robot/husky_a200.urdf"),
        terrain=terrain,
        ground_friction=0.8,
        timestep=0.004,
        max_wheel_torque=100.0,
        starts=(case.start,),
    )
    frame, meta = run_case(case, scenario, 0.555, Recording(imu=ImuModel(rate_hz=100.0), limits=HealthLimits(), seed=0))
    frame = pd.DataFrame(frame)
    np.testing.assert_allclose(np.diff(frame.time), 0.01, atol=1e-12)
    assert len(frame) == 200 and meta["imu_rate_hz"] == 100.0
    settled = frame[frame.time > 1.0]
    assert settled.az.mean() == pytest.approx(9.81, abs=0.05)
    assert settled.wz.abs().max() < 0.01


# ------------------------------------------------------------ summary: the segments source's rules


def _runs():
    """Two engines over three segments of one run; b diverged on s1."""
    rows = []
    for engine, errors, status in (
        ("a", (1.0, 2.0, 3.0), ("ok", "ok", "ok")),
        ("b", (2.0, 9.0, 4.0), ("ok", "diverged", "ok")),
    ):
        for k, (err, st) in enumerate(zip(errors, status)):
            rows.append(
                {
                    "engine": engine,
                    "terrain_class": "ice",
                    "segment": f"s{k}",
                    "test": f"s{k}",
                    "run": "1",
                    "kind": "straight",
                    "status": st,
                    "reasons": "" if st == "ok" else "diverged",
                    "yaw_rate_gain_real": np.nan,
                    "start_heading_deg": 0.0,
                    "error_angular": err if st == "ok" else np.nan,
                    "error_linear": 10 * err if st == "ok" else np.nan,
                    "yaw_rate_gain_sim": np.nan,
                    "gain_error": np.nan,
                    "heading_error": 0.0,
                    "speed_sim": 0.5,
                    "timestep": 0.001,
                    "steps": 1000,
                    "sim_time": 1.0,
                    "cpu_time": 0.1,
                    # a's run of s1 (which b failed) is slow: counted, it would pull a's RTF to 2.5
                    "wall_time": (1.0 if k == 1 else 0.1) if engine == "a" else 0.5,
                }
            )
    return pd.DataFrame(rows)


def test_a_failed_segment_is_counted_and_never_averaged():
    """As the segments source summarises: an engine's errors over the segments it ran healthily;
    the Eq. 7 totals and the real-time factor over those every engine ran healthily (s1 left out
    for all and listed)."""
    out = summarise(_runs()).set_index("engine")
    assert (out.loc["a", "n_failed"], out.loc["b", "n_failed"]) == (0, 1)
    assert (out.loc["a", "n_compared"], out.loc["b", "n_compared"]) == (3, 2)
    assert out.loc["a", "error_angular"] == pytest.approx(2.0)  # one run: (1 + 2 + 3) / 3
    assert out.loc["b", "error_angular"] == pytest.approx(3.0)  # (2 + 4) / 2: s1's 9 never counts
    assert out.loc["a", "n_runs"] == 1 and np.isnan(out.loc["a", "error_angular_low"])  # 1 run < min_runs
    assert out.loc["a", "excluded"] == out.loc["b", "excluded"] == "s1"
    assert (out.loc["a", "n_common"], out.loc["b", "n_common"]) == (2, 2)
    assert out.loc["a", "total_angular"] == pytest.approx(4.0) and out.loc["b", "total_linear"] == pytest.approx(60.0)
    # the real-time factor covers the segments every engine ran healthily: 2 s in 0.2 s, 2 s in 1.0 s
    assert out.loc["a", "real_time_factor"] == pytest.approx(10.0)
    assert out.loc["b", "real_time_factor"] == pytest.approx(2.0)
    assert out.loc["a", "steps_per_s"] == pytest.approx(10_000.0)


def test_sweep_errors_are_means_over_runs_with_intervals_from_min_runs_on():
    """Segments of one run are averaged first; an interval only from statistics.min_runs runs on."""
    runs = _runs()
    runs = runs[runs.engine == "a"].assign(run=["1", "1", "2"])  # s0 and s1 one run: (1 + 2) / 2, then 3
    out = summarise(runs, {"min_runs": 2, "level": 0.95}).iloc[0]
    assert out.n_runs == 2 and out.error_angular == pytest.approx((1.5 + 3.0) / 2)
    assert out.error_angular_low <= out.error_angular <= out.error_angular_high
    assert np.isnan(summarise(runs, {"min_runs": 3, "level": 0.95}).iloc[0].error_angular_low)


def test_the_sweep_has_no_aggregation_of_its_own():
    """Eq. 7 totals and per-run means come from the segments source's summarise step
    (workflow.source_tables); sweep.py names none of the functions that compute them."""
    import inspect

    import simpick.studies.sweep

    text = inspect.getsource(simpick.studies.sweep)
    assert "source_tables" in text
    for name in (
        "simpick.compare.metrics",
        "realmetrics",
        "mean_ci",
        "per_run",
        "eq7_",
        "equal_rtf",
        ".mean(",
        "fsum",
        "test_error",
        "trace_stats",
    ):
        assert name not in text, name


def test_a_sweep_job_reruns_with_the_segments_source_code():
    """Its code version (rules/sweep.smk) follows how the segments are driven, the compare stage's
    code, and not how the lab is driven."""
    from simpick.codeversion import job_files, script_roots
    from simpick.simulate.jobs import PREPARE

    roots = (*script_roots(ROOT / "scripts" / "sweep_segments.py"), PREPARE["segments"])
    files = {p.relative_to(ROOT / "src" / "simpick").as_posix() for p in job_files(*roots)}
    assert {
        "studies/sweep.py",
        "simulate/jobs.py",
        "simulate/real.py",
        "compare/real.py",
        "compare/kinds.py",
        "compare/metrics.py",
    } <= files
    assert not files & {"simulate/lab.py"} and not [f for f in files if f.startswith("studies/calibration/")]
    assert not [f for f in files if f.startswith("sources/")]
    summary = {
        p.relative_to(ROOT / "src" / "simpick").as_posix()
        for p in job_files(*script_roots(ROOT / "scripts" / "sweep_summary.py"))
    }
    assert {
        "studies/sweep.py",
        "compare/jobs.py",
        "compare/real.py",
        "compare/realmetrics.py",
        "compare/metrics.py",
    } <= summary


def test_the_sweep_at_the_studys_timestep_gives_the_segments_sources_figures(tmp_path):
    """The same traces (the segments source's simulate job at the study's timestep, one segment of
    one model failed) through the source's compare and summarise jobs, and through the sweep's
    compare and summary: the same errors, intervals, run counts, Eq. 7 totals and real-time factor."""
    from simpick.compare.jobs import compare_job, summarise_job
    from simpick.config import Study, plain
    from simpick.simulate.jobs import simulate_job, write_hung_trace
    from simpick.sources import segments as segments_source
    from simpick.sources.base import model_settings
    from simpick.studies.sweep import compare_traces, sweep_summary_job
    from simpick.tables import write_csv

    config = tiny_config()
    table = pd.read_csv(ROOT / config["real_data"]["segments"], dtype={"run": str})
    table = table[table.terrain_class == "flooring"].assign(duration=1.0)  # 4 segments of 2 runs
    table.to_csv(tmp_path / "segments.csv", index=False)
    inputs = {"segments": str(tmp_path / "segments.csv"), "urdf": config["robot"]["urdf"]}
    # intervals from 2 runs, at a level a 2-run sign-flip test can reach (the summarise job's Statistics refuses
    # one it cannot: simpick.compare.settings)
    settings, statistics = {"track": config["robot"]["track"]}, {"min_runs": 2, "level": 0.4}
    names = list(table.segment)
    traces = {}
    for model in ("mujoco", "coulomb"):
        study = Study.model_validate(config)
        own = model_settings(plain(study, config), model)
        params = segments_source.case_params(study, "segments", {}, model, own, "flooring", names)
        traces[model] = [str(tmp_path / model / f"{name}.parquet") for name in names]
        simulate_job(traces[model], inputs["urdf"], inputs, params)
    # MuJoCo's second segment (run 07's, which has two more) as its simulate job writes a hung case
    which = {
        "source": "segments",
        "engine": "mujoco",
        "test": names[1],
        "terrain": "flooring",
        "segment": names[1],
        "run": table.run.iloc[1],
        "motion": names[1],
        "dataset": table.dataset.iloc[1],
        "window": [1.0, 2.0],
    }
    write_hung_trace(traces["mujoco"][1], which, params | {"engine": "mujoco"}, 1.0)
    everything = traces["mujoco"] + traces["coulomb"]

    out = {
        n: str(tmp_path / f"{n}.csv")
        for n in ("per_test", "detail", "runs", "imu_errors", "rtf", "summary", "pairwise")
    }
    compare_job("segments", everything, inputs, settings, out)
    summarise_job(out["per_test"], out["runs"], {"group": "terrain_class", "statistics": statistics}, out)
    source = pd.read_csv(out["summary"]).set_index("engine")
    totals = pd.read_csv(out["imu_errors"]).pivot(index="engine", columns="quantity", values="error")
    rtf = pd.read_csv(out["rtf"]).set_index("engine").real_time_factor

    write_csv(compare_traces(everything, inputs, params, settings), tmp_path / "rows.csv")  # as sweep_job
    sweep_summary_job([str(tmp_path / "rows.csv")], str(tmp_path / "sweep.csv"), statistics)
    sweep = pd.read_csv(tmp_path / "sweep.csv").set_index("engine")
    assert (sweep.loc["mujoco", "n_failed"], sweep.loc["mujoco", "n_compared"]) == (1, 3)
    assert sweep.loc["coulomb", "n_compared"] == 4 and (sweep.n_common == 3).all()
    assert (sweep.timestep == config["physics"]["timestep"]).all()
    for engine in ("mujoco", "coulomb"):
        assert sweep.loc[engine, "n_runs"] == source.loc[engine, "n_runs"] == 2
        for fig in ("error_angular", "error_linear", "gain_error"):
            for end in ("", "_low", "_high"):
                assert sweep.loc[engine, fig + end] == source.loc[engine, fig + end], fig + end
        assert np.isfinite(sweep.loc[engine, "error_angular_low"])  # 2 runs >= min_runs: an interval
        assert sweep.loc[engine, "total_angular"] == totals.loc[engine, "angular"]
        assert sweep.loc[engine, "total_linear"] == totals.loc[engine, "linear"]
        assert sweep.loc[engine, "real_time_factor"] == rtf.loc[engine]


def test_the_report_section_pivots_by_timestep(tmp_path):
    from simpick.report import draw
    from simpick.report.sweep import sweep_section

    runs = pd.concat([_runs(), _runs().assign(timestep=0.002, steps=500)], ignore_index=True)
    summarise(runs).to_csv(tmp_path / "summary.csv", index=False)
    figure = tmp_path / "figures" / "sweep.png"  # what rule figure_sweep draws
    draw.sweep({"sweep": str(tmp_path / "summary.csv")}, {"engines": ["a", "b"]}, str(figure))
    assert figure.read_bytes().startswith(b"\x89PNG")
    section = sweep_section(summarise(runs), ["b", "a"], str(figure))
    assert section["given"] and section["uri"].startswith("data:image/png;base64,")
    assert section["timesteps_ms"] == [1.0, 2.0]
    assert [r["engine"] for r in section["rows"]] == ["b", "a"]  # the report's engine order
    assert all(len(r["cells"]) == 2 for r in section["rows"])
    assert section["failed"] == ["b ice 1 ms (1 of 3)", "b ice 2 ms (1 of 3)"]
    assert sweep_section(None, ["a"], None)["given"] is False


# ------------------------------------------------------------ through the workflow


@pytest.mark.workflow
def test_a_tiny_sweep_runs_and_reruns_nothing(tmp_path):
    config = tiny_config(tmp_path)
    config["engines"] = {"mujoco": config["engines"]["mujoco"], "ode": config["engines"]["ode"]}
    config["sweep"] = {"name": "tiny", "timesteps": [0.002, 0.004]}
    write_config(tmp_path, config)
    run = snakemake(tmp_path, "sweep")
    assert run.returncode == 0, run.stderr[-3000:]
    summary = pd.read_csv(tmp_path / "results/sweeps/tiny/summary.csv")
    assert sorted(summary.engine.unique()) == ["mujoco", "ode"]
    assert sorted(summary.timestep.unique()) == [0.002, 0.004]
    assert (summary.n_segments == 2).all() and (summary.n_failed == 0).all()
    assert summary.error_angular.notna().all() and (summary.real_time_factor > 1).all()
    runs = pd.read_csv(tmp_path / "results/sweeps/tiny/runs/ode/flooring/4ms.csv")
    assert (runs.timestep == 0.004).all() and np.allclose(runs.steps * 0.004, runs.sim_time)
    again = snakemake(tmp_path, "sweep", "-n")
    assert again.returncode == 0 and "Nothing to be done" in again.stdout + again.stderr
