"""The real robot's turning analysis on synthetic logs with known answers."""

import math

import numpy as np
import pandas as pd
import pytest

from simpick.real.logs.canonical import RealLog
from simpick.real.turning import WINDOW_COLUMNS, turning_summary, turning_windows

TRACK = 0.555


def synthetic_log(pieces, gain_of, run="01", terrain_class="ASPHALT", imu_hz=100.0, cmd_hz=6.5):
    """A log of consecutive (duration, v_left, v_right) commands whose gyro yaw rate is
    gain_of(v, w) x the kinematic yaw rate, switching with the command."""
    t_end = sum(p[0] for p in pieces)
    t_imu = np.arange(0.0, t_end, 1 / imu_hz)
    t_cmd = np.arange(0.0, t_end, 1 / cmd_hz)
    edges = np.cumsum([0.0] + [p[0] for p in pieces])

    def side(t, k):
        return np.array([pieces[min(np.searchsorted(edges, x, side="right") - 1, len(pieces) - 1)][k] for x in t])

    vl, vr = side(t_imu, 1), side(t_imu, 2)
    w = (vr - vl) / TRACK
    wz = np.array([gain_of((a + b) / 2, c) for a, b, c in zip(vl, vr, w)]) * w
    imu = pd.DataFrame({"time": t_imu, "ax": 0.0, "ay": 0.0, "az": 9.81, "wx": 0.0, "wy": 0.0, "wz": wz})
    commands = pd.DataFrame({"time": t_cmd, "v_left": side(t_cmd, 1), "v_right": side(t_cmd, 2)})
    return RealLog(
        imu=imu, commands=commands, meta={"dataset": "synthetic", "run_id": run, "terrain_class": terrain_class}
    )


def test_constant_gain_is_found_in_every_steady_window_and_a_step_is_left_out():
    log = synthetic_log([(4.0, 0.1, 0.4), (4.0, 0.4, 0.1)], lambda v, w: 0.6)
    windows = turning_windows(log, TRACK)
    assert list(windows.columns) == WINDOW_COLUMNS
    assert np.allclose(windows["yaw_rate_gain"], 0.6)
    # two 4 s pieces, 0.5 s settling each: at most 3 whole 1 s windows a piece; none spans the step
    assert 5 <= len(windows) <= 6
    assert not ((windows["t_start"] < 4.0) & (windows["t_end"] > 4.0)).any()
    assert set(np.sign(windows["w_kinematic"])) == {-1.0, 1.0}
    assert np.allclose(windows["turn_radius"], 0.25 / (0.3 / TRACK))


def test_straight_driving_and_spins_are_told_apart():
    log = synthetic_log([(4.0, 0.3, 0.3), (4.0, -0.2, 0.2)], lambda v, w: 0.5)
    windows = turning_windows(log, TRACK)
    assert len(windows) >= 2 and (windows["turn_radius"] == 0).all()  # only the spin turns
    summary = turning_summary(windows)
    assert summary.loc[0, "spin_gain_median"] == pytest.approx(0.5)
    assert np.isnan(summary.loc[0, "moving_gain_median"])


def test_a_gain_that_grows_with_speed_is_correlated_and_a_constant_one_is_not():
    pieces = [(3.0, v - 0.1, v + 0.1) for v in (0.1, 0.2, 0.3, 0.4, 0.5, 0.6)]
    rising = turning_windows(synthetic_log(pieces, lambda v, w: 0.2 + v), TRACK)
    summary = turning_summary(rising).iloc[0]
    assert summary["rho_speed"] > 0.9 and summary["p_speed"] < 0.01
    flat = turning_summary(turning_windows(synthetic_log(pieces, lambda v, w: 0.7), TRACK)).iloc[0]
    assert np.isnan(flat["rho_speed"])  # a constant gain has no rank correlation to give


def test_runs_spread_and_coulomb_prediction():
    a = turning_windows(synthetic_log([(6.0, 0.1, 0.4)], lambda v, w: 0.6, run="01"), TRACK, coulomb=lambda v, w: 0.478)
    b = turning_windows(synthetic_log([(6.0, 0.1, 0.4)], lambda v, w: 0.7, run="02"), TRACK, coulomb=lambda v, w: 0.478)
    summary = turning_summary(pd.concat([a, b])).iloc[0]
    assert summary["runs"] == 2
    assert summary["run_gain_min"] == pytest.approx(0.6) and summary["run_gain_max"] == pytest.approx(0.7)
    assert summary["coulomb_gain_min"] == summary["coulomb_gain_max"] == pytest.approx(0.478)


def test_body_twist_logs_give_the_windows_of_the_wheel_speeds_they_command():
    """A user's own log of (v, w) commands is read as the wheel speeds they command over the track, as the
    replay drives the engines with them: the same windows and gains as its wheel-command twin."""
    log = synthetic_log([(4.0, 0.1, 0.4), (4.0, 0.3, 0.3)], lambda v, w: 0.6)
    cmd = log.commands
    body = RealLog(
        imu=log.imu,
        commands=pd.DataFrame(
            {"time": cmd["time"], "v": (cmd.v_left + cmd.v_right) / 2, "w": (cmd.v_right - cmd.v_left) / TRACK}
        ),
        meta=log.meta,
    )
    windows, twin = turning_windows(body, TRACK), turning_windows(log, TRACK)
    assert len(windows) >= 2 and np.allclose(windows["yaw_rate_gain"], 0.6)
    pd.testing.assert_frame_equal(windows, twin)


def test_the_figure_job_draws_the_windows_or_says_there_are_none(tmp_path):
    from simpick.report.draw import figure_job

    windows = turning_windows(
        synthetic_log([(6.0, 0.1, 0.4), (6.0, -0.2, 0.2)], lambda v, w: 0.6), TRACK, coulomb=lambda v, w: 0.478
    )
    for name, frame in (("some", windows), ("none", windows.iloc[0:0])):
        table = tmp_path / f"{name}.csv"
        frame.to_csv(table, index=False)
        png = tmp_path / f"{name}.png"
        figure_job("figure_real_turning", {"windows": str(table)}, {}, {}, {"png": str(png)})
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_equivalents_give_the_ros_multiplier_and_the_coulomb_ratio(robot):
    import pandas as pd

    from simpick.coulomb import contact_layout
    from simpick.real.turning import SUMMARY_COLUMNS, with_equivalents

    summary = pd.DataFrame({"terrain_class": ["asphalt", "sandy_loam", "dry"], "gain_median": [0.70, 0.586, 0.99]})
    out = with_equivalents(summary, contact_layout(robot), 0.555, robot.track)
    assert robot.track == pytest.approx(0.5708, abs=1e-4)
    # 0.555 / (0.70 x 0.5708); r between the solver's 0.601 at 0.8 and 0.705 at 0.63 (hard ground: 0.639),
    # just above 0.8 for sandy loam (0.823)
    assert out.separation_multiplier.tolist()[:2] == pytest.approx([1.389, 1.659], abs=0.001)
    assert 0.63 < out.coulomb_ratio[0] < 0.65 and 0.8 < out.coulomb_ratio[1] < 0.85
    assert math.isnan(out.coulomb_ratio[2])  # above what even frictionless sideways sliding gives
    assert {"separation_multiplier", "coulomb_ratio"} <= set(SUMMARY_COLUMNS)
