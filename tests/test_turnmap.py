"""The turn map (simpick.studies.turnmap): which commands it runs, the Coulomb reference it stands beside,
and an engine's gain on the map against the same engine's validation gain."""

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from conftest import study_config
from simpick.coulomb import GRAVITY
from simpick.errors import InputError
from simpick.inputs.motions import side_speeds
from simpick.inputs.robot import load_from_config
from simpick.real.steps import MIN_TURN
from simpick.studies import turnmap

ROOT = Path(__file__).resolve().parents[1]
WARTHOG = {"urdf": str(ROOT / "resources" / "robot" / "warthog.urdf"), "track": 1.08, "max_wheel_torque": 835.0}
R, B = 0.3, 1.08  # DRIVE's wheel radius and baseline (its README)
CLASSES = {"asphalt": 0.75, "gravel": 0.55}  # terrain class -> friction


def _step(terrain, step, left, right, gain=0.6, session="s"):
    """A steps.csv row (simpick.real.drive.step_table) for measured wheel speeds ``left``, ``right`` (rad/s),
    commanded the same."""
    v, w = R * (left + right) / 2, R * (right - left) / B
    turning = abs(w) > MIN_TURN
    return {
        "terrain_class": terrain,
        "session": session,
        "step": step,
        "cmd_left": left,
        "cmd_right": right,
        "v_cmd": v,
        "w_cmd": w,
        "cmd_turn_radius": 0.0 if abs(v) < 0.05 else abs(v / w) if w else math.inf,
        "cmd_wheel_speed_difference": R * (right - left),
        "wheel_left": left,
        "wheel_right": right,
        "v_kin": v,
        "w_kin": w,
        "turning": turning,
        "gain": gain if turning else math.nan,
    }


def test_grid_never_holds_equal_wheel_speeds_and_picks_the_median_step():
    steps = pd.DataFrame(
        [
            _step("asphalt", 0, 3.0, 3.0),  # straight: gain 0 / 0, undefined
            _step("asphalt", 1, 5.0, 5.0),
            _step("asphalt", 2, 2.0, 2.3),  # w_kin 0.083 rad/s: below MIN_TURN, not turning
            _step("asphalt", 3, 1.0, 3.0, gain=0.50),  # v 0.6: bin (0.5, 1]
            _step("asphalt", 4, 1.0, 4.0, gain=0.70),  # v 0.75
            _step("asphalt", 5, 1.5, 5.0, gain=0.55),  # v 0.975
            _step("gravel", 0, 4.0, 4.0),
        ]
    )
    grid = turnmap.command_grid(steps, CLASSES)
    assert (grid.w_kin.abs() > MIN_TURN).all()
    assert set(grid.step) == {3, 4, 5} and "gravel" not in set(grid.terrain_class)  # straight-only: no bin
    speed = grid[grid.variable == "v_cmd"].iloc[0]
    assert speed.steps == 3 and speed.step == 4  # the median of 0.6, 0.75, 0.975 m/s
    assert speed.gain_median == pytest.approx(0.55) and speed.gain_q25 == pytest.approx(0.525)
    assert speed.friction == 0.75
    assert len(turnmap.unique_commands(grid)) == len(set(grid.step))  # one run per step, whatever its bins
    straight = pd.DataFrame([_step("asphalt", 0, 3.0, 3.0), _step("gravel", 1, 2.0, 2.0)])
    assert turnmap.command_grid(straight, CLASSES).empty


def test_a_terrain_without_friction_is_one_clear_error():
    steps = pd.DataFrame([_step("dune", 1, 1.0, 3.0)])
    with pytest.raises(InputError, match=r"real_data\.classes\.dune"):
        turnmap.command_grid(steps, CLASSES)


def _grid(robot_radius, track, commands):
    """A grid of (left, right) wheel speeds in rad/s, w_kin against ``track``."""
    return pd.DataFrame(
        [
            {
                "terrain_class": "asphalt",
                "session": "s",
                "step": k,
                "wheel_left": left,
                "wheel_right": right,
                "w_kin": robot_radius * (right - left) / track,
                "friction": 0.8,
            }
            for k, (left, right) in enumerate(commands)
        ]
    )


def test_coulomb_gain_of_a_rigid_two_wheeled_robot_is_one():
    """Two driven wheels on a frictionless swivel caster: no contact need slip, so the robot turns at the
    kinematic rate of its wheels, at any turn radius: exactly with one contact point per wheel; with the
    line contact across each wheel's width the wheels scuff (diffbot.yaml's 0.990), the same at any radius."""
    config = yaml.safe_load((ROOT / "config" / "robots" / "diffbot.yaml").read_text())["robot"]
    robot = load_from_config({**config, "urdf": str(ROOT / config["urdf"])})
    commands = [(-4.0, 4.0), (2.0, 6.0), (5.0, 6.0), (-6.0, -1.0)]  # spin, 0.24 m, 1.3 m, reverse
    grid = _grid(robot.wheel_radius, robot.track, commands)
    point = turnmap.coulomb_gains(grid, robot, robot.track, points_per_wheel=1).coulomb_gain
    np.testing.assert_allclose(point, 1.0, atol=1e-4)
    line = turnmap.coulomb_gains(grid, robot, robot.track).coulomb_gain
    np.testing.assert_allclose(line, 0.990, atol=0.001)
    # against the Warthog, whose four wheels must slip to turn: far below 1
    warthog = load_from_config(WARTHOG)
    gains = turnmap.coulomb_gains(_grid(R, B, commands), warthog, B).coulomb_gain
    assert (gains < 0.7).all()


def test_warthog_wheel_loads_are_the_coupled_rockers_balance():
    """Done by hand from the description's figures: chassis 100 kg at x 0, rockers 2 x 50 kg with their
    mass centres over the pivots at x 0.04, wheels 15 kg at x +0.50 / -0.42. With the rockers coupled the
    chassis takes no pitch freedom of its own, so the whole robot's balance of force and pitch moment fixes
    the front and back loads (left and right equal by symmetry)."""
    mass = 100 + 2 * 50 + 4 * 15
    x_com = (100 * 0.0 + 100 * 0.04 + 30 * 0.50 + 30 * -0.42) / mass
    weight = mass * GRAVITY
    front = weight / 2 * (x_com + 0.42) / 0.92
    back = weight / 2 - front
    grid = turnmap.coulomb_gains(_grid(R, B, [(1.0, 3.0)]), load_from_config(WARTHOG), B)
    assert grid.coulomb_front_load[0] == pytest.approx(front, rel=1e-6)
    assert grid.coulomb_back_load[0] == pytest.approx(back, rel=1e-6)
    assert front == pytest.approx(616.3, abs=0.1) and back == pytest.approx(659.0, abs=0.1)


def _mujoco_setup():
    from simpick.studies.validation.cases import Setup

    settings = dict(study_config()["engines"]["mujoco"])
    settings["wheel_servo_kp"] = 15000.0  # the Warthog's wheel: the Husky's servo bandwidth (warthog.yaml)
    return Setup(
        engine="mujoco",
        robot=load_from_config(WARTHOG),
        timestep=0.001,
        max_wheel_torque=WARTHOG["max_wheel_torque"],
        track=B,
        settings=settings,
    )


def test_mujoco_gain_on_the_map_is_its_validation_gain():
    """The map's run (turnmap.DURATION) against the validation's yaw_gain case at the same command, given as
    the validation gives it (v, w with the config's track, its default length): the map reaches it through
    DRIVE's wheel speeds and converts the gain to DRIVE's kinematic rate, which must change nothing when the
    track is DRIVE's baseline. Both are the same deterministic run, so they agree to rounding."""
    pytest.importorskip("mujoco")
    from simpick.studies.validation.cases import run_case

    setup = _mujoco_setup()
    commands = [(0.5, 0.5), (0.0, 0.5), (1.5, -0.4)]  # (v, w): the validation's turn, a spin, a wide right turn
    wheels = [tuple(s / R for s in side_speeds(v, w, B)) for v, w in commands]
    grid = _grid(R, B, wheels)
    mapped = turnmap.engine_gains(grid, setup)
    assert (mapped.status == "ok").all() and (mapped.duration == turnmap.DURATION).all()
    assert (mapped.wall_time > 0).all()
    for (v, w), gain in zip(commands, mapped.engine_gain):
        result = run_case(setup, "gain", {"kind": "yaw_gain", "v": v, "w": w, "mu": 0.8})
        assert gain == pytest.approx(result["checks"][0]["engine_value"], abs=1e-9)
        assert 0.4 < gain < 0.8  # a skid-steer's gain, neither rolling (1) nor stuck (0)


def test_an_engine_that_refuses_the_robot_says_so_on_every_row(monkeypatch):
    pytest.importorskip("mujoco")
    from simpick.engines.mujoco_engine import MujocoEngine

    monkeypatch.setattr(MujocoEngine, "simulates_suspension", False)
    table = turnmap.engine_gains(_grid(R, B, [(1.0, 3.0), (-2.0, 2.0)]), _mujoco_setup())
    assert (table.status == "refused").all() and table.engine_gain.isna().all()
    assert table.reason.str.contains("suspension").all()
    assert turnmap.wall_times([table]).ok[0] == 0


def test_figure_draws_real_coulomb_and_engines(tmp_path):
    rows = []
    for variable in ("v_cmd", "cmd_turn_radius"):
        for engine in ("mujoco", "dart"):
            for b, value in enumerate([0.3, 1.5]):
                rows.append(
                    {
                        "terrain_class": "asphalt",
                        "variable": variable,
                        "bin": f"({b}, {b + 1}]",
                        "value": value,
                        "steps": 5,
                        "gain_median": 0.58,
                        "gain_q25": 0.55,
                        "gain_q75": 0.61,
                        "coulomb_gain": 0.57,
                        "engine": engine,
                        "engine_gain": 0.56 if engine == "mujoco" else math.nan,
                        "status": "ok" if engine == "mujoco" else "refused",
                    }
                )
    from simpick.report.turnmap import turnmap_figure

    out = turnmap_figure(pd.DataFrame(rows), tmp_path / "turnmap.png")
    assert out.stat().st_size > 10_000


@pytest.mark.workflow
def test_the_workflow_maps_a_named_drive_folder(tmp_path):
    """rules/turnmap.smk, active with drive_dir: a few real steps cut from a shared session at test time,
    the Warthog in MuJoCo alone; the map, its table and figure are written and nothing committed changes."""
    from conftest import snakemake, tiny_config, write_config
    from test_drive import CALIB, _git_status, cut

    if not CALIB.is_dir():
        pytest.skip(f"DRIVE sessions not present at {CALIB} (the shared data folder; see its README)")
    data = tmp_path / "calib_data"
    cut(data, steps=12)
    config = tiny_config(tmp_path)
    config["robot"] = {**config["robot"], **WARTHOG, "label": "Warthog"}
    config["engines"] = {"mujoco": {**config["engines"]["mujoco"], "wheel_servo_kp": 15000.0}}
    config["accuracy"] = {**config.get("accuracy", {}), "reference": "paper"}
    config["drive_dir"] = str(data)
    write_config(tmp_path, config)
    before = _git_status()
    targets = ["results/drive/drive/turnmap.csv", "results/drive/drive/turnmap.png"]
    run = snakemake(tmp_path, "--cores", "1", *targets)
    assert run.returncode == 0, run.stderr[-3000:]
    table = pd.read_csv(tmp_path / targets[0])
    steps = pd.read_csv(tmp_path / "results/drive/drive/steps.csv")
    assert set(table.engine) == {"mujoco"} and (table.status == "ok").all()
    assert table.steps.groupby(table.variable).sum().eq(int(steps.turning.sum())).all()  # every turning step
    assert table.engine_gain.between(0.4, 0.8).all() and table.coulomb_gain.between(0.5, 0.65).all()
    wall = pd.read_csv(tmp_path / "results/drive/drive/turnmap/wall_time.csv")
    assert wall.engine.tolist() == ["mujoco"] and wall.ok[0] == wall.runs[0] > 0
    assert (tmp_path / targets[1]).stat().st_size > 10_000
    assert _git_status() == before
