import numpy as np
import pytest

from simpick import realmetrics as rm


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


def test_bootstrap_ci_brackets_the_mean_and_is_seeded():
    values = np.random.default_rng(2).normal(1.0, 0.5, 40)
    mean, low, high = rm.bootstrap_ci(values, seed=3)
    assert low < mean < high and mean == pytest.approx(values.mean())
    assert rm.bootstrap_ci(values, seed=3) == (mean, low, high)
    assert 0.1 < high - low < 0.5  # about 4 standard errors wide
    assert np.isnan(rm.bootstrap_ci([1.0])[1])


def test_paired_difference_excludes_zero_only_for_a_real_difference():
    base = np.random.default_rng(4).normal(2.0, 1.0, 30)
    _, low, high = rm.paired_difference_ci(base + 0.5, base)
    assert low > 0
    noise = np.random.default_rng(5).normal(0, 0.5, 30)
    _, low, high = rm.paired_difference_ci(base + noise, base)
    assert low < 0 < high
