"""The calibrated simulator profile (simpick.studies.simulator_calibration): its search spaces hold only what each
simulator exposes, each with its source; the split keeps every run on one side; the fit places the ratio by the
anisotropic Coulomb model and moves the engine's gain toward the real one (MuJoCo's through mujoco.sysid, which
recovers known settings within its intervals); the profile is judged against the mechanics of its own ratio; the
table's held-out columns and the settings file's header."""

import copy
import math
import re
import xml.etree.ElementTree as ET

import numpy as np
import pandas as pd
import pytest
import yaml

from conftest import ROOT, study_config
from simpick.config import Study
from simpick.coulomb import contact_layout, ratio_for_gain, with_friction_ratio, yaw_rate_gain
from simpick.engines import get_engine
from simpick.engines.catalog import load_catalog
from simpick.engines.simulators import SIMULATORS, VARIANTS
from simpick.inputs.robot import load_from_config
from simpick.plan import Plan
from simpick.score import simulator_classes as classes_stage
from simpick.score import simulator_settings as settings_stage
from simpick.score import simulators as stage
from simpick.studies import simulator_calibration as cal
from simpick.studies.validation.cases import Setup, run_case

SPACES = ROOT / "resources/simulators/calibration.yaml"
SEGMENTS = ROOT / "resources/real/borealtc_segments.csv"
# what the robot's description or its controller fixes, never a simulator setting to fit
NOT_THE_SIMULATOR_S = {"wheel_separation_multiplier", "track", "wheel_radius", "wheel_separation", "mass", "inertia"}
LINE = re.compile(r"\S+\.\w+:\d+")  # a repository path with a line


def _plan(config: dict) -> Plan:
    return Plan(config, Study.model_validate(config), basedir=str(ROOT))


def _config(run: list[str] | None = None) -> dict:
    config = study_config()
    config["robot"]["urdf"] = str(ROOT / config["robot"]["urdf"])
    config["simulators"]["catalog"] = str(ROOT / "resources/simulators/simulators.yaml")
    config["simulators"]["calibration"] = str(SPACES)
    if run is not None:
        config["simulators"]["run"] = run
    return config


@pytest.fixture(scope="module")
def husky():
    config = study_config()
    config["robot"]["urdf"] = str(ROOT / config["robot"]["urdf"])
    return load_from_config(config["robot"]), config["robot"]


# --- the search spaces ---


def test_every_runnable_simulator_has_a_search_space_of_exposed_settings_each_with_its_source():
    spaces = cal.load_search_spaces(SPACES)
    runnable = {name for name, engine in SIMULATORS.items() if engine is not None}
    assert runnable <= set(spaces)
    for name, space in spaces.items():
        assert not set(space.settings) & NOT_THE_SIMULATOR_S, name
        if not space.searchable:
            assert LINE.search(space.why_not), (name, space.why_not)  # quoted from the source, with its line
            continue
        fields = get_engine(SIMULATORS[name]).settings_model.model_fields
        for key, setting in space.settings.items():
            assert setting.exposed_as.strip() and setting.source.strip(), (name, key)
            assert LINE.search(setting.source) or "XMLreference" in setting.source, (name, key, setting.source)
            if key in fields:  # bounds the adapter accepts
                model = get_engine(SIMULATORS[name]).settings_model
                for bound in setting.bounds:
                    model.model_validate({key: bound, **{k: r.value for k, r in space.requires.items()}})
            else:
                assert space.if_unbound, (name, key)
    # CoppeliaSim's Bullet material exposes neither a second direction nor a compliance: it says so; the
    # two-direction ones are searchable where their engine binds the ratio, and the isotropic Drake and Isaac Sim
    # on their contact's compliance and their wheels' drive alone
    assert spaces["coppeliasim"].searchable is False
    for name in ("gazebo_classic", "webots", "mujoco", "drake", "isaac_sim"):
        assert cal.resolve(SPACES, name, spaces[name], SIMULATORS[name]) == (True, None)
    for name in ("drake", "isaac_sim"):
        assert "friction_ratio" not in spaces[name].settings and spaces[name].why_not is None
    # every searchable simulator's setting names its part and quotes its source, an actuator's part said in the file
    raw = yaml.safe_load(SPACES.read_text())["simulators"]
    parts = {}
    for name, space in spaces.items():
        for key, setting in space.settings.items():
            parts[(name, key)] = setting.part
            assert setting.part in ("contact", "actuator"), (name, key)
            assert LINE.search(setting.source) or "XMLreference" in setting.source, (name, key)
            if key.startswith(("wheel_servo", "wheel_drive")):
                assert raw[name]["settings"][key]["part"] == "actuator", (name, key)
    assert parts[("drake", "wheel_drive_damping")] == parts[("isaac_sim", "wheel_drive_damping")] == "actuator"
    assert {parts[("drake", "hydroelastic_modulus")], parts[("gazebo_classic", "contact_kp")]} == {"contact"}
    assert parts[("webots", "contact_soft_cfm")] == "contact"


def test_the_compliance_and_drive_settings_are_planned_for_every_simulator_that_fits_them():
    """The new settings pass planning (each an adapter setting, its bounds accepted) and reach the calibrate job's
    params: Drake and Isaac Sim get a calibrated profile of their own."""
    run = ["gazebo_classic", "webots", "drake", "isaac_sim", "coppeliasim"]
    plan = _plan(_config(run=run))
    assert {"drake-calibrated", "isaac_sim-calibrated", "gazebo_classic-calibrated"} <= set(plan.calibrated)
    assert "coppeliasim-calibrated" not in plan.calibrated
    expected = {
        "drake": {"hydroelastic_modulus", "wheel_drive_damping"},
        "isaac_sim": {"wheel_drive_damping"},
        "gazebo_classic": {"contact_kp", "contact_slip", "friction_ratio"},
        "webots": {"contact_slip", "contact_soft_cfm", "friction_ratio"},
    }
    for simulator, names in expected.items():
        p = cal.CalibrateParams.model_validate(plan.simulator_calibrate_params(simulator))
        assert p.searchable and set(p.space["settings"]) == names, simulator
        model = get_engine(p.engine).settings_model
        for name in names:  # the tuned profile with each bound validates on the adapter
            for bound in p.space["settings"][name]["bounds"]:
                required = {k: r["value"] for k, r in p.space["requires"].items()}
                model.model_validate({**p.engine_settings, **required, name: bound})


def test_planning_refuses_a_setting_the_engine_lacks(tmp_path):
    data = yaml.safe_load(SPACES.read_text())
    data["simulators"]["webots"]["settings"]["wheel_separation"] = {
        "exposed_as": "x",
        "bounds": [0.5, 1.0],
        "source": "nowhere.md:1",
    }
    bad = tmp_path / "calibration.yaml"
    bad.write_text(yaml.safe_dump(data))
    config = _config(run=["webots"])
    config["simulators"]["calibration"] = str(bad)
    with pytest.raises(
        cal.SearchSpaceError, match=r"calibration\.yaml: simulators\.webots\.settings\.wheel_separation"
    ):
        _plan(config)
    # a setting the simulator exposes but the adapter cannot bind is said, not fitted
    spaces = cal.load_search_spaces(SPACES)
    assert "friction_ratio" not in get_engine("newton").settings_model.model_fields
    ok, why = cal.resolve(SPACES, "isaac_lab_newton", spaces["isaac_lab_newton"], "newton")
    assert ok is False and "isotropic" in why
    # Gazebo's <mu2>/<fdir1> are bound by its own physics layer (gz-physics), not by dartpy
    assert cal.resolve(SPACES, "gazebo", spaces["gazebo"], "gzphysics")[0] is True
    with pytest.raises(cal.SearchSpaceError, match="the dart adapter has no such setting"):
        cal.resolve(SPACES, "gazebo", spaces["gazebo"], "dart")


def test_a_search_space_without_its_reason_is_refused(tmp_path):
    data = yaml.safe_load(SPACES.read_text())
    del data["simulators"]["coppeliasim"]["why_not"]
    path = tmp_path / "calibration.yaml"
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(cal.SearchSpaceError, match="simulators.coppeliasim: .*why_not"):
        cal.load_search_spaces(path)


# --- the split ---


def test_the_split_keeps_every_run_on_one_side_and_repeats(tmp_path):
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    cal.split_job({"segments": str(SEGMENTS)}, 0.5, 11, str(a))
    cal.split_job({"segments": str(SEGMENTS)}, 0.5, 11, str(b))
    assert a.read_text() == b.read_text()
    train, test = cal.read_split(a)
    assert train and test and not set(train) & set(test)
    segments = pd.read_csv(SEGMENTS, dtype={"run": str})
    runs = set(segments.terrain_class + "/" + segments.run)
    assert set(train) | set(test) == runs
    # stratified by turning: a class with two turning runs has one on each side
    turning = segments[segments.kind == "turning"]
    for cls, g in turning.groupby("terrain_class"):
        keys = set(cls + "/" + g.run)
        if len(keys) == 2:
            assert keys & set(train) and keys & set(test), cls
    split = pd.read_csv(a, dtype={"run": str})
    split.loc[0, "set"] = "train" if split.loc[0, "set"] == "test" else "test"
    split = pd.concat([split, split.iloc[[0]].assign(set="test" if split.loc[0, "set"] == "train" else "train")])
    split.to_csv(b, index=False)
    with pytest.raises(ValueError, match="both sides"):
        cal.read_split(b)


# --- the fit ---


def test_coulomb_places_the_ratio_whose_gain_is_the_real_one(husky):
    robot, section = husky
    layout = contact_layout(robot)
    isotropic = yaw_rate_gain(layout, 0.5, 0.5, section["track"])
    for gain in (0.55, 0.645, 0.70):
        r = ratio_for_gain(layout, gain, 0.5, 0.5, section["track"], (0.3, 1.8))
        assert r < 1.0 and gain > isotropic  # more turning than isotropic Coulomb: less lateral friction
        assert yaw_rate_gain(with_friction_ratio(layout, r), 0.5, 0.5, section["track"]) == pytest.approx(
            gain, abs=2e-3
        )


def _generated_segments(tmp_path, gains: dict[str, float], duration: float = 2.0):
    """The committed segment table with its training runs' turning segments shortened to ``duration`` s and given
    the real gains ``gains`` (segment -> gain): runs whose real robot is known (made by an engine)."""
    table = pd.read_csv(SEGMENTS, dtype={"run": str})
    table["duration"] = np.where(table.kind == "turning", np.minimum(table.duration, duration), table.duration)
    for name, gain in gains.items():
        table.loc[table.segment == name, "yaw_rate_gain"] = gain
    path = tmp_path / "segments.csv"
    table.to_csv(path, index=False)
    split = tmp_path / "split.csv"
    cal.split_job({"segments": str(SEGMENTS)}, 0.5, 11, str(split))
    return {"split": str(split), "segments": str(path), "urdf": str(ROOT / "resources/robot/husky_a200.urdf")}


def _mujoco_params(**over):
    plan = _plan(_config(run=["mujoco"]))
    params = plan.simulator_calibrate_params("mujoco")
    assert params["kind"] == "segments" and params["segments_case"]["engine"] == "mujoco-calibrated"
    return dict(params, **over)


def test_the_fit_recovers_a_known_ratio_within_its_interval(tmp_path):
    """Real runs made by MuJoCo itself at friction_ratio 0.7 (each run's gain off by a known few thousandths, the
    robot's own spread): the fit from the tuned profile (ratio 1) finds 0.7 within its interval, and the wheels'
    servo gain, which these runs cannot tell apart, is named unidentifiable and kept as tuned."""
    params = _mujoco_params(class_nfev=0, max_nfev=5)
    inputs = _generated_segments(tmp_path, {})
    p = cal.CalibrateParams.model_validate(params)
    train, _ = cal.read_split(inputs["split"])
    units = cal.segment_units(p, inputs, train, p.classes)
    assert len(set(units.runs)) == 3  # flooring/07, ice/02, sandy_loam/02: their turning segments
    made = units.simulate({"friction_ratio": 0.7})
    spread = np.array([0.012, -0.008, -0.004])[: len(made)]
    inputs = _generated_segments(tmp_path, dict(zip(units.names, made + spread)))
    fit = cal.calibrate(inputs, params, str(tmp_path / "mujoco.yaml"))
    f = fit["fit"]
    ratio = f["parameters"]["friction_ratio"]
    assert ratio["identifiable"] and ratio["interval"][0] <= 0.7 <= ratio["interval"][1], ratio
    assert fit["settings"]["friction_ratio"] == pytest.approx(0.7, abs=0.03)
    assert ratio["interval"][1] - ratio["interval"][0] < 0.3  # an interval that says something
    servo = f["parameters"]["wheel_servo_kp"]
    assert servo["identifiable"] is False and "unidentifiable" in servo["why"]
    assert fit["settings"]["wheel_servo_kp"] == params["engine_settings"]["wheel_servo_kp"]
    # the training error at the optimum is the figure's own: each run's |engine - real gain|, the mean over runs
    assert f["train_error"] == pytest.approx(np.mean(np.abs(spread)), abs=0.01)
    assert f["train_error"] < f["train_error_tuned"] and f["kept"] == "the fit"
    assert f["trials"][0][0] == 1.0  # the first evaluation is the tuned profile
    # MuJoCo's own system identification ran it, within the evaluations it was given
    assert f["optimizer"]["name"] == "mujoco.sysid.optimize" and f["optimizer"]["evaluations"] <= 5
    assert not set(f["real_runs"]) & set(fit["test_runs"])  # the test runs never reach the fit


@pytest.mark.parametrize("optimizer", ["scipy", "mujoco.sysid"])
def test_the_intervals_name_a_setting_that_does_nothing_or_jumps_and_bound_one_that_slopes(optimizer):
    """Without an engine: three runs' gains as functions of two settings. The ratio's gain slopes: it is fitted
    and its interval holds the truth; the other does nothing: unidentifiable, kept at its start. With a gain that
    steps (DART's friction box locking) at the optimum, the ratio gets no interval. The same with either
    optimizer: the checks are the fit's, not the optimizer's."""
    space = {
        "friction_ratio": cal.SearchSetting(exposed_as="r", bounds=(0.3, 1.8), source="a.c:1"),
        "other": cal.SearchSetting(exposed_as="o", bounds=(1.0, 100.0), source="a.c:2", log=True),
    }
    axes = [cal.Axis(k, v) for k, v in space.items()]
    real = np.array([0.70, 0.66, 0.69])

    def sloping(settings):
        return 0.95 - 0.4 * settings["friction_ratio"] + np.array([0.0, 0.0, 0.0])

    units = cal.Units(["a/1", "b/1", "c/1"], real, ["a", "b", "c"], sloping, {})
    fit = cal.least_squares_fit(units, axes, {}, {"friction_ratio": 1.0, "other": 10.0}, 8, 0.05, 0.045, 0, optimizer)
    truth = (0.95 - real.mean()) / 0.4
    ratio, other = fit["parameters"]["friction_ratio"], fit["parameters"]["other"]
    assert ratio["identifiable"] and ratio["interval"][0] <= truth <= ratio["interval"][1]
    assert fit["settings"]["friction_ratio"] == pytest.approx(truth, abs=0.01)
    assert other["identifiable"] is False and fit["settings"]["other"] == pytest.approx(10.0)
    assert fit["error"] < fit["start_error"] and fit["residual_sd_from"].startswith("the residuals (2 degrees")

    def stepping(settings):  # turns at 0.81 below r 0.74, locks above
        r = settings["friction_ratio"]
        return np.full(3, 0.81 if r < 0.74 else 0.0) - 0.2 * max(0.0, r - 0.6)

    units = cal.Units(["a/1", "b/1", "c/1"], real, ["a", "b", "c"], stepping, {})
    fit = cal.least_squares_fit(units, axes[:1], {}, {"friction_ratio": 0.72}, 4, 0.05, 0.045, 0, optimizer)
    assert fit["parameters"]["friction_ratio"]["identifiable"] is False
    assert "jumps" in fit["parameters"]["friction_ratio"]["why"]


# a generated robot for the fit without an engine: per unit its commanded turn rate (rad/s) and its run; the gain
# falls with the friction ratio (a little more on the faster turns) and, on the faster turns, with a softer wheel
# servo (a wheel lagging its command), a tenth of the ratio's effect
TURN_RATES = np.array([0.2, 0.35, 0.5, 0.65, 0.8, 0.95, 0.6])
UNIT_RUNS = ["flooring/07", "flooring/09", "ice/02", "ice/03", "sandy_loam/02", "sandy_loam/05", "flooring/07"]


def _generated_gains(settings: dict, servo: float = 0.05) -> np.ndarray:
    ratio, kp = settings["friction_ratio"], settings["wheel_servo_kp"]
    return 0.95 - 0.4 * ratio * (1 + 0.1 * TURN_RATES) - servo * TURN_RATES * math.sqrt(1000.0 / kp)


def _generated_fit(tmp_path, monkeypatch, truth: dict, noise: np.ndarray, servo: float, gains=None, **over):
    """The MuJoCo profile's fit (rule simulator_calibrate's params for mujoco, its search space) with the engine's
    replays replaced by ``gains`` (:func:`_generated_gains` by default), its real gains those at ``truth`` plus
    ``noise``: the file."""
    gains = gains or _generated_gains
    params = _mujoco_params(class_nfev=0, **over)
    real = _generated_gains(truth, servo) + noise

    def simulate(settings: dict) -> np.ndarray:
        return gains({**params["engine_settings"], **settings}, servo)

    units = cal.Units(UNIT_RUNS, real, [f"u{k}" for k in range(len(real))], simulate, {"generated": True})
    monkeypatch.setattr(cal.job, "_units", lambda *args: units)
    split = tmp_path / "split.csv"
    cal.split_job({"segments": str(SEGMENTS)}, 0.5, 11, str(split))
    inputs = {"split": str(split), "segments": str(SEGMENTS), "urdf": str(ROOT / "resources/robot/husky_a200.urdf")}
    cal.calibrate(inputs, params, str(tmp_path / "mujoco.yaml"))
    return params, yaml.safe_load((tmp_path / "mujoco.yaml").read_text())


def test_the_mujoco_fit_runs_mujoco_s_own_system_identification_and_says_so(tmp_path, monkeypatch):
    """The MuJoCo profile's file names its optimizer (mujoco.sysid, MuJoCo's version, its iterations and
    evaluations) and gives each setting an interval or the reason it has none (the servo gain, which these runs
    do not move); every other simulator keeps scipy's least squares."""
    import mujoco

    spaces = cal.load_search_spaces(SPACES)
    assert spaces["mujoco"].optimizer == "mujoco.sysid"
    assert {s.optimizer for name, s in spaces.items() if name != "mujoco"} == {"scipy"}
    truth = {"friction_ratio": 0.7, "wheel_servo_kp": 1000.0}
    params, out = _generated_fit(tmp_path, monkeypatch, truth, np.zeros(len(TURN_RATES)), servo=0.0)
    f = out["fit"]
    assert f["method"].startswith("MuJoCo's own system identification (mujoco.sysid.optimize")
    ran = f["optimizer"]
    assert ran["name"] == "mujoco.sysid.optimize" and ran["version"] == mujoco.__version__
    assert ran["iterations"] >= 1 and 1 <= ran["evaluations"] <= params["max_nfev"]
    assert ran["engine_evaluations"] == len(f["all_trials"]) and ran["message"].startswith("Terminated")
    assert f["intervals"].startswith("mujoco.sysid.calculate_intervals at the optimum: 95 %")
    assert set(f["parameters"]) == {"friction_ratio", "wheel_servo_kp"}
    for name, entry in f["parameters"].items():
        if entry["identifiable"]:
            low, high = entry["interval"]
            assert entry["bounds"][0] <= low <= entry["value"] <= high <= entry["bounds"][1], name
        else:
            assert entry["why"].startswith("unidentifiable from these runs: "), name
    assert f["parameters"]["friction_ratio"]["identifiable"] and not f["parameters"]["wheel_servo_kp"]["identifiable"]
    assert out["settings"]["friction_ratio"] == pytest.approx(0.7, abs=1e-3)


def test_the_mujoco_fit_recovers_known_settings_within_its_intervals(tmp_path, monkeypatch):
    """A generated robot with known settings (friction ratio 0.7, wheel servo gain 400: both move the gains, the
    servo on the faster turns only) and noisy real gains (sd 0.003): the MuJoCo profile's fit from the tuned
    profile (1.0, 1000) recovers both within their 95 % intervals, and the intervals are narrow enough to say
    something."""
    truth = {"friction_ratio": 0.7, "wheel_servo_kp": 400.0}
    noise = np.random.default_rng(3).normal(0.0, 0.003, len(TURN_RATES))
    params, out = _generated_fit(tmp_path, monkeypatch, truth, noise, servo=0.05)
    assert params["engine_settings"]["friction_ratio"] == 1.0 and params["engine_settings"]["wheel_servo_kp"] == 1000
    f = out["fit"]
    assert f["optimizer"]["name"] == "mujoco.sysid.optimize" and f["kept"] == "the fit"
    # the settings file's header says which optimizer fitted it
    catalog = load_catalog(ROOT / "resources/simulators/simulators.yaml")
    head = "\n".join(settings_stage.calibrated_header(catalog.simulators["mujoco"], "mujoco", out, None))
    assert "gain residuals by mujoco.sysid.optimize 4." in head, head
    assert f["residual_sd_from"] == "the residuals (5 degrees of freedom)"  # 6 runs' 7 units, 2 settings
    for name, true in truth.items():
        entry = f["parameters"][name]
        assert entry["identifiable"], (name, entry)
        low, high = entry["interval"]
        assert low <= true <= high, (name, entry)
        assert out["settings"][name] == pytest.approx(true, rel=0.05), (name, entry)
    ratio, servo = f["parameters"]["friction_ratio"]["interval"], f["parameters"]["wheel_servo_kp"]["interval"]
    # the ratio to a fifteenth of its range; the servo's smaller effect to a tenth of its range's factor 50
    assert ratio[1] - ratio[0] < 0.1 and servo[1] / servo[0] < 5
    assert f["train_error"] < 0.005 < f["train_error_tuned"]


def test_a_fit_that_cannot_beat_the_tuned_profile_keeps_the_tuned_settings_and_says_so(tmp_path):
    """Real runs that the tuned profile already reproduces: no optimum lies below its training error, so the
    calibrated settings are the tuned ones, and the file says so."""
    params = _mujoco_params(class_nfev=0, max_nfev=2)
    inputs = _generated_segments(tmp_path, {})
    p = cal.CalibrateParams.model_validate(params)
    train, _ = cal.read_split(inputs["split"])
    units = cal.segment_units(p, inputs, train, p.classes)
    inputs = _generated_segments(tmp_path, dict(zip(units.names, units.simulate({}))))
    fit = cal.calibrate(inputs, params, str(tmp_path / "mujoco.yaml"))
    f = fit["fit"]
    assert f["train_error"] <= f["train_error_tuned"] + 1e-9 and f["train_error_tuned"] < 1e-3
    tuned = params["engine_settings"]
    assert fit["settings"] == {k: tuned[k] for k in ("friction_ratio", "wheel_servo_kp")}
    assert f["kept"].startswith("the tuned settings")


def test_the_fit_on_the_committed_segments_lowers_its_training_error_and_fits_each_class(tmp_path):
    params = _mujoco_params(max_nfev=3, class_nfev=1)
    split = tmp_path / "split.csv"
    cal.split_job({"segments": str(SEGMENTS)}, 0.5, 11, str(split))
    inputs = {"split": str(split), "segments": str(SEGMENTS), "urdf": str(ROOT / "resources/robot/husky_a200.urdf")}
    fit = cal.calibrate(inputs, params, str(tmp_path / "mujoco.yaml"))
    out = yaml.safe_load((tmp_path / "mujoco.yaml").read_text())
    assert out["settings"] == fit["settings"]
    f = fit["fit"]
    assert not set(f["real_runs"]) & set(fit["test_runs"])  # the test runs never reach the fit
    # the real robot turns more than the isotropic tuned profile: a ratio below 1, and a lower training error
    assert fit["settings"]["friction_ratio"] < 1.0 and f["train_error"] < f["train_error_tuned"]
    assert {u["run"] for u in f["units"]} == set(f["real_runs"])
    # each class with a training run that turns has its own fit of the ratio from the pooled one, judged on its
    # held-out runs' replayed segments (never a training one)
    assert fit["per_class"] and set(fit["per_class"]) <= set(params["classes"])
    judged = 0
    for entry in fit["per_class"].values():
        assert entry["placed_by"].startswith("its own least-squares fit on the engine")
        # one training run: the first of the pooled fit's settings, from the pooled value
        assert entry["fitted"] == ["friction_ratio"] and set(entry["settings"]) == set(fit["settings"])
        assert entry["fitted_runs"] == 1 == len(entry["runs"])  # its one training run, replayed
        assert entry["trials"][0]["settings"]["friction_ratio"] == pytest.approx(
            fit["settings"]["friction_ratio"], abs=1e-4
        )
        assert entry["train_error"] <= entry["pooled_train_error"] + 1e-9
        assert entry["improves"] == (entry["train_error"] + params["tolerance"] < entry["pooled_train_error"])
        assert not set(entry["runs"]) & set(fit["test_runs"]) and set(entry["runs"]) <= set(fit["train_runs"])
        held = entry.get("heldout")
        if held:
            judged += 1
            assert held["runs"] >= 1 and held["class_fit_error"] >= 0 and held["pooled_fit_error"] >= 0
            assert held["runs"] <= held["available"]  # the runs judged, of the class's held-out ones
            # a class's few held-out runs (fewer than statistics.min_runs) give no interval
            assert held["runs"] < 6 and held["class_fit_error_interval"] is None
            assert set(held["cases"]["segments"]).isdisjoint(f["cases"]["segments"])
    assert judged >= 1


def _setup(plan, simulator, params):
    robot = load_from_config(plan.config["robot"])
    return Setup(
        engine=params["engine"],
        robot=robot,
        timestep=params["physics"]["timestep"],
        max_wheel_torque=params["robot"]["max_wheel_torque"],
        track=params["robot"]["track"],
        settings=params["engine_settings"],
    )


def test_a_simulator_without_a_turning_setting_writes_why_and_fits_nothing(tmp_path):
    plan = _plan(_config(run=["coppeliasim"]))
    params = plan.simulator_calibrate_params("coppeliasim")
    split = tmp_path / "split.csv"
    cal.split_job({"segments": str(SEGMENTS)}, 0.5, 11, str(split))
    fit = cal.calibrate(
        {"split": str(split), "segments": str(SEGMENTS), "urdf": str(ROOT / "resources/robot/husky_a200.urdf")},
        params,
        str(tmp_path / "coppeliasim.yaml"),
    )
    assert fit["searchable"] is False and fit["settings"] == {} and "Bullet material" in fit["why_not"]
    assert plan.profile_results["coppeliasim-calibrated"] == plan.profile_results["coppeliasim-tuned"]


# --- the plan and the jobs ---


def test_the_calibrated_profile_reads_its_fit_and_leaves_the_other_profiles_jobs_alone():
    config = _config(run=["gazebo_classic", "coppeliasim"])
    with_cal = _plan(copy.deepcopy(config))
    config["simulators"]["variants"] = ["shipped", "tuned"]
    without = _plan(config)
    assert "gazebo_classic-calibrated" in with_cal.profiles and "gazebo_classic-calibrated" in with_cal.calibrated
    assert with_cal.profile_results["coppeliasim-calibrated"] == with_cal.profile_results["coppeliasim-tuned"]
    assert with_cal.validation_inputs("gazebo_classic-calibrated")["calibrated"].endswith("gazebo_classic.yaml")
    assert "calibrated" not in with_cal.validation_inputs("gazebo_classic-tuned")
    for model in ("gazebo_classic-shipped", "gazebo_classic-tuned", "ode"):
        assert repr(with_cal.validation_params(model)) == repr(without.validation_params(model))
    params = with_cal.validation_params("gazebo_classic-calibrated")
    merged, provenance = cal.with_calibrated(params, None)
    assert merged is params and provenance == {}


def test_a_job_merges_the_fit_over_its_settings_and_records_where_they_came_from(tmp_path):
    path = tmp_path / "fit.yaml"
    path.write_text(yaml.safe_dump({"settings": {"friction_ratio": 0.6, "contact_slip": 0.001}}))
    params = {"engine": "ode", "engine_settings": {"friction_ratio": 1.0, "contact_slip": 0.004, "erp": 0.2}}
    merged, provenance = cal.with_calibrated(params, str(path))
    assert merged["engine_settings"] == {"friction_ratio": 0.6, "contact_slip": 0.001, "erp": 0.2}
    assert params["engine_settings"]["friction_ratio"] == 1.0  # the plan's params are not edited
    assert provenance == {
        "calibrated_from": str(path),
        "calibrated_settings": {"friction_ratio": 0.6, "contact_slip": 0.001},
    }


# --- the mechanics of its own parameters ---


def test_a_yaw_gain_case_without_a_ratio_is_judged_against_the_model_s_own_ratio(husky):
    robot, section = husky
    settings = (
        get_engine("mujoco")
        .settings_model.model_validate(
            {
                "cone": "elliptic",
                "wheel_contact": "decoupled",
                "integrator": "implicitfast",
                "wheel_servo": "intvelocity",
            }
        )
        .model_dump(mode="json")
    )
    case = {"kind": "yaw_gain", "v": 0.5, "w": 0.5, "mu": 0.8, "duration": 3.0}
    layout = contact_layout(robot)
    for ratio in (1.0, 0.7):
        setup = Setup(
            engine="mujoco",
            robot=robot,
            timestep=0.001,
            max_wheel_torque=section["max_wheel_torque"],
            track=section["track"],
            settings={**settings, "friction_ratio": ratio},
        )
        check = run_case(setup, "gain", case)["checks"][0]
        expected = yaw_rate_gain(with_friction_ratio(layout, ratio), 0.5, 0.5, section["track"])
        assert check["analytic_value"] == pytest.approx(expected, rel=1e-6)
        assert "friction_ratio" not in check  # an isotropic case of its own set-up (gains.csv keeps it)
        assert check["engine_value"] == pytest.approx(expected, rel=0.10)  # MuJoCo follows its own Coulomb gain
    assert yaw_rate_gain(with_friction_ratio(layout, 0.7), 0.5, 0.5, section["track"]) > 0.6 > 0.478


# --- the table and the file ---


def test_the_table_has_the_held_out_columns_computed_on_the_test_runs_only(tmp_path):
    for column in (
        "heldout_gain_error",
        "heldout_gain_error_low",
        "heldout_gain_error_high",
        "heldout_runs",
        "real_spread",
        "within_spread",
        "heldout_heading_error",
        "calibrated_settings",
        "turning_settable",
        "mechanics_own",
    ):
        assert column in stage.TABLE_COLUMNS
    split = tmp_path / "split.csv"
    pd.DataFrame(
        {
            "terrain_class": ["a", "a", "b", "b"],
            "run": ["1", "2", "1", "2"],
            "unit": list("wxyz"),
            "set": ["train", "test", "train", "test"],
        }
    ).to_csv(split, index=False)
    rows = []
    for cls, run, real, err in [
        ("a", "1", 0.70, 0.5),
        ("a", "2", 0.74, 0.02),
        ("b", "1", 0.60, 0.5),
        ("b", "2", 0.64, 0.06),
    ]:
        rows.append(
            {
                "engine": "m",
                "terrain_class": cls,
                "run": run,
                "test": f"{cls}{run}",
                "status": "ok",
                "gain_error": err,
                "heading_error": 2 * err,
                "yaw_rate_gain_real": real,
            }
        )
    tests = pd.DataFrame(rows)
    verdict = {"margins": {"gain_error": {"basis": "real_spread", "value": 1.0}}}
    columns = stage._heldout({"split": str(split)}, tests, verdict, {"min_runs": 6, "level": 0.95}, 0)("m")
    assert columns["heldout_gain_error"] == pytest.approx(0.04)  # the training runs' 0.5 never counts
    assert columns["train_gain_error"] == pytest.approx(0.5)  # they count beside it, apart
    assert columns["heldout_runs"] == 2 and math.isnan(columns["heldout_gain_error_low"])  # too few runs
    assert columns["heldout_heading_error"] == pytest.approx(0.08)
    assert columns["real_spread"] == pytest.approx(math.sqrt(0.02**2 * 2 * 2 / 2))  # pooled within-class sd
    assert columns["within_spread"] is False
    # the training column over the fitted classes only: the runs the fit's objective covers
    tests.loc[tests.terrain_class == "b", "gain_error"] = [0.9, 0.06]
    fitted = stage._heldout({"split": str(split)}, tests, verdict, {"min_runs": 6, "level": 0.95}, 0, ["a"])("m")
    assert fitted["train_gain_error"] == pytest.approx(0.5)  # b/1's 0.9 is not a fitted class's
    every = stage._heldout({"split": str(split)}, tests, verdict, {"min_runs": 6, "level": 0.95}, 0)("m")
    assert every["train_gain_error"] == pytest.approx(0.7)
    assert fitted["heldout_gain_error"] == every["heldout_gain_error"]  # the held-out runs stay every class's


def test_the_calibrated_settings_file_is_headed_by_its_data_figures_and_command_and_reads_back(tmp_path):
    catalog = load_catalog(ROOT / "resources/simulators/simulators.yaml")
    sim = catalog.simulators["gazebo_classic"]
    fit = {
        "simulator": "gazebo_classic",
        "robot": "husky_a200",
        "source": "segments-borealtc",
        "train_runs": ["flooring/07", "ice/02"],
        "test_runs": ["flooring/01", "ice/04"],
        "searchable": True,
        "why_not": None,
        "settings": {"contact_slip": 0.001, "friction_ratio": 0.49},
        "exposed": {"friction_ratio": "<mu2>0.49 x mu</mu2> with <fdir1>1 0 0</fdir1>"},
        "fit": {
            "real_gain": 0.645,
            "real_runs": ["flooring/07", "ice/02"],
            "coulomb_ratio": 0.73,
            "trials": [[1.0, 0.43], [0.49, 0.644]],
            "train_error_tuned": 0.207,
            "train_error": 0.1,
            "kept": "the fit",
            "parameters": {
                "friction_ratio": {"value": 0.49, "identifiable": True, "interval": [0.3, 0.77], "at_bound": "low"},
                "contact_slip": {"value": 0.001, "identifiable": False, "why": "unidentifiable from these runs"},
            },
            "engine_gain": 0.644,
            "reached": True,
            "tolerance": 0.005,
        },
    }
    row = {
        "heldout_gain_error": 0.031,
        "heldout_gain_error_low": math.nan,
        "heldout_gain_error_high": math.nan,
        "heldout_runs": 4,
        "real_spread": 0.045,
        "within_spread": True,
        "heldout_heading_error": 0.04,
        "mechanics_own": "passes 17/20",
    }
    table = pd.DataFrame([dict(row, simulator="gazebo_classic", variant="calibrated")])
    from simpick.engines import simulator_files as formats

    settings = catalog.settings("gazebo_classic", "tuned", "husky_a200")
    settings = get_engine("ode").settings_model.model_validate(settings).model_dump(mode="json")
    settings_stage._calibrated_file(
        formats, sim, "gazebo_classic", settings, fit, table, catalog, "husky_a200", ["front_left_wheel_link"], tmp_path
    )
    texts = {p.name.split(".", 1)[1]: p.read_text() for p in tmp_path.glob("gazebo_classic-calibrated.*")}
    assert set(texts) == {"world.sdf", "wheels.urdf"}
    head = texts["wheels.urdf"]
    assert "flooring/07" in head and "0.031" in head and "0.045" in head and "passes 17/20" in head
    assert "regenerate: snakemake" in head and "results/simulators/settings" in head
    for text in texts.values():
        comments = re.findall(r"<!--(.*?)-->", text, flags=re.S)
        assert comments and not any("--" in c for c in comments)
        ET.fromstring(re.sub(r"<!--.*?-->\n?", "", text, flags=re.S))
    back = formats.read("sdf", "ode", texts)
    assert back["friction_ratio"] == pytest.approx(0.49) and back["contact_slip"] == pytest.approx(0.001)


def test_a_class_whose_own_fit_differs_gets_its_own_file_and_a_row_beside_the_pooled(tmp_path):
    catalog = load_catalog(ROOT / "resources/simulators/simulators.yaml")
    sim = catalog.simulators["mujoco"]
    entry = {
        "settings": {"friction_ratio": 0.576},
        "real_gain": 0.712,
        "runs": ["flooring/07"],
        "placed_by": "its own fit on the engine (2 trials from the Coulomb placement)",
        "engine_gain": 0.7115,
        "reached": True,
        "heldout": {
            "runs": 7,
            "real_gain": 0.72,
            "class_fit_error": 0.011,
            "class_fit_error_interval": [0.006, 0.02],
            "pooled_fit_error": 0.079,
            "pooled_fit_error_interval": None,
        },
    }
    same = dict(entry, settings={"friction_ratio": 0.702}, heldout=None)  # within 0.01 of the pooled: no file
    placed = {k: v for k, v in entry.items() if k != "engine_gain"}  # placed by Coulomb alone: no file
    worse = dict(entry, settings={"friction_ratio": 0.9}, improves=False)  # farther from its training runs: none
    fit = {
        "simulator": "mujoco",
        "robot": "husky_a200",
        "source": "segments-borealtc",
        "searchable": True,
        "settings": {"friction_ratio": 0.698},
        "exposed": {"friction_ratio": 'friction="0.698 x mu mu 0 0 0"'},
        "per_class": {"flooring": entry, "ice": same, "snow": placed, "asphalt": worse},
        "fit": {"real_gain": 0.645},
    }
    assert set(settings_stage.class_files(fit)) == {"flooring"}
    table = classes_stage.per_class_table({"mujoco": fit}, catalog)
    assert list(table.terrain_class) == ["flooring", "ice", "snow", "asphalt"]
    row = table.set_index("terrain_class").loc["flooring"]
    assert (row.class_settings, row.pooled_settings, row.class_fit_error, row.pooled_fit_error) == (
        "friction_ratio = 0.576",
        "friction_ratio = 0.698",
        0.011,
        0.079,
    )
    assert (row.class_fit_error_low, row.class_fit_error_high) == (0.006, 0.02)
    assert math.isnan(row.pooled_fit_error_low) and math.isnan(row.pooled_fit_error_high)
    assert row.settings_file.endswith("mujoco-calibrated-flooring")
    assert table.set_index("terrain_class").loc["ice"].settings_file == ""

    settings = catalog.settings("mujoco", "tuned", "husky_a200")
    settings = get_engine("mujoco").settings_model.model_validate(settings).model_dump(mode="json")
    from simpick.engines import simulator_files as formats

    settings_stage._calibrated_file(
        formats,
        sim,
        "mujoco",
        settings,
        fit,
        pd.DataFrame(columns=["simulator", "variant"]),
        catalog,
        "husky_a200",
        ["front_left_wheel_link"],
        tmp_path,
    )
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["mujoco-calibrated-flooring.xml", "mujoco-calibrated.xml"], names
    own = (tmp_path / "mujoco-calibrated-flooring.xml").read_text()
    assert "calibrated for flooring" in own and "0.079" in own and "friction_ratio = 0.576" in own
    back = formats.read("mjcf", "mujoco", {"xml": own})
    assert back["friction_ratio"] == pytest.approx(0.576)
    pooled = formats.read("mjcf", "mujoco", {"xml": (tmp_path / "mujoco-calibrated.xml").read_text()})
    assert pooled["friction_ratio"] == pytest.approx(0.698)


def test_the_calibrated_variant_is_a_model_of_its_own_in_the_registry():
    assert VARIANTS == ("shipped", "tuned", "calibrated")
    catalog = load_catalog(ROOT / "resources/simulators/simulators.yaml")
    assert catalog.settings("webots", "calibrated", "husky_a200") == catalog.settings("webots", "tuned", "husky_a200")
    assert np.isfinite(0.0)


# --- on DRIVE's steps (a robot whose real runs are DRIVE's: the Warthog) ---

CALIB = ROOT.parent / "shared/data/drive/calib_data"
needs_drive = pytest.mark.skipif(
    not CALIB.is_dir(), reason=f"DRIVE sessions not present at {CALIB} (the shared data folder; see its README)"
)


@pytest.fixture(scope="module")
def drive_steps(tmp_path_factory):
    """DRIVE's steps table of the shared sessions, as its import step writes it, its case and wheels tables
    beside it."""
    from simpick.real import drive as D

    folder = tmp_path_factory.mktemp("drive")
    D.write_tables(
        D.open_drive(CALIB),
        {t: str(folder / f"{t}.csv") for t in ("steps", "cases")} | {"wheels": str(folder / "wheels.parquet")},
    )
    return folder / "steps.csv"


def _warthog_config(drive: bool = True, run: list[str] | None = None) -> dict:
    config = study_config("config/robots/warthog.yaml")
    config["robot"]["urdf"] = str(ROOT / config["robot"]["urdf"])
    config["simulators"]["catalog"] = str(ROOT / "resources/simulators/simulators.yaml")
    config["simulators"]["calibration"] = str(SPACES)
    config["simulators"]["drive"] = drive
    config["drive_dir"] = str(CALIB)
    if run is not None:
        config["simulators"]["run"] = run
    return config


@needs_drive
def test_drive_steps_are_split_one_by_one_stratified_by_turning_and_the_same_every_time(drive_steps, tmp_path):
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    cal.split_job({"steps": str(drive_steps)}, 0.5, 11, str(a))
    cal.split_job({"steps": str(drive_steps)}, 0.5, 11, str(b))
    assert a.read_text() == b.read_text()
    train, test = cal.read_split(a)
    steps = pd.read_csv(drive_steps)
    keys = steps.terrain_class + "/" + cal.steps_key(steps)
    assert set(train) | set(test) == set(keys) and not set(train) & set(test)
    assert len(keys) == 350  # DRIVE's README: 100 + 100 + 30 + 20 + 100 steps in the 5 sessions, each once
    # half of each class's turning steps, and of its straight ones, on each side (within one of a half)
    for (cls, turns), g in steps.assign(key=keys).groupby(["terrain_class", "turning"]):
        held = g.key.isin(set(test)).sum()
        assert abs(held - len(g) / 2) <= 1, (cls, turns, held, len(g))


@needs_drive
def test_the_fit_on_drive_pools_the_target_class_s_training_steps_and_never_a_held_out_one(drive_steps, tmp_path):
    plan = _plan(_warthog_config(run=["mujoco"]))
    assert plan.calibration_source == "drive" and "mujoco-calibrated" in plan.calibrated
    assert plan.calibration_real_input() == {
        "steps": "results/drive/drive/steps.csv",
        "cases": "results/drive/drive/cases.csv",
        "wheels": "results/drive/drive/wheels.parquet",
    }
    params = dict(plan.simulator_calibrate_params("mujoco"), max_nfev=2, class_nfev=0, drive_commands=2)
    assert params["kind"] == "drive" and params["source"] == "drive-drive"
    assert params["steps_case"]["engine"] == "mujoco-calibrated" and "session" not in params["steps_case"]
    split = tmp_path / "split.csv"
    cal.split_job({"steps": str(drive_steps)}, 0.5, 11, str(split))
    folder = drive_steps.parent
    inputs = {
        "split": str(split),
        "steps": str(drive_steps),
        "cases": str(folder / "cases.csv"),
        "wheels": str(folder / "wheels.parquet"),
        "urdf": str(ROOT / "resources/robot/warthog.urdf"),
    }
    fit = cal.calibrate(inputs, params, str(tmp_path / "mujoco.yaml"))
    train, test = cal.read_split(split)
    steps = pd.read_csv(drive_steps)
    steps["key"] = steps.terrain_class + "/" + cal.steps_key(steps)
    # DRIVE's terrains are asphalt, grass and gravel: of the target classes only asphalt
    assert fit["fit"]["classes"] == ["asphalt"]
    fitted = steps[steps.key.isin(set(train)) & steps.turning & (steps.terrain_class == "asphalt")]
    assert fit["fit"]["real_gain"] == pytest.approx(fitted.gain.mean(), abs=1e-4)
    assert set(fit["fit"]["real_runs"]) == set(fitted.key) and not set(fit["fit"]["real_runs"]) & set(test)
    assert sorted(fit["per_class"]) == ["asphalt", "grass", "gravel"]
    # a class's spread is its own step-to-step repeatability (the table's spread over its steps alone), not the
    # spread of its steps' gains, which DRIVE draws at independent commands
    from simpick.compare.steps import gain_repeatability

    assert params["drive_tolerance"] > 0
    for cls, entry in fit["per_class"].items():
        sd, pairs = gain_repeatability(steps[steps.terrain_class == cls], params["drive_tolerance"])
        assert entry["class_spread"] == pytest.approx(sd, abs=1e-4) and entry["spread_runs"] == pairs > 0
        assert "pairs of steps of similar command" in entry["spread_basis"]
        assert entry["class_spread"] < steps[(steps.terrain_class == cls) & steps.turning].gain.std()
    # two training steps, each replayed from its warm-up as DRIVE's replay replays it, none held out
    assert len(fit["fit"]["cases"]["steps"]) == 2 and not set(fit["fit"]["cases"]["steps"]) & set(test)
    assert fit["fit"]["method"].endswith(cal.job.REPLAYED["drive"]) and "warm-up" in fit["fit"]["cases"]["from"]
    # the Warthog's real gain on asphalt (0.58) is about its isotropic Coulomb gain (0.57): a ratio near 1
    assert 0.8 < fit["settings"]["friction_ratio"] < 1.3


def test_drive_without_the_profiles_replaying_it_leaves_the_calibrated_row_out_and_says_how():
    plan = _plan(_warthog_config(drive=False, run=["mujoco"]))
    assert plan.calibration_source is None and not plan.calibrated
    assert "simulators.drive: true" in plan.calibrated_left_out


def test_held_out_drive_steps_judge_every_row_on_the_test_steps_only(tmp_path):
    split = pd.DataFrame(
        {
            "terrain_class": ["asphalt"] * 8,
            "run": [f"s/{k:03d}" for k in range(8)],
            "unit": [f"s/{k:03d}" for k in range(8)],
            "set": ["train", "test"] * 4,
        }
    )
    split.to_csv(tmp_path / "split.csv", index=False)
    rows = []
    for k in range(8):  # a training step's error is 1.0, a test step's 0.01 k: only the latter may count
        held = k % 2 == 1
        rows.append(
            {
                "case": f"s/{k:03d}",
                "engine": "m",
                "terrain_class": "asphalt",
                "status": "ok",
                "gain_error": 0.01 * k if held else 1.0,
                "heading_error": 0.1 if held else 5.0,
                "speed_error": 0.2 if held else 5.0,
            }
        )
    pd.DataFrame(rows).to_csv(tmp_path / "errors.csv", index=False)
    statistics = {"min_runs": 3, "confidence": 0.95}
    columns = stage._heldout_steps(
        {"split": str(tmp_path / "split.csv"), "drive_errors": str(tmp_path / "errors.csv")}, 0.015, statistics, 1
    )("m")
    assert columns["heldout_runs"] == 4 and columns["heldout_gain_error"] == pytest.approx(0.04)
    assert columns["heldout_heading_error"] == pytest.approx(0.1)
    assert columns["heldout_speed_error"] == pytest.approx(0.2)
    assert columns["train_gain_error"] == pytest.approx(1.0)  # the training steps' own error, beside it
    assert columns["real_spread"] == 0.015 and columns["within_spread"] is False
    assert columns["heldout_gain_error_low"] <= 0.04 <= columns["heldout_gain_error_high"]


# --- on the full replay's runs (borealtc_dir): the calibration's split, the steady turning windows ---


def _replay_log(tmp_path, cls: str, run: str, gain: float, straight: float) -> str:
    """A canonical log of 35 s: straight for ``straight`` s, then a spin (0.4 m/s a side) turning at ``gain``."""
    from simpick.real.logs.canonical import RealLog, write_canonical

    t = np.round(np.arange(0.0, 35.0, 0.01), 6)
    spin = t >= straight
    left, right = np.where(spin, -0.4, 0.3), np.where(spin, 0.4, 0.3)
    wz = gain * (right - left) / 0.555
    imu = pd.DataFrame({"time": t, "ax": 0.0, "ay": 0.0, "az": 9.81, "wx": 0.0, "wy": 0.0, "wz": wz})
    commands = pd.DataFrame({"time": t, "v_left": left, "v_right": right})
    meta = {"dataset": "borealtc", "terrain_class": cls.upper(), "run_id": run, "name": f"{cls}-{run}"}
    return str(write_canonical(RealLog(imu=imu, commands=commands, meta=meta), tmp_path / f"logs/{cls}/{run}.parquet"))


def test_the_full_replay_fits_on_its_training_runs_first_turning_windows_replayed_from_rest(tmp_path, monkeypatch):
    """Kind replay fits what its held-out table judges: each training run replayed from rest as its replay simulate
    job replays it (its class's case params, the trial's settings merged), up to the end of its first turning
    window of the comparison's grid, and that window's gain taken as the comparison takes it; never a held-out
    run, and each class's own fit judged on its held-out runs' windows the same way."""
    import simpick.simulate.real as real_sim

    config = _config(run=["mujoco"])
    config["borealtc_dir"] = str(ROOT.parent / "shared/data/borealtc")
    plan = _plan(config)
    assert plan.calibration_source == "replay"
    real_input = plan.calibration_real_input()
    assert real_input["windows"] == "results/real/borealtc/turning/windows.csv"
    assert real_input["calibration_split"] == "results/calibration/replay-borealtc/split.csv"
    assert real_input["logs"] and all(path.startswith("results/real/borealtc/logs/") for path in real_input["logs"])
    params = dict(plan.simulator_calibrate_params("mujoco"), max_nfev=4, class_nfev=2)
    assert params["kind"] == "replay" and params["source"] == "replay-borealtc"
    assert params["replay_window"] == 10.0 and set(params["replay_cases"]) == set(params["classes"])
    assert params["replay_cases"]["ice"]["engine"] == "mujoco-calibrated"
    assert params["replay_cases"]["ice"]["terrain_class"] == "ice"
    # the calibration's split of the replay's runs, taken as it is
    runs = [("flooring", f"{k:02d}") for k in range(1, 7)] + [("ice", f"{k:02d}") for k in range(1, 5)]
    calibration_split = tmp_path / "calibration_split.csv"
    pd.DataFrame(
        [[c, r, r, "test" if i % 2 else "train"] for i, (c, r) in enumerate(runs)],
        columns=["terrain_class", "run", "unit", "set"],
    ).to_csv(calibration_split, index=False)
    split = tmp_path / "split.csv"
    cal.split_job({"calibration_split": str(calibration_split), "windows": "unused"}, 0.5, 11, str(split))
    assert pd.read_csv(split).equals(pd.read_csv(calibration_split))
    # the real robot turns at 0.7 on flooring, 0.6 on ice; some runs drive straight 12 s first
    logs = [
        _replay_log(tmp_path, c, r, 0.7 if c == "flooring" else 0.6, 12.0 * (i % 4 == 2))
        for i, (c, r) in enumerate(runs)
    ]
    windows = pd.DataFrame(
        [{"terrain_class": c, "run": r, "v": 0.0, "w_kinematic": 1.44, "yaw_rate_gain": 0.7} for c, r in runs]
    )
    windows.to_csv(tmp_path / "windows.csv", index=False)
    replayed = []

    def fake_replay(log, urdf, p, duration=None):  # the engine: gain 1.05 - 0.5 x ratio, 0.2 less on ice
        p = real_sim.real_case(p)
        replayed.append((f"{p.terrain_class}/{log.meta['run_id']}", duration, p.engine))
        t = np.round(np.arange(0.01, duration, 0.01), 6)
        cmd = log.wheel_commands(0.555)
        held = np.clip(np.searchsorted(cmd.time.to_numpy(), t, side="right") - 1, 0, len(cmd) - 1)
        w = (cmd.v_right.to_numpy()[held] - cmd.v_left.to_numpy()[held]) / 0.555
        gain = 1.05 - 0.5 * p.engine_settings["friction_ratio"] - (0.2 if p.terrain_class == "ice" else 0.0)
        return {"time": t, "wz": gain * w}, {"health": {"status": "ok", "reasons": []}}

    monkeypatch.setattr(real_sim, "replay_log", fake_replay)
    inputs = {
        "split": str(split),
        "windows": str(tmp_path / "windows.csv"),
        "logs": logs,
        "urdf": config["robot"]["urdf"],
    }
    train, test = cal.read_split(split)
    fit = cal.calibrate(inputs, params, str(tmp_path / "mujoco.yaml"))
    f = fit["fit"]
    # one window a run, its first that turns on the comparison's grid: [0, 10] s, or [10, 20] s after 12 s straight;
    # each run replayed from rest up to that window's end
    assert f["cases"]["windows"] == [
        "flooring/01 [0, 10] s",
        "flooring/03 [10, 20] s",
        "flooring/05 [0, 10] s",
        "ice/01 [10, 20] s",
        "ice/03 [0, 10] s",
    ]
    assert {w.split()[0] for w in f["cases"]["windows"]} == set(train)
    assert all(run in set(train) | set(test) for run, _, _ in replayed)
    pooled = {(run, d) for run, d, e in replayed[: len(f["cases"]["windows"])]}
    assert all(run in set(train) and d <= 20.1 for run, d in pooled) and all(
        e == "mujoco-calibrated" for *_, e in replayed
    )
    assert f["method"].endswith(cal.job.REPLAYED["replay"])
    # each class's own ratio is where the engine turns as its runs do: flooring 0.7 at 0.7, ice 0.6 at 0.5
    assert f["kept"] == "the fit" and f["train_error"] < f["train_error_tuned"]
    flooring, ice = fit["per_class"]["flooring"], fit["per_class"]["ice"]
    assert flooring["settings"]["friction_ratio"] == pytest.approx(0.7, abs=0.03)
    assert ice["settings"]["friction_ratio"] == pytest.approx(0.5, abs=0.03)
    assert flooring["heldout"]["runs"] == 3 and "windows" in flooring["heldout"]["cases"]
    assert ice["heldout"]["class_fit_error"] < ice["heldout"]["pooled_fit_error"]


@needs_drive
def test_the_held_out_steps_spread_is_the_warthog_s_step_to_step_repeatability(drive_steps):
    """The spread a DRIVE row is set beside is the verdict's gain margin on DRIVE: the real robot's step-to-step
    repeatability of its gain over similar commands (0.015 on the shared sessions), not a tolerance."""
    from simpick.score.settings import Verdict
    from simpick.sources.drive import SIMILAR

    verdict = Verdict.model_validate(study_config()["verdict"])
    spread = stage.drive_spread({"drive_steps": str(drive_steps)}, verdict, SIMILAR)
    assert spread == pytest.approx(0.0153, abs=5e-4)


def test_a_fit_within_two_percent_of_a_step_in_the_engine_s_gain_is_no_calibration(tmp_path, monkeypatch):
    """An engine whose gain steps to 0 below a ratio of 0.69 (as DART's friction box in gz-physics locks the
    Husky's turn on one side of a ratio between 0.74 and 0.78), runs made at 0.70: from the tuned 1.0 the fit lands
    1.4 % above the step. Stepped 2 % of its value down, the gains jump, so the fit is not kept: the calibrated
    settings are the tuned ones, and the file says why and where it probed. The same runs on an engine without the
    step keep the fit."""

    def locking(settings: dict, servo: float) -> np.ndarray:
        smooth = _generated_gains(settings, servo)
        return np.where(settings["friction_ratio"] >= 0.69, smooth, 0.0)

    truth = {"friction_ratio": 0.7, "wheel_servo_kp": 1000.0}
    noise = np.zeros(len(TURN_RATES))
    params, out = _generated_fit(tmp_path, monkeypatch, truth, noise, servo=0.0, gains=locking)
    f = out["fit"]
    assert f["optimum_error"] < f["train_error_tuned"]  # the optimum itself fits the runs
    margin = f["step_margins"]["friction_ratio"]
    assert margin["step"] is True and margin["probed"] == [
        pytest.approx(0.7 * 0.98, abs=2e-3),
        pytest.approx(0.714, abs=2e-3),
    ]
    assert f["kept"].startswith("the tuned settings: the optimum's friction_ratio lies within 2% of a step")
    assert out["settings"]["friction_ratio"] == params["engine_settings"]["friction_ratio"]

    _, smooth = _generated_fit(tmp_path, monkeypatch, truth, noise, servo=0.0)
    assert smooth["fit"]["step_margins"]["friction_ratio"]["step"] is False and smooth["fit"]["kept"] == "the fit"


def test_the_contact_s_and_the_actuator_s_shares_of_a_fit_are_measured_apart():
    """Without an engine: a gain falling with the friction ratio (contact) and with a softer servo (actuator). Each
    part alone at its fitted value, the other at its tuned one, gives its own training error; the contact, whose
    effect is ten times the servo's here, takes most of the fall. A fit with no actuator setting says so."""
    space = cal.SearchSpace.model_validate(
        {
            "searchable": True,
            "settings": {
                "friction_ratio": {"exposed_as": "r", "bounds": [0.3, 1.8], "source": "a.c:1"},
                "wheel_servo_kp": {
                    "exposed_as": "k",
                    "bounds": [100.0, 5000.0],
                    "source": "a.c:2",
                    "log": True,
                    "part": "actuator",
                },
            },
        }
    )
    runs = ["a/1", "b/1", "c/1"]
    rates = np.array([0.2, 0.5, 0.9])

    def gains(settings):
        return 0.95 - 0.4 * settings["friction_ratio"] - 0.04 * rates * math.sqrt(1000.0 / settings["wheel_servo_kp"])

    tuned = {"friction_ratio": 1.0, "wheel_servo_kp": 1000.0}
    fitted = {"friction_ratio": 0.62, "wheel_servo_kp": 4000.0}
    units = cal.Units(runs, gains(fitted), runs, lambda s: gains({**tuned, **s}), {})
    tuned_error, error = units.error(gains(tuned)), units.error(gains(fitted))
    parts = cal.part_shares(units, space, {}, tuned, fitted, tuned_error, error, True)
    assert parts["contact"]["settings"] == ["friction_ratio"] and parts["actuator"]["settings"] == ["wheel_servo_kp"]
    contact_alone = units.error(gains({**tuned, "friction_ratio": 0.62}))
    assert parts["contact"]["train_error"] == pytest.approx(contact_alone, abs=1e-4)
    assert 0.8 < parts["contact"]["share"] < 1.0 and 0.0 < parts["actuator"]["share"] < 0.2, parts
    alone = cal.part_shares(units, space, {}, tuned, {"friction_ratio": 0.62}, tuned_error, error, True)
    assert alone["contact"]["share"] == 1.0 and alone["actuator"]["settings"] == []
    assert "no actuator setting" in alone["actuator"]["why_none"]


@pytest.mark.parametrize("order", [["wheel_servo_kp", "friction_ratio"], ["friction_ratio", "wheel_servo_kp"]])
def test_the_fit_takes_the_settings_in_the_search_space_s_order_one_alone_on_one_run(tmp_path, monkeypatch, order):
    """The fit takes the settings in the search space's ``order``: one training run fits the first alone, and the
    file keeps the other's tuned value. Here the MuJoCo fit on one run, each order in turn (the shipped one puts
    the ratio first, so that a class with one training run fits its ratio)."""
    params = _mujoco_params(class_nfev=0)
    params["space"] = {**params["space"], "order": order}
    tuned = params["engine_settings"]
    truth = {"friction_ratio": 0.8, "wheel_servo_kp": 400.0}
    real = _generated_gains(truth, 0.05)

    def simulate(s: dict) -> np.ndarray:
        return _generated_gains({**tuned, **s}, 0.05)

    runs = ["flooring/07"] * len(real)
    units = cal.Units(runs, real, [f"u{k}" for k in range(len(real))], simulate, {"generated": True})
    monkeypatch.setattr(cal.job, "_units", lambda *args: units)
    split = tmp_path / "split.csv"
    cal.split_job({"segments": str(SEGMENTS)}, 0.5, 11, str(split))
    inputs = {"split": str(split), "segments": str(SEGMENTS), "urdf": str(ROOT / "resources/robot/husky_a200.urdf")}
    out = cal.calibrate(inputs, params, str(tmp_path / "mujoco.yaml"))
    f = out["fit"]
    first, other = order
    assert list(f["parameters"]) == [first]
    assert f["kept"] == "the fit" and f["train_error"] < f["train_error_tuned"]
    assert out["settings"].get(other, tuned[other]) == tuned[other]


def test_an_order_naming_a_setting_twice_or_one_the_entry_lacks_is_refused():
    space = cal.load_search_spaces(ROOT / "resources/simulators/calibration.yaml")["mujoco"].model_dump()
    for order in (["friction_ratio", "friction_ratio"], ["wheel_separation"]):
        with pytest.raises(ValueError, match="must name settings of this entry, each once"):
            cal.SearchSpace.model_validate({**space, "order": order})
    assert cal.SearchSpace.model_validate({**space, "order": []}).fit_order() == sorted(space["settings"])
    assert cal.SearchSpace.model_validate({**space, "order": ["wheel_servo_kp"]}).fit_order() == [
        "wheel_servo_kp",
        "friction_ratio",
    ]


def test_a_setting_the_tuned_profile_leaves_unset_starts_at_its_bounds_middle(tmp_path, monkeypatch):
    """Gazebo's tuned profile writes no <slip2> (its value None): the fit starts that setting at its bounds' middle
    (over their logarithms for a log setting), since from a bound scipy's trf starts its trust region as small as
    the start and stops there, and where the fit is not kept the file leaves the setting unset. Here the MuJoCo
    fit with its servo gain unset in the tuned profile."""
    params = _mujoco_params(class_nfev=0, max_nfev=4)
    params["engine_settings"] = {**params["engine_settings"], "wheel_servo_kp": None}
    low, high = params["space"]["settings"]["wheel_servo_kp"]["bounds"]
    truth = {"friction_ratio": 0.7, "wheel_servo_kp": 1000.0}
    real = _generated_gains(truth, 0.05)

    def simulate(s: dict) -> np.ndarray:
        merged = {**params["engine_settings"], **s}
        return _generated_gains({**merged, "wheel_servo_kp": merged["wheel_servo_kp"] or 1000.0}, 0.05)

    units = cal.Units(UNIT_RUNS, real, [f"u{k}" for k in range(len(real))], simulate, {"generated": True})
    monkeypatch.setattr(cal.job, "_units", lambda *args: units)
    split = tmp_path / "split.csv"
    cal.split_job({"segments": str(SEGMENTS)}, 0.5, 11, str(split))
    inputs = {"split": str(split), "segments": str(SEGMENTS), "urdf": str(ROOT / "resources/robot/husky_a200.urdf")}
    out = cal.calibrate(inputs, params, str(tmp_path / "mujoco.yaml"))
    assert out["fit"]["start"]["wheel_servo_kp"] == pytest.approx(math.sqrt(low * high), rel=1e-3)
    assert out["fit"]["kept"] == "the fit" and out["settings"]["friction_ratio"] == pytest.approx(0.7, abs=0.03)
    # the same runs where the tuned profile cannot be beaten: the unset setting stays unset
    units.real = simulate({})
    out = cal.calibrate(inputs, params, str(tmp_path / "mujoco.yaml"))
    assert out["fit"]["kept"].startswith("the tuned settings") and "wheel_servo_kp" not in out["settings"]


def _ratio_fixed(params: dict) -> dict:
    """The MuJoCo fit's params with its ratio fixed at 0.7 among the required settings and its servo gain the only
    setting fitted, as Gazebo's space fixes its ratio and fits its slip2."""
    space = params["space"]
    ratio = {"value": 0.7, "exposed_as": "the pairs' friction ratio, fixed", "source": "a test"}
    params["space"] = {
        **space,
        "settings": {"wheel_servo_kp": space["settings"]["wheel_servo_kp"]},
        "requires": {**space.get("requires", {}), "friction_ratio": ratio},
        "order": [],
    }
    return params


def test_a_ratio_the_search_space_fixes_is_set_not_fitted_and_gets_no_class_fit(tmp_path, monkeypatch):
    """Gazebo's search space fixes the ratio among its required settings (it only switches DART's turn) and fits
    the wheels' slip2: the fit runs with the ratio fixed, the file states it with the fit, no class gets a fit of
    its own ratio, and the Coulomb reference keeps the calibration's ratio bounds. Here the MuJoCo fit with its
    ratio fixed at the runs' own 0.7 and its servo gain fitted."""
    params = _ratio_fixed(_mujoco_params(class_nfev=3, max_nfev=4))
    truth = {"friction_ratio": 0.7, "wheel_servo_kp": 400.0}
    real = _generated_gains(truth, 0.05)

    def simulate(s: dict) -> np.ndarray:
        return _generated_gains({**params["engine_settings"], **s}, 0.05)

    units = cal.Units(UNIT_RUNS, real, [f"u{k}" for k in range(len(real))], simulate, {"generated": True})
    monkeypatch.setattr(cal.job, "_units", lambda *args: units)
    split = tmp_path / "split.csv"
    cal.split_job({"segments": str(SEGMENTS)}, 0.5, 11, str(split))
    inputs = {"split": str(split), "segments": str(SEGMENTS), "urdf": str(ROOT / "resources/robot/husky_a200.urdf")}
    out = cal.calibrate(inputs, params, str(tmp_path / "mujoco.yaml"))
    f = out["fit"]
    assert list(f["parameters"]) == ["wheel_servo_kp"] and f["kept"] == "the fit"
    assert out["settings"]["friction_ratio"] == 0.7 and f["fixed"]["friction_ratio"] == 0.7
    assert out["settings"]["wheel_servo_kp"] == pytest.approx(400.0, rel=0.1)
    assert f["bounds"] == [0.3, 1.8] and all(t[0] == 0.7 for t in f["trials"])
    # the classes fit what the pooled fit fitted (the servo gain), never the fixed ratio
    assert out["per_class"] and all(e["fitted"] == ["wheel_servo_kp"] for e in out["per_class"].values())
    assert all(e["settings"]["friction_ratio"] == 0.7 for e in out["per_class"].values())


def test_a_class_fits_every_setting_the_pooled_fit_fitted_and_its_file_carries_them(tmp_path, monkeypatch):
    """A class's own fit takes the pooled fit's settings in its order, as many as its training runs identify, from
    the pooled values: here the servo gain alone (Gazebo's slip2 stands the same way, its ratio fixed), which only
    ice's runs set lower; ice's entry carries its fitted gain with its interval, and its file and the per-class
    table read them."""
    params = _ratio_fixed(_mujoco_params(class_nfev=4, max_nfev=4))
    truth = {"friction_ratio": 0.7, "wheel_servo_kp": 1000.0}

    def simulate(s: dict) -> np.ndarray:
        return _generated_gains({**params["engine_settings"], **s}, 0.05)

    pooled = cal.Units(UNIT_RUNS, _generated_gains(truth, 0.05), [f"u{k}" for k in range(7)], simulate, {"g": 1})
    ice = cal.Units(
        ["ice/02", "ice/03"], _generated_gains({**truth, "wheel_servo_kp": 300.0}, 0.05)[2:4], ["i0", "i1"], None, {}
    )
    ice.simulate = lambda s: simulate(s)[2:4]

    def units(p, inputs, robot, runs, classes, turns):
        return ice if classes == ["ice"] else pooled

    monkeypatch.setattr(cal.job, "_units", units)
    split = tmp_path / "split.csv"
    cal.split_job({"segments": str(SEGMENTS)}, 0.5, 11, str(split))
    inputs = {"split": str(split), "segments": str(SEGMENTS), "urdf": str(ROOT / "resources/robot/husky_a200.urdf")}
    out = cal.calibrate(inputs, params, str(tmp_path / "mujoco.yaml"))
    e = out["per_class"]["ice"]
    assert out["settings"]["wheel_servo_kp"] == pytest.approx(1000.0, rel=0.1)
    assert e["fitted"] == ["wheel_servo_kp"] and e["improves"], e
    assert e["settings"]["wheel_servo_kp"] == pytest.approx(300.0, rel=0.15) and e["settings"]["friction_ratio"] == 0.7
    assert "wheel_servo_kp" in e["parameters"] and e["trials"][0]["settings"]["wheel_servo_kp"] == pytest.approx(
        out["settings"]["wheel_servo_kp"], rel=1e-3
    )
    assert set(settings_stage.class_files(out)) >= {"ice"}
    catalog = load_catalog(ROOT / "resources/simulators/simulators.yaml")
    tuned = catalog.settings("mujoco", "tuned", "husky_a200")
    files = settings_stage.calibrated_settings("mujoco", tuned, out)
    assert files["-ice"]["wheel_servo_kp"] == pytest.approx(e["settings"]["wheel_servo_kp"])
    row = classes_stage.per_class_table({"mujoco": out}, catalog).set_index("terrain_class").loc["ice"]
    assert f"wheel_servo_kp = {e['settings']['wheel_servo_kp']}" in row.class_settings


def test_the_drive_steps_replayed_are_stratified_by_their_turn_rate_each_with_its_real_gain():
    """Kind drive replays at most n training steps, stratified by how fast they turn: per unit its turning window of
    median |w| and the mean of its windows' real gains, the median unit of each of n bins by |w|."""
    turns = pd.DataFrame(
        {
            "terrain_class": ["ice", "ice", "ice", "flooring", "flooring", "snow"],
            "run": ["02", "02", "02", "01", "01", "04"],
            "gain": [0.6, 0.7, 0.8, 0.72, 0.70, 0.1],
            "v": [0.1, 0.2, 0.3, 0.0, 0.1, 0.0],
            "w": [0.2, -0.5, 0.3, 0.4, -0.1, 0.34],
        }
    )
    picked = cal.representative_units(turns, 6)
    by = {f"{r.terrain_class}/{r.run}": r for r in picked.itertuples()}
    assert sorted(by) == ["flooring/01", "ice/02", "snow/04"]
    assert (by["ice/02"].v, by["ice/02"].w) == (0.3, 0.3) and by["ice/02"].gain == pytest.approx(0.7)
    assert (by["flooring/01"].v, by["flooring/01"].w) == (0.0, 0.4) and by["flooring/01"].gain == pytest.approx(0.71)
    two = cal.representative_units(turns, 2)  # bins by |w|: [ice 0.3, snow 0.34] and [flooring 0.4]
    assert len(two) == 2 and set(two.run) == {"04", "01"}


def test_a_space_without_a_friction_ratio_fits_its_compliance_and_drive(tmp_path, monkeypatch):
    """Drake's space (no second friction direction: its wheels' hydroelastic modulus and PD damping) fitted on a
    generated robot whose gain falls with a softer tyre and a softer drive: the fit runs without a ratio, recovers
    both settings, says which setting its trials follow and places no Coulomb ratio; each part has its share."""
    plan = _plan(_config(run=["drake"]))
    params = dict(plan.simulator_calibrate_params("drake"), class_nfev=0, max_nfev=8)
    assert "friction_ratio" not in params["space"]["settings"] and "friction_ratio" not in params["engine_settings"]
    rates = TURN_RATES

    def gains(settings: dict) -> np.ndarray:
        soft = math.log10(1.0e8 / settings["hydroelastic_modulus"])  # 0 rigid .. 3 soft
        lag = math.log10(1.0e6 / settings["wheel_drive_damping"])  # 0 stiff .. 4 soft
        return 0.70 - 0.02 * soft * (1 + rates) - 0.01 * lag * rates

    truth = {"hydroelastic_modulus": 1.0e6, "wheel_drive_damping": 1.0e3}
    real = gains(truth)

    def simulate(settings: dict) -> np.ndarray:
        return gains({**params["engine_settings"], **settings})

    units = cal.Units(UNIT_RUNS, real, [f"u{k}" for k in range(len(real))], simulate, {"generated": True})
    monkeypatch.setattr(cal.job, "_units", lambda *args: units)
    split = tmp_path / "split.csv"
    cal.split_job({"segments": str(SEGMENTS)}, 0.5, 11, str(split))
    inputs = {"split": str(split), "segments": str(SEGMENTS), "urdf": str(ROOT / "resources/robot/husky_a200.urdf")}
    out = cal.calibrate(inputs, params, str(tmp_path / "drake.yaml"))
    f = out["fit"]
    assert f["kept"] == "the fit" and f["train_error"] < f["train_error_tuned"]
    assert set(out["settings"]) == set(truth) and "friction_ratio" not in out["exposed"]
    for name, value in truth.items():
        assert out["settings"][name] == pytest.approx(value, rel=0.1), (name, f["parameters"][name])
        assert f["parameters"][name]["identifiable"], name
    assert f["coulomb_ratio"] is None and f["bounds"] is None and f["trials_of"] == "wheel_drive_damping"
    assert f["trials"][0][0] == params["engine_settings"]["wheel_drive_damping"]
    assert f["parts"]["contact"]["settings"] == ["hydroelastic_modulus"]
    assert f["parts"]["actuator"]["settings"] == ["wheel_drive_damping"]
    assert out["per_class"] and all(e["placed_by"].startswith("the pooled fit") for e in out["per_class"].values())


def test_own_logs_the_verdict_rests_on_are_the_calibration_s_runs(tmp_path):
    """With accuracy.reference own, the calibrated profiles fit on the user's own logs as on a full replay's runs:
    the logs replayed (kind replay, each class's replay params), their steady turning windows (rule real_turning
    over source own) and a split of every own run by whether it turns; without it, the committed segments."""
    config = _config(run=["mujoco"])
    csv_log = tmp_path / "mine.csv"
    csv_log.write_text("t,ax,ay,az,wx,wy,wz,v,w\n0,0,0,9.81,0,0,0,0,0\n")
    mapping = {k: k for k in ("ax", "ay", "az", "wx", "wy", "wz", "v", "w")} | {"time": "t"}
    config["own_logs"] = [
        {"name": n, "terrain_class": c, "csv": str(csv_log), "mapping": mapping}
        for n, c in (("a", "flooring"), ("b", "flooring"), ("c", "flooring"), ("d", "ice"))
    ]
    assert _plan(config).calibration_source == "segments"  # own logs compared, the verdict on the segments
    config["accuracy"]["reference"] = "own"
    plan = _plan(config)
    assert plan.calibration_source == "own" and plan.calibrated == ["mujoco-calibrated"]
    inputs = plan.calibration_real_input()
    assert inputs["windows"] == "results/real/own/turning/windows.csv" and "calibration_split" not in inputs
    assert sorted(inputs["logs"]) == [
        f"results/real/own/logs/{c}/{n}.parquet"
        for n, c in (("a", "flooring"), ("b", "flooring"), ("c", "flooring"), ("d", "ice"))
    ]
    params = plan.simulator_calibrate_params("mujoco")
    assert params["kind"] == "replay" and params["source"] == "replay-own"
    assert params["replay_cases"]["flooring"]["terrain_class"] == "flooring"
    # the split: every own run a unit, stratified by whether its log has a steady turning window
    windows = tmp_path / "windows.csv"
    pd.DataFrame({"terrain_class": ["flooring", "flooring"], "run": ["a", "b"]}).to_csv(windows, index=False)
    logs = [
        str(tmp_path / "own" / c / f"{n}.parquet")
        for n, c in (("a", "flooring"), ("b", "flooring"), ("c", "flooring"), ("d", "ice"))
    ]
    split = tmp_path / "split.csv"
    cal.split_job({"windows": str(windows), "logs": logs}, 0.5, 11, str(split))
    table = pd.read_csv(split, dtype={"run": str})
    assert sorted(table.run) == ["a", "b", "c", "d"]
    sets = dict(zip(table.run, table.set))
    assert {sets["a"], sets["b"]} == {"train", "test"}  # the two turning runs, one each side
    assert sets["d"] == "train"  # a class of one run keeps it for training


def test_a_fitted_setting_is_written_to_four_significant_digits_not_four_decimals():
    """Webots' softCFM is fitted over 1e-6 to 1e-2: four decimals would write 2.3e-6 as 0, another contact."""
    from simpick.studies.simulator_calibration.fit import _r, _rs

    assert _rs(2.34567e-6) == 2.346e-6 and _r(2.34567e-6) == 0.0
    assert _rs(0.00123456) == 0.001235 and _rs(880123.4) == 880100.0 and _rs(0.69694) == 0.6969
    assert _rs(None) is None and _rs(float("nan")) is None


def test_a_class_file_is_told_apart_by_its_numbers_beside_a_required_choice():
    """A class's settings carry the search space's required ones, some of them words (Webots' friction_direction
    "wheel"): the class gets a file of its own where a number differs, and a word only where the word does."""
    from simpick.score.simulator_settings import class_files

    pooled = {"friction_direction": "wheel", "friction_ratio": 0.7, "contact_slip": 0.001}
    entry = {"engine_gain": 0.6, "improves": True}
    fit = {
        "searchable": True,
        "settings": pooled,
        "per_class": {
            "ice": {**entry, "settings": {**pooled, "friction_ratio": 0.5}},
            "flooring": {**entry, "settings": dict(pooled)},
            "snow": {**entry, "settings": {**pooled, "friction_direction": "wheel_x"}},
        },
    }
    assert sorted(class_files(fit)) == ["ice", "snow"]


def test_a_log_setting_of_many_decades_beside_a_ratio_gets_an_interval_that_holds_its_truth():
    """A contact stiffness over 1e5-1e11 (Gazebo Classic's <kp>) fitted beside a ratio: the covariance is taken over
    u, where both span [0, 1]; in the settings' own units J^T J is singular to machine precision and gave the
    stiffness a zero-width interval. The gains slope with both, differently per run."""
    space = {
        "friction_ratio": cal.SearchSetting(exposed_as="r", bounds=(0.3, 1.8), source="a.c:1"),
        "kp": cal.SearchSetting(exposed_as="k", bounds=(1.0e5, 1.0e11), source="a.c:2", log=True),
    }
    axes = [cal.Axis(k, v) for k, v in space.items()]
    weight = np.array([0.02, 0.05, 0.08, 0.03])

    def gains(settings):
        return 0.95 - 0.4 * settings["friction_ratio"] - weight * math.log10(settings["kp"] / 1.0e5)

    truth = {"friction_ratio": 0.6, "kp": 1.0e9}
    noise = np.array([0.004, -0.003, 0.002, -0.004])
    units = cal.Units(["a/1", "b/1", "c/1", "d/1"], gains(truth) + noise, list("abcd"), gains, {})
    fit = cal.least_squares_fit(units, axes, {}, {"friction_ratio": 1.0, "kp": 1.0e8}, 12, 0.05, 0.045, 0, "scipy")
    kp = fit["parameters"]["kp"]
    assert kp["identifiable"], kp
    low, high = kp["interval"]
    assert low < truth["kp"] < high and high / low > 1.01  # not a point
    assert fit["parameters"]["friction_ratio"]["interval"][0] < 0.6 < fit["parameters"]["friction_ratio"]["interval"][1]


def test_a_class_held_out_error_gets_its_interval_over_runs_only_from_min_runs_runs():
    """The per-class held-out error's interval is the table's: BCa over runs (each run's units averaged first), none
    below statistics.min_runs runs; a run with many units weighs as one run."""
    from simpick.compare.realmetrics import mean_ci
    from simpick.studies.simulator_calibration.fit import Units

    runs = [f"ice/{i:02d}" for i in range(7)] + ["ice/00"] * 3
    real = np.full(len(runs), 0.6)
    errors = np.array([0.01, 0.03, 0.02, 0.05, 0.04, 0.02, 0.03, 0.01, 0.01, 0.01])
    units = Units(runs, real, [f"u{i}" for i in range(len(runs))], lambda s: None, {})
    sims = real + errors
    low, high = units.error_interval(sims, 6, 0.95, 0)
    mean, want_low, want_high, n = mean_ci(np.abs(sims - real), np.asarray(runs, object), 6, 0.95, 0)
    assert n == 7 and units.error(sims) == pytest.approx(mean) and (low, high) == pytest.approx((want_low, want_high))
    assert low < mean < high
    assert all(math.isnan(x) for x in units.error_interval(sims, 8, 0.95, 0))  # 7 runs < 8
    assert all(math.isnan(x) for x in units.error_interval(np.full(len(runs), np.nan), 6, 0.95, 0))
