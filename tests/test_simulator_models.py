"""The MuJoCo models rule simulator_models writes (simpick.studies.simulator_models) open as they are and do what
their headers claim. Each is loaded by MuJoCo's own loader alone (``mujoco.MjModel.from_xml_path``: nothing of
simpick builds or reads the model; the file's own <custom> numerics are read with MuJoCo's API), driven through
its own actuators at the commands it states, and measured as the validation measures a turning case: the gain it
gives there is the one the file claims, which the job took from simpick's validation (``run_case``, the validate
job's function) on the profile's settings."""

from __future__ import annotations

import shutil
from pathlib import Path

import mujoco
import numpy as np
import pytest
import yaml
from lxml import etree

from conftest import ROOT, study_config
from simpick.config import Study
from simpick.engines.catalog import load_catalog
from simpick.plan import Plan
from simpick.score.simulator_classes import per_class_table
from simpick.studies.simulator_models import simulator_models_job

# s: each claimed case cut from its 6 s to 1 s, so each model steps 6 s in all. A claim is tested at the duration
# its file states; the gains at 1 s are the 6-s ones to 1e-4 (measured on both profiles, MuJoCo 4.0.0): the servo
# has settled to 0.1 rad/s by 0.26 s, before the measured second half begins.
DURATION = 1.0
# a calibrated-like fit: the pooled friction ratio 0.7, and a terrain class with a ratio (and a file) of its own
FIT = {
    "searchable": True,
    "source": "a test's runs",
    "settings": {"friction_ratio": 0.7},
    "per_class": {"grass": {"settings": {"friction_ratio": 0.5}, "engine_gain": 0.75, "improves": True}},
}
STEMS = ("mujoco-tuned", "mujoco-calibrated", "mujoco-calibrated-grass")
# attributes through which an MJCF names another file
FILE_ATTRIBUTES = ("file", "meshdir", "texturedir", "assetdir")


@pytest.fixture(scope="module")
def plan():
    config = study_config()
    return Plan(config, Study.model_validate(config), basedir=str(ROOT))


@pytest.fixture(scope="module")
def models(tmp_path_factory, plan):
    """The job's models of the tuned profile and of a calibrated-like one (FIT), from the plan's params with the
    claimed cases cut to DURATION; and the claims the job measured, per model."""
    tmp = tmp_path_factory.mktemp("models")
    params = plan.simulator_models_params()
    params["profiles"] = {p: params["profiles"][p] for p in ("mujoco-tuned", "mujoco-calibrated")}
    params["cases"] = {name: dict(case, duration=DURATION) for name, case in params["cases"].items()}
    fit = tmp / "mujoco.yaml"  # named as rule simulator_calibrate names a simulator's fit
    fit.write_text(yaml.safe_dump(FIT))
    inputs = {"urdf": str(ROOT / plan.config["robot"]["urdf"]), "calibrations": [str(fit)]}
    claims = simulator_models_job(inputs, params, str(tmp / "models"))
    return tmp / "models", claims


def _numeric(model, name: str) -> np.ndarray:
    return np.asarray(model.numeric(name).data, dtype=float)


def _text(model, name: str) -> str:
    i = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_TEXT, name)
    start = model.text_adr[i]
    return model.text_data[start : start + model.text_size[i]].rstrip(b"\0").decode()


def loader_gain(model, v: float, w: float, duration: float) -> float:
    """The yaw-rate gain of the loaded model, measured as a validation turning case measures it
    (simpick.studies.validation.cases._yaw_gain): the command held from the first step for ``duration``, the
    base's yaw rate about its own z axis after each step (the free joint's angular velocity, qvel[3:6], is in the
    body's frame), its mean over the steps from half the run on, over ``w``. The wheels' ctrl as the header says:
    (v - w x wheel_side x command_track / 2) x wheel_axis_sign / wheel_radius."""
    data = mujoco.MjData(model)
    track, radius = _numeric(model, "command_track")[0], _numeric(model, "wheel_radius")
    side, sign = _numeric(model, "wheel_side"), _numeric(model, "wheel_axis_sign")
    data.ctrl[:] = (v - w * side * track / 2) * sign / radius
    steps = round(duration / model.opt.timestep)
    rates = np.empty(steps)
    for k in range(steps):
        mujoco.mj_step(model, data)
        rates[k] = data.qvel[5]
    return float(rates[steps // 2 :].mean() / w)


@pytest.mark.parametrize("stem", STEMS)
def test_mujoco_s_loader_alone_gives_every_gain_the_model_claims(models, stem):
    folder, claims = models
    model = mujoco.MjModel.from_xml_path(str(folder / f"{stem}.xml"))
    # the actuators the file names, in ctrl order
    assert _text(model, "wheel_actuators").split() == [model.actuator(i).name for i in range(model.nu)]
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_NUMERIC, i) for i in range(model.nnumeric)]
    stated = {n.removeprefix("yaw_rate_gain/"): _numeric(model, n) for n in names if n.startswith("yaw_rate_gain/")}
    measured = {c.case: c for c in claims[stem]}
    assert stated and sorted(stated) == sorted(measured)
    for case, (v, w, duration, claimed) in stated.items():
        # the file's claim is the validation's figure (6 digits in the file) ...
        assert claimed == pytest.approx(measured[case].gain, abs=1e-5), case
        assert duration == DURATION
        # ... and MuJoCo gives it from the file alone
        gain = loader_gain(model, v, w, duration)
        assert abs(gain - claimed) < 0.01, f"{stem} {case}: loaded {gain:.4f}, claimed {claimed:.4f}"


def test_the_fitted_friction_ratio_is_in_the_file_and_turns_it(models):
    """The calibrated-like models turn more than the tuned one (a lower lateral friction), in the order of their
    ratios (1, 0.7, 0.5), and their headers say so."""
    folder, claims = models
    spin = {stem: next(c.gain for c in claims[stem] if c.case == "gain_spin_mu0.8") for stem in STEMS}
    assert spin["mujoco-tuned"] + 0.1 < spin["mujoco-calibrated"] < spin["mujoco-calibrated-grass"] - 0.05, spin
    assert "across the wheel 0.7 x mu" in (folder / "mujoco-calibrated.xml").read_text()
    assert "grass's own friction_ratio = 0.5" in (folder / "mujoco-calibrated-grass.xml").read_text()


def test_a_model_names_no_file_and_opens_alone_from_another_folder(models, tmp_path, monkeypatch):
    folder, _ = models
    for path in sorted(folder.glob("*.xml")):
        # a strict parser reads it (its header's comments hold no "--")
        root = etree.parse(str(path), etree.XMLParser(resolve_entities=False)).getroot()
        named = [(e.tag, a, v) for e in root.iter() if isinstance(e.tag, str) for a, v in e.attrib.items()]
        missing = [n for n in named if n[1] in FILE_ATTRIBUTES and not Path(n[2]).exists()]
        assert not missing, f"{path.name} names files that do not exist: {missing}"
        # the file alone in an empty folder, opened from another one, by a relative path
        alone = tmp_path / path.stem / "alone"
        alone.mkdir(parents=True)
        shutil.copy(path, alone / path.name)
        (tmp_path / path.stem / "elsewhere").mkdir()
        monkeypatch.chdir(tmp_path / path.stem / "elsewhere")
        model = mujoco.MjModel.from_xml_path(f"../alone/{path.name}")
        data = mujoco.MjData(model)
        mujoco.mj_step(model, data, nstep=10)
        assert np.isfinite(data.qpos).all()


def test_the_models_claim_the_validation_s_turning_cases_on_their_ground_and_no_weight_reaches_them(plan):
    """The plan's profiles and cases: every MuJoCo profile among those of the engines with a writer; the yaw_gain
    cases at the ground's friction from heading 0 with the profile's own ratio (not mu 0.2, not another heading, not
    a case with a ratio of its own).
    Editing the weights or a tolerance leaves the rule's params as they are; editing a claimed case does not."""
    params = plan.simulator_models_params()
    mujoco = sorted(p for p in params["profiles"] if p.startswith("mujoco-"))
    assert mujoco == ["mujoco-calibrated", "mujoco-shipped", "mujoco-tuned"]
    assert params["ground_mu"] == 0.8
    cases = params["cases"]
    assert {c["kind"] for c in cases.values()} == {"yaw_gain"} and "gain_v0.5_w0.5_mu0.8" in cases
    for other in ("gain_spin_mu0.2", "gain_v0.5_w0.5_mu0.8_h112.5", "gain_v0.5_w0.5_mu0.8_r0.63", "rest_mu0.8"):
        assert other not in cases
    assert plan.model_files()["mujoco-tuned"] == "results/simulators/models/mujoco-tuned.xml"

    def edited(change) -> dict:
        config = study_config()
        change(config)
        return Plan(config, Study.model_validate(config), basedir=str(ROOT)).simulator_models_params()

    assert edited(lambda c: c["weights"].update(ui=1)) == params
    assert edited(lambda c: c["validation"]["tolerances"].update(yaw_rate_gain=0.2)) == params
    assert edited(lambda c: c["validation"]["cases"]["gain_v0.5_w0.5_mu0.8"].update(duration=3.0)) != params


def test_the_per_class_table_names_a_class_s_model_beside_its_settings_file(plan):
    catalog = load_catalog(ROOT / "resources/simulators/simulators.yaml")
    row = per_class_table({"mujoco": FIT}, catalog, plan.model_files()).iloc[0]
    assert row.settings_file == "results/simulators/settings/mujoco-calibrated-grass"
    assert row.model_file == "results/simulators/models/mujoco-calibrated-grass.xml"
