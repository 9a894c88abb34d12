import math

import numpy as np
import pandas as pd
import pytest

from conftest import ROOT
from simpick.compare import metrics
from simpick.engines.kinematics import imu_from_kinematics
from simpick.inputs.published import load_published
from simpick.inputs.reference import lab_reference, to_simpick_frame
from simpick.simulate.imu import ImuModel, block_average, sensor_output


def test_trimmed_range_uses_the_mean_of_each_one_percent_tail():
    x = np.arange(1, 201, dtype=float)  # 200 samples: tails of 2
    assert metrics.trimmed_range(x) == pytest.approx(199.5 - 1.5)


def test_trimmed_range_discounts_a_single_outlier():
    x = np.r_[np.zeros(99), [100.0]]  # tail of 1 sample
    assert metrics.trimmed_range(x) == pytest.approx(100.0)
    x = np.r_[np.zeros(999), [100.0]]  # tail of 10 samples: the outlier is averaged down
    assert metrics.trimmed_range(x) == pytest.approx(10.0)


def test_trimmed_range_short_series_and_bad_input():
    assert metrics.trimmed_range([3.0, 1.0]) == pytest.approx(2.0)
    with pytest.raises(ValueError):
        metrics.trimmed_range([])
    with pytest.raises(ValueError):
        metrics.trimmed_range([1.0, float("nan")])


def test_paper_worked_example_angular_error_is_1_237():
    example = load_published()["worked_example"]
    assert metrics.test_error(example["table6"]["sim"], example["table6"]["real"]) == pytest.approx(1.237, abs=5e-4)


def test_paper_worked_example_linear_error_from_table7():
    example = load_published()["worked_example"]
    # 8.30 + 0.20 + 4.80 + 0.83 + 8.50 + 0.80; the paper prints 23.39 (Table 9) and 23.19 (text)
    assert metrics.test_error(example["table7"]["sim"], example["table7"]["real"]) == pytest.approx(23.43, abs=5e-3)


def test_trace_stats_on_a_known_trace():
    n = 1000
    frame = pd.DataFrame({c: np.zeros(n) for c in ("ax", "ay", "az", "wx", "wy", "wz")})
    frame["az"] = 9.81
    frame["wz"] = np.linspace(-1, 1, n)
    stats = metrics.trace_stats(frame)
    assert stats["linear"]["z"] == {"mean": pytest.approx(9.81), "range": pytest.approx(0.0)}
    assert stats["angular"]["z"]["mean"] == pytest.approx(0.0, abs=1e-12)
    assert stats["angular"]["z"]["range"] == pytest.approx(
        2 * (1 - 4.5 * 2 / 999), rel=1e-9
    )  # top 10 samples average 1 - 4.5 steps


def test_real_time_factor_is_total_sim_over_total_wall():
    assert metrics.real_time_factor([10, 20], [1, 4]) == pytest.approx(6.0)
    with pytest.raises(ValueError):
        metrics.real_time_factor([1], [0])


def test_imu_from_kinematics_at_rest_and_in_a_steady_turn():
    n, dt = 2000, 0.001
    quat = np.tile([1.0, 0, 0, 0], (n, 1))
    f, g = imu_from_kinematics(quat, np.zeros((n, 3)), np.zeros((n, 3)), (0.19, 0, 0.149), dt)
    assert np.allclose(f, [0, 0, 9.81]) and np.allclose(g, 0)

    # spinning in place at w about z: the mount at r = 0.19 m ahead feels a centripetal
    # acceleration w^2 r toward the centre, i.e. -x in the body frame
    w = 0.5
    t = dt * np.arange(1, n + 1)
    yaw = w * t
    quat = np.stack([np.cos(yaw / 2), 0 * t, 0 * t, np.sin(yaw / 2)], 1)
    omega = np.tile([0, 0, w], (n, 1))
    f, g = imu_from_kinematics(quat, np.zeros((n, 3)), omega, (0.19, 0, 0.149), dt)
    assert np.allclose(f[10:, 0], -w * w * 0.19, atol=1e-3)
    assert np.allclose(f[10:, 1], 0.0, atol=1e-3)  # tangential: none at constant rate
    assert np.allclose(g[:, 2], w)


def test_block_average_and_saturation():
    x = np.arange(25, dtype=float).reshape(-1, 1)
    assert block_average(x, 10)[:, 0].tolist() == [4.5, 14.5]  # the incomplete block is dropped
    model = ImuModel(accel_range=10.0, gyro_range=1.0)
    a, g = sensor_output(np.array([[20.0, -20.0, 5.0]]), np.array([[2.0, -2.0, 0.5]]), model, np.random.default_rng(0))
    assert a.tolist() == [[10.0, -10.0, 5.0]] and g.tolist() == [[1.0, -1.0, 0.5]]


def test_sensor_noise_is_seeded():
    model = ImuModel(accel_noise_std=0.1, gyro_noise_std=0.01)
    zeros = np.zeros((100, 3))
    a1, _ = sensor_output(zeros, zeros, model, np.random.default_rng(7))
    a2, _ = sensor_output(zeros, zeros, model, np.random.default_rng(7))
    a3, _ = sensor_output(zeros, zeros, model, np.random.default_rng(8))
    assert np.array_equal(a1, a2) and not np.array_equal(a1, a3)
    assert 0.07 < a1.std() < 0.13


def test_paper_frame_is_mapped_to_z_up():
    ref = lab_reference(load_published())[("gravel", "straight")]
    assert ref["linear"]["z"]["mean"] == pytest.approx(11.50)  # -11.50 in the paper's z-down frame
    assert ref["linear"]["y"]["mean"] == pytest.approx(-0.10)
    assert ref["linear"]["x"]["mean"] == pytest.approx(-0.18)
    assert ref["linear"]["z"]["range"] == pytest.approx(11.80)  # ranges do not change sign
    assert ref["angular"]["z"]["mean"] == pytest.approx(-0.060)


def test_a_general_rotation_is_refused():
    c = math.sqrt(0.5)
    stats = {a: {"mean": 0.0, "range": 1.0} for a in "xyz"}
    with pytest.raises(ValueError, match="signed axis permutation"):
        to_simpick_frame(stats, [[c, -c, 0], [c, c, 0], [0, 0, 1]], "test")


def test_lab_totals_leave_out_a_test_any_engine_failed(tmp_path):
    """A failed run must not make its engine look better: the test leaves every engine's total."""
    from simpick.compare.jobs import compare_job, summarise_job
    from simpick.inputs.published import DEFAULT_PATH
    from simpick.simulate.traces import COLUMNS, write_trace

    paths = []
    for engine, status in (("a", "ok"), ("b", "failed")):
        frame = pd.DataFrame({c: np.linspace(0, 1, 200) for c in COLUMNS})
        frame["time"] = np.arange(1, 201) * 0.01
        meta = {
            "engine": engine,
            "engine_version": "1",
            "terrain": "gravel",
            "motion": "straight",
            "steps": 2000,
            "sim_time": 2.0,
            "wall_time": 0.1,
            "cpu_time": 0.1,
            "real_time_factor": 20.0,
            "config_hash": "x",
            "health": {"status": status, "reasons": [] if status == "ok" else ["flipped"]},
        }
        path = tmp_path / f"{engine}.parquet"
        write_trace(frame, meta, path)
        paths.append(str(path))
    names = ("per_test", "detail", "runs", "imu_errors", "rtf", "summary", "pairwise")
    outputs = {n: str(tmp_path / f"{n}.csv") for n in names}
    compare_job("lab", paths, {"published": str(DEFAULT_PATH)}, {}, outputs)
    summarise_job(outputs["per_test"], outputs["runs"], {"group": "terrain"}, outputs)
    errors = pd.read_csv(outputs["imu_errors"])
    assert errors.error.isna().all() and (errors.n_tests == 0).all()
    assert set(errors.excluded) == {"gravel/straight"}
    runs = pd.read_csv(outputs["runs"])
    assert runs.set_index("engine").status.to_dict() == {"a": "ok", "b": "failed"}
    # a failed run does not count for speed either: its test is left out for every engine, so here
    # no engine has a real-time factor
    rtf = pd.read_csv(outputs["rtf"])
    assert list(rtf.engine) == ["a", "b"] and rtf.real_time_factor.isna().all()
    assert (rtf.excluded == "gravel/straight").all() and (rtf.n_runs == 0).all()


def test_rotation_matrices_and_quaternions_round_trip():
    from simpick.engines.kinematics import matrices_to_quaternions, rotation_matrices

    rng = np.random.default_rng(3)
    q = rng.normal(size=(500, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    q *= np.where(q[:, :1] < 0, -1.0, 1.0)  # the canonical sign (w >= 0)
    q[:4] = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]  # every branch of the conversion
    np.testing.assert_allclose(matrices_to_quaternions(rotation_matrices(q)), q, atol=1e-12)


def test_real_time_factor_covers_the_same_tests_for_every_engine():
    """An engine failing the slow terrain must not look faster for it."""
    from simpick.compare.jobs import equal_rtf

    runs = pd.DataFrame(
        {
            "engine": ["a", "a", "b", "b"],
            "terrain": ["grass", "gravel"] * 2,
            "motion": ["straight"] * 4,
            "sim_time": [10.0, 10.0, 10.0, 10.0],
            "wall_time": [1.0, 9.0, 2.0, 0.5],
            "status": ["ok", "ok", "ok", "failed"],
        }
    )
    rtf = equal_rtf(runs).set_index("engine")
    assert rtf.loc["a", "real_time_factor"] == pytest.approx(10.0)  # grass only, not 20 / 10
    assert rtf.loc["b", "real_time_factor"] == pytest.approx(5.0)
    assert (
        (rtf.n_runs == 1).all() and (rtf.excluded == "gravel/straight").all() and (rtf.tests == "grass/straight").all()
    )


def test_cpu_load_runs_are_health_checked(tmp_path):
    from simpick.inputs import terrain
    from simpick.simulate.cpuload import measure
    from simpick.simulate.health import HealthLimits

    path = tmp_path / "flat.json"
    terrain.save(terrain.generate("flat", "flat", 0, 0.8, tiles=0), path)
    params = {
        "engine": "mujoco",
        "physics": {"timestep": 0.001, "ground_friction": 0.8},
        "robot": {"max_wheel_torque": 100.0, "track": 0.555},
        "imu": {"rate_hz": 100.0, "accel_range": 50.0, "gyro_range": 5.0},
        "health": dict(HealthLimits().__dict__),
        "seed": 0,
        "engine_settings": {},
        "terrain": "flat",
        "motion_name": "straight",
        "motion": {"v": 0.5, "w": 0.0, "duration": 0.3, "start": [0.0, 0.0, 0.0]},
        "cpu_load": {
            "terrain": "flat",
            "motion": "straight",
            "duration": 0.3,
            "repeats": 1,
            "robots_average": 1,
            "robots_intense": 2,
            "spacing": 1.2,
        },
    }
    common = dict(params=params, urdf=str(ROOT / "resources/robot/husky_a200.urdf"), terrain_file=str(path))
    ok = measure(**common, limits=HealthLimits())
    assert ok["health"] == {"status": "ok", "reasons": [], "checked": True}
    # limits no real run can meet: the measurement is failed, with the reason
    bad = measure(**common, limits=HealthLimits(max_speed=0.01))
    assert bad["health"]["status"] == "failed"
    assert any(r.startswith("average (1 robots): exploded") for r in bad["health"]["reasons"])


def test_every_rule_that_runs_library_code_carries_its_code_version():
    """Snakemake reruns on a params change, not on an edited import: src/ must be in the params."""
    import re

    for smk in sorted((ROOT / "rules").glob("*.smk")):
        text = smk.read_text()
        for block in re.split(r"\n(?=\s*rule )", text):
            m = re.match(r"\s*rule (\w+):", block)
            # targets and the maintainer's copy of a derived table run no library code of their own;
            # a download is not redone for a code edit
            if not m or m.group(1) in (
                "all",
                "sweep",
                "calibration",
                "maintain_segments",
                "dataset_manifest",
                "fetch_borealtc",
            ):
                continue
            assert "code=" in block, f"{smk.name}: rule {m.group(1)} has no code= param"


def test_eq7_is_summed_one_way_whatever_the_order_of_the_rows():
    """metrics.eq7_sum / eq7_per_run: the one aggregation of Eq. 7 (axes, windows, tests, runs);
    exactly rounded, so a reordered table gives the same totals to the last bit."""
    from simpick.compare.metrics import eq7_per_run, eq7_sum

    values = [1e16, 1.0, 1.0, 0.1, 0.2]
    assert eq7_sum(values) == 1e16 + 2 == eq7_sum(reversed(values))
    assert sum(values) == 1e16  # a left-to-right sum loses both 1.0
    rows = pd.DataFrame(
        {
            "engine": ["a"] * 5 + ["b"],
            "run": ["r1"] * 3 + ["r2"] * 2 + ["r1"],
            "error_angular": values + [2.0],
            "error_linear": [1.0] * 6,
        }
    )
    out = eq7_per_run(rows, ["engine", "run"])
    assert out.to_dict("records") == [
        {"engine": "a", "run": "r1", "error_angular": 1e16 + 2, "error_linear": 3.0},
        {"engine": "a", "run": "r2", "error_angular": eq7_sum([0.1, 0.2]), "error_linear": 2.0},
        {"engine": "b", "run": "r1", "error_angular": 2.0, "error_linear": 1.0},
    ]
    shuffled = eq7_per_run(rows.sample(frac=1.0, random_state=3), ["engine", "run"])
    pd.testing.assert_frame_equal(out, shuffled)
    assert list(eq7_per_run(rows.iloc[:0], ["engine", "run"]).columns) == [
        "engine",
        "run",
        "error_angular",
        "error_linear",
    ]
