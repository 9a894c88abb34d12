import numpy as np
import pytest

from simpick.compare import realmetrics as rm


def test_yaw_rate_gain_recovers_a_known_slip():
    t = np.linspace(0, 10, 1001)
    v_left, v_right = 0.3 - 0.2 * np.sin(t), 0.3 + 0.2 * np.sin(t)
    kinematic = (v_right - v_left) / 0.555
    assert rm.yaw_rate_gain(0.4 * kinematic, v_left, v_right, 0.555) == pytest.approx(0.4)


def test_yaw_rate_gain_is_nan_when_never_turning():
    v = np.full(100, 0.5)
    assert np.isnan(rm.yaw_rate_gain(np.zeros(100), v, v, 0.555))


def test_lowpass_keeps_slow_and_removes_fast():
    fs = 100.0
    t = np.arange(0, 20, 1 / fs)
    slow, fast = np.sin(2 * np.pi * 0.2 * t), np.sin(2 * np.pi * 20 * t)
    out = rm.lowpass(slow + fast, fs)
    assert np.abs(out - slow)[200:-200].max() < 0.02


def test_aligned_rmse_zero_for_the_same_signal_and_sees_an_offset():
    x = np.sin(np.linspace(0, 10, 1000))
    assert rm.aligned_rmse(x, x, 100.0) == pytest.approx(0.0, abs=1e-12)
    assert rm.aligned_rmse(x, x + 0.3, 100.0) == pytest.approx(0.3, rel=1e-3)


def test_psd_distance_in_decades():
    rng = np.random.default_rng(1)
    x = rng.normal(size=6000)
    assert rm.psd_distance(x, x, 100.0) == pytest.approx(0.0, abs=1e-12)
    assert rm.psd_distance(x, np.sqrt(10) * x, 100.0) == pytest.approx(1.0, rel=1e-6)  # 10x power


def test_mean_ci_averages_per_run_and_gives_an_interval_only_from_min_runs():
    values = np.random.default_rng(2).normal(1.0, 0.5, 40)
    mean, low, high, n = rm.mean_ci(values, min_runs=6, seed=3)
    assert low < mean < high and mean == pytest.approx(values.mean()) and n == 40
    assert rm.mean_ci(values, min_runs=6, seed=3) == (mean, low, high, n)  # seeded
    assert 0.1 < high - low < 0.5  # about 4 standard errors wide
    # five runs of eight windows each: five samples, too few for an interval
    runs = np.repeat(np.arange(5), 8)
    mean, low, high, n = rm.mean_ci(values, runs, min_runs=6)
    assert n == 5 and np.isnan(low) and np.isnan(high)
    assert mean == pytest.approx(np.mean([values[runs == r].mean() for r in range(5)]))


def test_a_paired_difference_is_found_only_when_real():
    base = np.random.default_rng(4).normal(2.0, 1.0, 30)
    t = rm.paired_test(base + 0.5, base)
    assert t["verdict"] == "a" and t["p_value"] < 0.05 and t["low"] > 0 and t["n_runs"] == 30
    noise = np.random.default_rng(5).normal(0, 0.5, 30)
    t = rm.paired_test(base + noise, base)
    assert t["verdict"] == "no clear difference" and t["p_value"] >= 0.05 and t["low"] < 0 < t["high"]
    assert rm.paired_test(base, base + 0.5)["verdict"] == "b"


def test_two_runs_give_no_verdict():
    """The hand-written bootstrap called any two same-sign differences clear at 95 %."""
    t = rm.paired_test([1, 1.2], [0.9, 1.19])
    assert t["verdict"] == "too few runs" and t["n_runs"] == 2
    assert np.isnan(t["p_value"]) and np.isnan(t["low"]) and np.isnan(t["high"])
    assert t["mean"] == pytest.approx(0.055)


def test_windows_of_one_run_are_not_independent_samples():
    a, b = np.arange(12) + 1.0, np.zeros(12)
    assert rm.paired_test(a, b, min_runs=6)["verdict"] == "a"  # 12 runs, all one sign: p = 2/4096
    runs = np.repeat(["r1", "r2", "r3"], 4)  # the same 12 values from 3 runs
    t = rm.paired_test(a, b, runs, min_runs=6)
    assert t["n_runs"] == 3 and t["verdict"] == "too few runs"


def test_the_sign_flip_test_is_exact_and_its_smallest_p_sets_the_minimum():
    assert rm.smallest_p(5) == pytest.approx(0.0625) and rm.smallest_p(6) == pytest.approx(0.03125)
    t = rm.paired_test(np.arange(6) + 1.0, np.zeros(6), min_runs=6)
    assert t["p_value"] == pytest.approx(2 / 2**6) and t["verdict"] == "a"
    # with min_runs lowered to 5, five same-sign runs still cannot reach 5 %
    t = rm.paired_test(np.arange(5) + 1.0, np.zeros(5), min_runs=5)
    assert t["p_value"] == pytest.approx(0.0625) and t["verdict"] == "no clear difference"


def test_a_minimum_that_could_never_reach_the_level_is_refused():
    from pydantic import ValidationError

    from simpick.config import Statistics

    assert Statistics().min_runs == 6
    with pytest.raises(ValidationError, match="at least 6"):
        Statistics(min_runs=5, level=0.95)
    assert Statistics(min_runs=8, level=0.99).min_runs == 8


def test_the_statistics_defaults_are_stated_once():
    """statistics.min_runs and level default in one place (simpick.compare.realmetrics), which the config
    model takes; the jobs read them through statistics_settings, never a restated literal."""
    import re
    from pathlib import Path

    from simpick.config import Statistics

    assert rm.statistics_settings() == (Statistics().min_runs, Statistics().level) == (rm.MIN_RUNS, rm.LEVEL)
    assert rm.statistics_settings({"min_runs": 8}) == (8, rm.LEVEL)
    src = Path(rm.__file__).parent
    restated = [
        str(p.relative_to(src))
        for p in sorted(src.rglob("*.py"))
        if p.name != "realmetrics.py" and re.search(r'"level":\s*0\.\d|"min_runs":\s*(MIN_RUNS|\d)', p.read_text())
    ]
    assert restated == [], restated
