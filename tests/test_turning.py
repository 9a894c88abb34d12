"""Anisotropic (lateral/longitudinal) wheel friction in the engines, checked against the
anisotropic Coulomb solver (simpick.coulomb) at the same ratio."""

import copy

import pytest

from conftest import ROOT, study_config
from simpick.config import problems
from simpick.engines import ADAPTERS, get_engine
from simpick.errors import InputError
from simpick.inputs.robot import load_robot
from simpick.studies.validation.cases import Setup, run_case
from simpick.studies.validation.judge import summarise

CONFIG = study_config()
TOLERANCES = CONFIG["validation"]["tolerances"]
CASE = "gain_v0.5_w0.5_mu0.8_r0.63"
# engines whose adapter has a friction_ratio setting (the others skip the case, saying why)
ANISOTROPIC = sorted(e for e in ADAPTERS if "friction_ratio" in get_engine(e).settings_model.model_fields)


def _setup(engine, **settings):
    return Setup(
        engine=engine,
        robot=load_robot(ROOT / CONFIG["robot"]["urdf"]),
        timestep=CONFIG["physics"]["timestep"],
        max_wheel_torque=CONFIG["robot"]["max_wheel_torque"],
        track=CONFIG["robot"]["track"],
        settings={**(CONFIG["engines"][engine] or {}), **settings},
    )


def test_the_config_has_an_anisotropic_case_and_ode_supports_it():
    assert CONFIG["validation"]["cases"][CASE]["friction_ratio"] == 0.63
    # measured and documented: dartpy 6.20 exposes no secondary coefficient or direction, SAPIEN
    # 3.0.3's PhysxMaterial and Drake's CoulombFriction have static/dynamic only
    assert ANISOTROPIC == ["mujoco", "ode", "pybullet"]


def test_pybullet_gain_rises_as_the_ratio_falls():
    gains = []
    for r in (1.0, 0.8, 0.5):
        result = run_case(
            _setup("pybullet"),
            "x",
            {"kind": "yaw_gain", "v": 0.0, "w": 0.5, "mu": 0.8, "duration": 3.0, "friction_ratio": r},
        )
        gains.append(result["checks"][0]["engine_value"])
    assert gains[0] < gains[1] < gains[2], gains


# Bullet's friction rows stay world-aligned (tests/test_validation.py _BULLET); anisotropicFriction
# scales them in the wheel's frame and raises the gain, but it stays 12 % low, as the isotropic
# gain is 22 % low: measured 6 s, (0, 0.5) / (0.5, 0.5) / (0.5, -0.5), r 1 0.375 / 0.372 / 0.278
# (0.478), 0.63 0.618 / 0.620 / 0.600 (0.705)
EXPECTED_FAILURES = {
    "pybullet": "Bullet's world-aligned friction rows: r 0.63 gives 0.62 for 0.705 (isotropic 0.37 for 0.478)"
}


@pytest.mark.parametrize(
    "engine",
    [
        pytest.param(
            e, marks=[pytest.mark.xfail(reason=EXPECTED_FAILURES[e], strict=True)] if e in EXPECTED_FAILURES else []
        )
        for e in ANISOTROPIC
    ],
)
def test_engine_turns_at_the_anisotropic_coulomb_gain(engine):
    """At r = 0.63 the analytic gain is 0.705 (0.478 isotropic); the engine is within the gain
    tolerance of it (ODE measured 0.694)."""
    result = run_case(_setup(engine), CASE, dict(CONFIG["validation"]["cases"][CASE], duration=3.0))
    summary = summarise([copy.deepcopy(result)], TOLERANCES)
    row = summary.iloc[0]
    assert row.analytic_value == pytest.approx(0.705, abs=0.002)
    assert row.friction_ratio == 0.63
    assert row.passed, summary[["engine_value", "analytic_value", "error", "tolerance"]].to_string()
    # and it is not the isotropic gain: the setting moved the engine's turning
    assert row.engine_value > 0.478 * 1.25


def test_an_engine_without_the_setting_skips_the_case_saying_why():
    missing = sorted(set(ADAPTERS) - set(ANISOTROPIC))
    assert missing
    result = run_case(_setup(missing[0]), CASE, CONFIG["validation"]["cases"][CASE])
    assert result["status"] == "skipped" and "friction_ratio" in result["reasons"][0]
    summary = summarise([result], TOLERANCES)
    assert summary.iloc[0].status == "skipped" and summary.iloc[0].friction_ratio == 0.63


def test_anisotropic_cases_stay_out_of_the_invariance_checks_and_gains_table():
    from simpick.studies.validation.judge import gain_table

    def gain(case, w, value, **extra):
        return {
            "engine": "a",
            "case": case,
            "kind": "yaw_gain",
            "status": "ok",
            "reasons": [],
            "steps_per_s": 1.0,
            "checks": [
                {
                    "quantity": "yaw_rate_gain",
                    "unit": "1",
                    "error_kind": "relative",
                    "engine_value": value,
                    "analytic_value": 0.705 if extra else 0.478,
                    "v": 0.5,
                    "w": w,
                    "mu": 0.8,
                    "heading": 0.0,
                    **extra,
                }
            ],
        }

    summary = summarise(
        [gain("l", 0.5, 0.48), gain("r", -0.5, 0.48), gain("l63", 0.5, 0.70, friction_ratio=0.63)], TOLERANCES
    )
    turn = summary[summary.quantity == "turn_asymmetry"]
    assert len(turn) == 1 and turn.iloc[0].engine_value == pytest.approx(0.0) and "l63" not in turn.iloc[0].covers
    assert gain_table(summary)["max"].tolist() == [0.48]


def test_friction_ratio_is_refused_outside_yaw_gain_cases_and_on_odes_box():
    bad = copy.deepcopy(CONFIG)
    bad["validation"]["cases"]["straight_mu0.8"]["friction_ratio"] = 0.5
    assert any("friction_ratio is a yaw_gain case's parameter only" in p for p in problems(bad))
    with pytest.raises(InputError, match="friction_ratio.*needs friction_direction 'coulomb'"):
        get_engine("ode").settings_model.of({"friction_ratio": 0.6, "friction_direction": "slip"}, "ode")
    with pytest.raises(InputError, match="friction_ratio.*needs wheel_contact 'decoupled'"):
        get_engine("mujoco").settings_model.of({"friction_ratio": 0.6, "wheel_contact": "default"}, "mujoco")


def test_ode_gain_follows_the_ratio():
    """ODE (elliptic friction in its slip-aligned mode) against the anisotropic Coulomb gain at
    three ratios, spin and moving turn (measured 6 s: r 0.8 0.600 / 0.598 for 0.601, r 0.5
    0.761 / 0.764 for 0.781)."""
    for r in (0.8, 0.5):
        for v, w in ((0.0, 0.5), (0.5, -0.5)):
            result = run_case(
                _setup("ode"),
                "x",
                {"kind": "yaw_gain", "v": v, "w": w, "mu": 0.8, "duration": 3.0, "friction_ratio": r},
            )
            check = result["checks"][0]
            assert check["engine_value"] == pytest.approx(check["analytic_value"], rel=0.05), (r, v, w)


def test_ode_anisotropy_follows_the_wheel_at_any_heading():
    """The ratio is applied in each wheel's frame, not the world's: the same gain from start
    headings 0 and 112.5 degrees (measured 4 s: 0.694 / 0.694 left, 0.696 / 0.696 right)."""
    gains = []
    for heading in (0.0, 112.5):
        result = run_case(
            _setup("ode"),
            "x",
            {
                "kind": "yaw_gain",
                "v": 0.5,
                "w": -0.5,
                "mu": 0.8,
                "duration": 3.0,
                "heading": heading,
                "friction_ratio": 0.63,
            },
        )
        gains.append(result["checks"][0]["engine_value"])
    assert gains[0] == pytest.approx(gains[1], abs=0.01) and gains[0] > 0.65, gains


def test_ode_contact_slip_against_the_compliant_coulomb_gain():
    """ODE's force-dependent slip (contact_slip k per contact, 2 contacts per wheel on flat ground)
    against simpick.coulomb with the wheel's compliance k / 2 on a 2-point layout. Measured 4 s,
    (0, 0.5) / (0.5, 0.5) / (0.5, 0.2), ODE / analytic: k 5e-3 mu 0.8 0.527 / 0.527 all three;
    mu 0.2 0.512 / 0.498, 0.514 / 0.498, 0.527 / 0.527; k 1e-3 mu 0.8 0.501 / 0.480, 0.500 / 0.480,
    0.527 / 0.527. Compliance moves the gain from 0.474 (rigid) to 0.527 (viscous) at most."""
    from simpick.coulomb import contact_layout, with_slip_compliance, yaw_rate_gain

    setup = _setup("ode", contact_slip=5e-3)
    for mu, v, w in ((0.8, 0.0, 0.5), (0.2, 0.5, 0.2)):
        result = run_case(setup, "x", {"kind": "yaw_gain", "v": v, "w": w, "mu": mu, "duration": 3.0})
        analytic = yaw_rate_gain(
            with_slip_compliance(contact_layout(setup.robot, 2), 5e-3 / 2), v, w, setup.track, mu=mu
        )
        assert result["checks"][0]["engine_value"] == pytest.approx(analytic, rel=0.05), (mu, v, w)
    assert analytic == pytest.approx(0.527, abs=0.002)  # the viscous limit, not the rigid 0.474


def test_mujoco_capsule_frame_follows_the_wheel():
    """MuJoCo's anisotropic pairs (capsule wheels): the same gain from headings 0 and 112.5
    (measured 4 s: 0.686 both, for 0.705), and a capsule at r ~ 1 turns as the cylinder does
    (0.462 / 0.462 at (0.5, 0.5), 6 s)."""
    gains = []
    for heading, r in ((0.0, 0.63), (112.5, 0.63), (0.0, 0.9999)):
        result = run_case(
            _setup("mujoco"),
            "x",
            {
                "kind": "yaw_gain",
                "v": 0.5,
                "w": -0.5,
                "mu": 0.8,
                "duration": 3.0,
                "heading": heading,
                "friction_ratio": r,
            },
        )
        gains.append(result["checks"][0]["engine_value"])
    cylinder = run_case(_setup("mujoco"), "x", {"kind": "yaw_gain", "v": 0.5, "w": -0.5, "mu": 0.8, "duration": 3.0})
    assert gains[0] == pytest.approx(gains[1], abs=0.01) and gains[0] > 0.65, gains
    assert gains[2] == pytest.approx(cylinder["checks"][0]["engine_value"], abs=0.01), (gains, cylinder["checks"])


def test_report_takes_the_analytic_of_an_engine_that_ran_and_names_the_engines_that_skipped():
    from simpick.report.validation import validation_section

    ran = run_case(_setup("ode"), CASE, dict(CONFIG["validation"]["cases"][CASE], duration=1.0))
    gone = run_case(_setup("dart"), CASE, CONFIG["validation"]["cases"][CASE])
    section = validation_section(summarise([gone, ran], TOLERANCES), ["dart", "ode"], None)
    row = next(r for r in section["rows"] if r["case"] == CASE)
    assert row["analytic"] == pytest.approx(0.705, abs=0.002)
    assert row["cells"]["dart"]["status"] == "skipped" and row["cells"]["ode"]["status"] == "ok"
    assert list(section["skipped"]) == [f"{CASE} (dart)"] and "friction_ratio" in section["skipped"][f"{CASE} (dart)"]
