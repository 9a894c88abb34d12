"""Newton and Genesis: engines in virtual environments of their own (simpick.engines.isolated).

Without their venvs (``make engine-venvs``) the registry reports them unavailable with the command
that installs them, and the study runs without them; the tests that step them say so in pytest's
summary (skipped, with that reason), except in CI (``CI=true``, set by .ci/run), where a missing
engine fails them: ``make test`` builds the venvs, so one missing there is a broken install. With
the venvs, they check the worker protocol and the one mechanics figure each engine's settings were
chosen for: the skid-steer yaw-rate gain.
"""

import math
import os
from pathlib import Path

import numpy as np
import pytest
import yaml

from conftest import ROOT, setup, study_config
from simpick.config import problems
from simpick.coulomb import contact_layout, yaw_rate_gain
from simpick.engines import get_engine, isolated, unavailable

NEW = ("newton", "genesis")


def installed(engine: str) -> bool:
    return engine not in unavailable([engine])


def needs(engine: str):
    """Skip where ``engine`` is not installed, with the reason; in CI run it, so that it fails."""
    in_ci = os.environ.get("CI", "").lower() == "true"
    return pytest.mark.skipif(
        not in_ci and not installed(engine), reason=f"{engine} is not installed here: make engine-venvs"
    )


def test_defaults_are_the_measured_setups():
    newton = get_engine("newton").settings_model()
    assert (newton.solver, newton.mujoco_cone, newton.wheel_contact) == ("mujoco", "elliptic", "pairs")
    genesis = get_engine("genesis").settings_model()
    assert (genesis.friction_cone, genesis.constraint_solver, genesis.default_armature) == ("elliptic", "Newton", None)
    assert genesis.wheel_kv == newton.wheel_drive_damping == 3000.0


def test_newton_passes_the_mujoco_adapter_s_contact_defaults():
    from simpick.engines import mujoco_engine, newton_engine

    assert (newton_engine.MUJOCO_TIMECONST, newton_engine.MUJOCO_DMAX) == (
        mujoco_engine.MUJOCO_TIMECONST,
        mujoco_engine.MUJOCO_DMAX,
    )


def test_a_missing_venv_names_the_make_target(tmp_path, monkeypatch):
    monkeypatch.setenv("SIMPICK_ENGINE_VENVS", str(tmp_path))
    for engine in NEW:
        if isolated.in_process(engine):  # the engine imports in this interpreter: no venv needed
            continue
        reason = unavailable([engine])[engine]
        assert "make engine-venvs" in reason and str(tmp_path / f".venv-{engine}") in reason


def test_the_opt_in_config_adds_both_engines_to_the_six():
    config = study_config()
    extra = yaml.safe_load((ROOT / "config" / "engines" / "newton_genesis.yaml").read_text())
    assert set(config["engines"]).isdisjoint(NEW)  # the default study does not run them
    config["engines"] = {**config["engines"], **extra["engines"]}
    assert problems(config) == []
    bad = dict(config, engines={**config["engines"], "newton": {"solver": "featherstone"}})
    assert any("engines.newton.solver" in line for line in problems(bad))


def _gain(engine: str, settings: dict, robot, w: float = 0.5, heading: float = 0.0) -> float:
    # 3 s, the gain over the last 1.5: both engines turn steadily by then (measured: the same ratios to Coulomb to
    # 4 digits as over the last 3 s of 6 s, Genesis -0.0219 / -0.0024 both ways, Newton -0.0345 / -0.0121)
    scenario, commands = setup(
        robot,
        ground=0.8,
        torque=100.0,
        v=0.5,
        w=w,
        duration=3.0,
        settings=settings,
        starts=((0.0, 0.0, math.radians(heading)),),
    )
    record = get_engine(engine).simulate(scenario, commands)
    q = record.quaternion
    yaw = np.unwrap(np.arctan2(2 * (q[:, 0] * q[:, 3] + q[:, 1] * q[:, 2]), 1 - 2 * (q[:, 2] ** 2 + q[:, 3] ** 2)))
    half = len(yaw) // 2
    return float((yaw[-1] - yaw[half]) / ((len(yaw) - 1 - half) * scenario.timestep) / w)


def _coulomb(robot) -> float:
    return yaw_rate_gain(contact_layout(robot), 0.5, 0.5, 0.555)


@needs("newton")
def test_newton_worker_answers_step_by_step_as_in_one_rollout(robot):
    scenario, commands = setup(
        robot, ground=0.8, torque=100.0, v=0.5, w=0.5, duration=0.2, settings={"solver": "mujoco"}
    )
    record = get_engine("newton").simulate(scenario, commands)
    world = get_engine("newton").build(scenario)
    try:
        world.set_wheel_targets(commands[0])
        for _ in range(len(commands)):
            world.step(1)
        state = world.read()
    finally:
        world.close()
    np.testing.assert_allclose(state.position, record.position[-1], atol=1e-9)
    np.testing.assert_allclose(state.wheel_speed, record.wheel_speed[-1], atol=1e-6)
    assert record.imu_specific_force.shape == (len(commands), 3)


@needs("newton")
def test_newton_solvermujoco_turns_within_ten_percent_of_coulomb(robot):
    """Newton's defaults turn at half the mechanics' rate (0.24); the MuJoCo adapter's wheel contact
    pairs, passed through Newton's MuJoCo attributes, bring it within 5 % (0.4617 measured,
    the MuJoCo adapter's 0.462)."""
    coulomb = _coulomb(robot)
    assert abs(_gain("newton", {"solver": "mujoco"}, robot) / coulomb - 1) < 0.05
    default = _gain("newton", {"solver": "mujoco", "wheel_contact": "default", "mujoco_cone": "pyramidal"}, robot)
    assert default / coulomb < 0.6


@needs("genesis")
def test_genesis_turns_within_five_percent_of_coulomb_both_ways(robot):
    coulomb = _coulomb(robot)
    for w in (0.5, -0.5):
        assert abs(_gain("genesis", {}, robot, w=w) / coulomb - 1) < 0.05


def test_the_engine_venvs_are_not_tracked():
    ignored = (ROOT / ".gitignore").read_text().split()
    assert {".venv-newton/", ".venv-genesis/"} <= set(ignored)
    assert Path(isolated.venv_python("newton")).parent.parent.name == ".venv-newton"


def test_the_default_study_s_report_names_the_opt_in_engines_as_not_run(tmp_path):
    """The six-engine report says Newton and Genesis were not run, why (their measured cost) and the
    switch that runs them; a study that ran them, or measured nothing, says no such figure."""
    import re

    from test_report import _real_params, _render, write_synthetic_inputs

    lab = write_synthetic_inputs(tmp_path / "in", seconds=1.0, failed=None)
    inputs = {**lab, "accuracy_errors": lab["imu_errors"]}
    switch = "snakemake --cores 2 --configfile config.yaml config/engines/newton_genesis.yaml (make study-eight)"
    opt_in = {
        "genesis": {"switch": switch, "seconds": 200.0, "study_seconds": 500.0},
        "newton": {"switch": switch, "seconds": 100.0, "study_seconds": 500.0},
    }
    text = " ".join(_render(inputs, {**_real_params(), "opt_in": opt_in}).split())
    summary = re.search(r'<div class="summary".*?</div>', text, re.S).group(0)
    assert "Not run in this study: genesis and newton" in summary
    assert "300 s of job time" in summary and "60 % of their 500 s" in summary and switch in summary
    unmeasured = {e: dict(v, seconds=None) for e, v in opt_in.items()}
    text = " ".join(_render(inputs, {**_real_params(), "opt_in": unmeasured}).split())
    assert "not measured yet" in text and "s of job time" not in text
    assert "Not run in this study" not in _render(inputs, _real_params())
