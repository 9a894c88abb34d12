"""Each converted rule's params are its job's typed model (simpick.params): the plan builds them from
the typed study and validates them against the model the job reads, so a field the two disagree on
stops the run at planning time, and a job reads typed fields, never string keys.

``CONVERTED`` lists each converted rule with its job's model and the params the plan gives it; every
entry is checked on the default study and on a robot study (the Warthog: a suspension, other engine
settings)."""

import copy

import pytest
from pydantic import ValidationError

from conftest import ROOT, study_config, tiny_config, write_dataset
from simpick.compare.kinds import SETTINGS as COMPARE_SETTINGS
from simpick.compare.settings import SummariseSettings
from simpick.config import Study
from simpick.plan import Plan, PlanError
from simpick.plan.jobs import job_params
from simpick.plan.sources import BATCHED
from simpick.real.jobs import ImportParams, SegmentsParams
from simpick.real.turning import TurningParams
from simpick.report import draw
from simpick.report import params as report_params
from simpick.report.weighing import WeighingParams
from simpick.score import simulator_settings as settings_stage
from simpick.score import simulators as simulators_stage
from simpick.score.answer import AnswerParams
from simpick.score.steps import CompareParams
from simpick.score.verdict.job import VerdictParams
from simpick.simulate.cpuload import CpuLoadParams
from simpick.simulate.lab import LabUnitParams
from simpick.simulate.real import RealUnitParams, SegmentsUnitParams
from simpick.simulate.steps import SessionReplayParams
from simpick.sources import module as source_module
from simpick.sources.base import canonical, model_settings
from simpick.studies import turnmap
from simpick.studies.calibration.settings import EvaluateSettings, SearchSettings
from simpick.studies.calibration.steps import StepCalibrateParams, StepSummaryParams
from simpick.studies.simulator_models import SimulatorModelsParams
from simpick.studies.sweep import SweepPointParams
from simpick.studies.validation import job as validation_job


def plan_of(config: dict) -> Plan:
    return Plan(config, Study.model_validate(config), basedir=str(ROOT))


def simulation_before_typing(config: dict, model: str) -> dict:
    """What every simulation on ``model`` was given before typing, from the plan's plain settings (the retired
    simpick.sources.base.engine_params): the params built from the typed study must keep this content."""
    return canonical(
        {
            "engine": model,
            "engine_settings": model_settings(config, model),
            "physics": config["physics"],
            "robot": {k: v for k, v in config["robot"].items() if k != "urdf"},
            "imu": config["imu"],
            "health": config["health"],
            "seed": config["seed"],
        }
    )


def real_units(kind: str):
    """A real-data kind's simulate params: the plan's (simulate_params) for each source of the kind it has, else,
    where it has none (no dataset folder, another robot than the committed segments'), its source module's for
    every real model and terrain class."""

    def params_of(plan: Plan) -> list[dict]:
        sources = [s for s in plan.sources if plan.sources[s]["kind"] == kind and plan.sources[s]["cases"]]
        if sources:
            units = []
            for s in sources:
                cases = plan.sources[s]["cases"]
                # a source batched whole is one unit per model (simpick.plan.sources.BATCHED), another's one case
                if BATCHED.get(s) == "source":
                    units.append((s, None, [n for _, n in cases]))
                else:
                    units += [(s, g, [n]) for g, n in dict(cases).items()]  # a case of each group
            return [plan.simulate_params(s, m, g, names) for s, g, names in units for m in plan.sources[s]["models"]]
        module = source_module(kind)
        return [
            module.case_params(plan.settings, kind, {}, m, plan.model_settings(m), c, ["a-case"])
            for m in plan.real_models
            for c in plan.settings.real_data.classes
        ]

    return params_of


def compare_settings_of(kind: str):
    """Rule compare's settings for each source of a driven kind in the plan, else the kind's source module's."""

    def params_of(plan: Plan) -> list[dict]:
        found = [plan.compare_params(s) for s in plan.sources if plan.source_of(s).DRIVEN == kind]
        return found or [canonical(source_module(kind).compare_settings(plan.settings))]

    return params_of


# rule -> (the job's model, the params of each of its jobs in a plan)
CONVERTED = {
    "turnmap_grid": (turnmap.TurnmapGridParams, lambda plan: [plan.turnmap_params()]),
    "turnmap_engine": (turnmap.TurnmapEngineParams, lambda plan: [plan.turnmap_params(e) for e in plan.engines]),
    "validate": (validation_job.ValidateParams, lambda plan: [plan.validation_params(m) for m in plan.validated]),
    "cpu_load": (CpuLoadParams, lambda plan: [plan.cpu_load_params(e) for e in plan.engines]),
    "sweep_segments": (
        SweepPointParams,
        lambda plan: [
            plan.sweep_params(e, c, dt) for e in plan.engines for c in plan.segments for dt in plan.sweep_labels
        ],
    ),
    "simulators": (simulators_stage.SimulatorsParams, lambda plan: [plan.simulators_params()]),
    "simulator_settings": (settings_stage.SimulatorSettingsParams, lambda plan: [plan.simulator_settings_params()]),
    "simulator_models": (SimulatorModelsParams, lambda plan: [plan.simulator_models_params()]),
    # the report job's weighing (simpick.report.weighing): its simulators' and answer's parts below
    "report (weighing)": (WeighingParams, lambda plan: [plan.weighing_params()]),
    "report (weighing: simulators)": (
        simulators_stage.SimulatorScoresParams,
        lambda plan: [plan.simulator_scores_params()],
    ),
    "simulator_tree": (simulators_stage.SimulatorTreeParams, lambda plan: [plan.simulator_tree_params()]),
    "calibrate": (SearchSettings, lambda plan: [plan.calibration_settings(m) for m in plan.cal_models]),
    "calibration_evaluate": (
        EvaluateSettings,
        lambda plan: [plan.calibration_settings(m, search=False) for m in plan.cal_models],
    ),
    "real_turning": (TurningParams, lambda plan: [plan.real_turning_params()]),
    # rules/drive.smk still builds these two inline (test below: the same content)
    "drive_calibration": (StepSummaryParams, lambda plan: [plan.drive_calibration_params()]),
    "drive_calibrate": (
        StepCalibrateParams,
        lambda plan: [plan.drive_calibrate_params(m, c) for m in plan.engines for c in plan.settings.real_data.classes],
    ),
    # --- the verdict, the answer and DRIVE's step verdict ---
    "verdict": (VerdictParams, lambda plan: [plan.verdict_settings()] if plan.verdict else []),
    "report (weighing: answer)": (AnswerParams, lambda plan: [plan.answer_settings()] if plan.answer_source else []),
    # the rule exists where drive_dir is set; its params do not depend on the folder: the study's engines
    "drive_compare": (CompareParams, lambda plan: [plan.drive_compare_params(plan.engines)]),
    # --- the report: its figures, its evidence and the report itself ---
    **{
        rule: (model, lambda plan, rule=rule: [plan.figure_params(rule)])
        for rule, (_, _, _, model) in draw.RULES.items()
    },
    "report_evidence": (report_params.EvidenceParams, lambda plan: [plan.evidence_params()]),
    # with what rule report adds from its inputs (the DRIVE tables' and simulators' folders; here: none)
    "report": (
        report_params.ReportParams,
        lambda plan: [canonical(plan.report_params() | {"drive": "", "drive_calibration": "", "simulators": ""})],
    ),
    # the lab's simulate jobs, a terrain's motions on one engine (their params: simpick.sources.lab.case_params)
    "simulate (lab)": (
        LabUnitParams,
        lambda plan: [
            plan.simulate_params("lab", e, t, list(plan.motions)) for e in plan.engines for t in plan.terrains
        ],
    ),
    # the real-data simulate jobs (simpick.simulate.jobs.PARAMS), DRIVE's replay, the comparisons and summaries
    "simulate (segments)": (SegmentsUnitParams, real_units("segments")),
    "simulate (replay)": (RealUnitParams, real_units("replay")),
    "drive_replay": (
        SessionReplayParams,
        lambda plan: [plan.drive_replay_params(m, "a-session") for m in plan.real_models],
    ),
    "compare (lab)": (COMPARE_SETTINGS["lab"], compare_settings_of("lab")),
    "compare (segments)": (COMPARE_SETTINGS["segments"], compare_settings_of("segments")),
    "compare (replay)": (COMPARE_SETTINGS["replay"], compare_settings_of("replay")),
    "summarise": (SummariseSettings, lambda plan: [plan.summarise_params(s) for s in plan.sources]),
}


@pytest.fixture(scope="module")
def default_plan(tmp_path_factory):
    config = tiny_config(tmp_path_factory.mktemp("default"))
    config["sweep"] = {"name": "steps", "timesteps": [0.0005, 0.002]}  # the sweep's jobs exist
    return plan_of(config)


@pytest.fixture(scope="module")
def robot_plan():
    config = study_config("config/robots/warthog.yaml")
    for key in ("urdf",):
        config["robot"][key] = str(ROOT / config["robot"][key])
    return plan_of(config)


@pytest.mark.parametrize("rule", sorted(CONVERTED))
@pytest.mark.parametrize("which", ["default_plan", "robot_plan"])
def test_each_converted_rule_s_params_validate_against_its_job_s_model(rule, which, request):
    plan = request.getfixturevalue(which)
    model, params_of = CONVERTED[rule]
    all_params = params_of(plan)
    # the sweep runs the committed segments, which a study of another robot than theirs refuses
    no_jobs = {("robot_plan", "sweep_segments")}
    # the Warthog's study has no real data of its robot: no verdict, no answer
    no_jobs |= {("robot_plan", "verdict"), ("robot_plan", "report (weighing: answer)")}
    assert bool(all_params) != ((which, rule) in no_jobs), f"{rule}: jobs in this plan: {len(all_params)}"
    for params in all_params:
        # plain builtins, canonical: what Snakemake fingerprints by repr (the simulate family's params are
        # the source modules', whose unit keys follow the case's: equal, in another order)
        assert params == canonical(params)
        if not rule.startswith("simulate"):
            assert repr(params) == repr(canonical(params))
        typed = model.model_validate(params)
        # nothing is lost or added on the way through the model
        assert canonical(typed.model_dump(mode="json", by_alias=True)) == params


def test_the_robot_study_s_params_carry_its_own_robot(default_plan, robot_plan):
    husky, warthog = (p.turnmap_params("mujoco") for p in (default_plan, robot_plan))
    assert warthog["robot"]["track"] == 1.08 and husky["robot"]["track"] != 1.08
    assert warthog["robot"]["label"] == "Clearpath Warthog" and "urdf" not in warthog["robot"]
    assert warthog["engine_settings"] != husky["engine_settings"]


def test_a_field_the_plan_and_the_job_disagree_on_stops_the_planning_naming_rule_and_key(default_plan):
    data = copy.deepcopy(default_plan.turnmap_params("mujoco"))
    data["physics"] = {"time_step": data["physics"]["timestep"]}  # a renamed field
    with pytest.raises(PlanError, match=r"rule turnmap_engine: .*TurnmapEngineParams.*physics\.timestep"):
        job_params("turnmap_engine", turnmap.TurnmapEngineParams, data)


def test_a_job_refuses_params_missing_a_field_it_reads_naming_the_key(default_plan, tmp_path):
    params = copy.deepcopy(default_plan.turnmap_params())
    del params["robot"]["track"]
    with pytest.raises(ValidationError, match=r"robot\.track"):
        turnmap.grid_job(tmp_path / "steps.csv", ROOT / "resources/robot/husky_a200.urdf", params, tmp_path / "out.csv")


def test_the_job_models_are_frozen(default_plan):
    typed = turnmap.TurnmapEngineParams.model_validate(default_plan.turnmap_params("mujoco"))
    with pytest.raises(ValidationError):
        typed.robot.track = 1.0  # type: ignore[misc]


def test_the_turnmap_params_hold_only_what_its_jobs_read(tmp_path):
    """Editing the IMU, the health limits, the validation's cases or a terrain class's source reruns no
    turn-map job; one engine's settings rerun that engine's job only."""
    config = tiny_config(tmp_path)
    before = plan_of(config)
    edited = copy.deepcopy(config)
    edited["imu"]["accel_noise_std"] = 0.5
    edited["health"]["timeout"] = 999.0
    edited["validation"]["cases"]["rest_mu0.8"]["mu"] = 0.5
    edited["real_data"]["classes"]["ice"]["source"] = "another handbook"
    edited["engines"]["mujoco"] = dict(edited["engines"]["mujoco"] or {}, solver_iterations=77)
    after = plan_of(edited)
    assert after.turnmap_params() == before.turnmap_params()
    for engine in before.engines:
        same = after.turnmap_params(engine) == before.turnmap_params(engine)
        assert same == (engine != "mujoco"), engine


def test_the_cpu_load_params_are_what_they_were_before_typing(default_plan):
    """Their content is the plain slices' as before (only the job's code changed): no spurious rerun."""
    cpu = default_plan.config["cpu_load"]
    for engine in default_plan.engines:
        before = default_plan.simulation_params(engine, cpu["terrain"], cpu["motion"]) | {"cpu_load": canonical(cpu)}
        assert default_plan.cpu_load_params(engine) == before


def test_the_sweep_params_are_the_segments_unit_s_at_the_sweep_step(default_plan):
    """As before typing: the segments source's params, the timestep replaced (no spurious rerun)."""
    for terrain_class, segments in default_plan.segments.items():
        unit = default_plan.case_params("segments", "mujoco", terrain_class, segments)
        before = canonical(unit | {"physics": unit["physics"] | {"timestep": 0.0005}})
        assert default_plan.sweep_params("mujoco", terrain_class, "0.5ms") == before


@pytest.fixture(scope="module")
def replay_plan(tmp_path_factory):
    """A study with a dataset folder (borealtc_dir): its import and segments jobs exist."""
    workdir = tmp_path_factory.mktemp("replay")
    folder = write_dataset(workdir / "yard", {"FLOORING": ["7"]}, seconds=2.0, imu_hz=50.0, cmd_hz=15.0)
    config = tiny_config(workdir)
    config["real_data"]["datasets"]["yard"] = {"label": "Husky yard", "imu_hz": 50, "commands_hz": 15}
    config["borealtc_dir"] = str(folder)
    return plan_of(config)


def test_the_dataset_folder_s_job_params_validate_and_equal_what_rules_real_smk_builds(replay_plan):
    """rules/real.smk builds these params inline today; the plan's typed ones validate against the jobs' models
    and hold the same values (the declared rates each stated, None where not declared), so passing them
    instead reruns only what the jobs' code change reruns."""
    plan = replay_plan
    segments = plan.real_segments_params()
    SegmentsParams.model_validate(segments)
    inline = canonical(
        {
            "segment_rules": plan.config["real_data"]["segment_rules"],
            "track": plan.config["robot"]["track"],
            "source": plan.replay_dataset()["source"],
        }
    )
    assert segments == inline
    settings = plan.import_real_params()
    typed = ImportParams.model_validate(settings)
    assert (typed.declared.imu_hz, typed.declared.commands_hz, typed.label) == (50.0, 15.0, "Husky yard")
    inline = canonical(
        {
            "track": plan.config["robot"]["track"],
            "dataset": plan.replay_set.name,
            "label": plan.replay_dataset()["label"],
            "declared": plan.replay_dataset()["declared"],
        }
    )
    assert settings == inline
    # the inline form, with an undeclared rate left out, validates too (the job reads None)
    no_rates = dict(inline, declared={})
    assert ImportParams.model_validate(no_rates).declared.imu_hz is None


def test_a_replayed_run_s_calibration_settings_carry_its_turning_windows(replay_plan):
    settings = EvaluateSettings.model_validate(replay_plan.calibration_settings(None, search=False))
    rules = replay_plan.settings.real_data.segment_rules
    assert settings.source == "replay" and settings.segment_seconds is None
    assert (settings.steady.tolerance, settings.steady.min_turn) == (rules.tolerance, rules.min_turn)


def test_an_infinite_setting_reaches_the_job_as_infinity_not_null():
    """Webots leaves ODE's correcting velocity at ODE's infinity (the catalog's ``.inf``); the plan's typed
    dump must hand the job that infinity, not JSON's null, which the engine's settings model refuses."""
    from simpick.studies.validation.job import ValidateParams

    config = study_config()
    config["robot"]["urdf"] = str(ROOT / config["robot"]["urdf"])
    plan = plan_of(config)
    assert "webots-shipped" in plan.profiles  # the default study runs Webots as shipped
    params = plan.validation_params("webots-shipped")
    assert params["engine_settings"]["contact_max_correcting_vel"] == float("inf")
    assert ValidateParams.model_validate(params).engine_settings["contact_max_correcting_vel"] == float("inf")


def test_the_real_turning_params_are_what_rules_real_smk_built_inline(replay_plan):
    """As before typing (the rule built them inline from the plain settings): no spurious rerun."""
    plan = replay_plan
    inline = canonical(
        {
            "track": plan.config["robot"]["track"],
            "window": 1.0,
            "settle": 0.5,
            "tolerance": plan.config["real_data"]["segment_rules"]["tolerance"],
            "min_turn": plan.config["real_data"]["segment_rules"]["min_turn"],
        }
    )
    assert plan.real_turning_params() == inline


def test_the_step_calibration_params_equal_what_rules_drive_smk_built(default_plan, robot_plan):
    """rules/drive.smk built drive_calibrate's params inline from the plain settings; the plan's typed ones, which
    it passes now, validate against the job's model and hold the same content (no calibration searched again)."""
    for plan in (default_plan, robot_plan):
        config = plan.config
        for model in plan.real_models:
            for terrain in config["real_data"]["classes"]:
                inline = canonical(
                    {
                        "engine": model,
                        "terrain_class": terrain,
                        "case": simulation_before_typing(config, model),
                        "classes": config["real_data"]["classes"],
                        "replay": config["drive_replay"],
                        "calibration": {
                            "source": "drive",
                            "scales": config["calibration"]["scales"],
                            "test_fraction": config["calibration"]["test_fraction"],
                            "n_trials": config["calibration"]["n_trials"],
                            "startup_trials": config["calibration"]["startup_trials"],
                            "seed": config["calibration"]["seed"],
                            "bounds": {model: (config["calibration"].get("bounds") or {}).get(model) or {}},
                        },
                    }
                )
                assert plan.drive_calibrate_params(model, terrain) == inline
        assert plan.drive_calibration_params() == canonical({"statistics": config["statistics"]})


def test_the_job_models_below_the_config_agree_with_its_sections():
    """The step replay's and the split's fields are defined below the config for the jobs (simpick.real.settings,
    simpick.studies.calibration.settings) beside the config's own sections, which do not yet reuse them: the
    same fields, defaults and constraints."""
    from simpick.config.real import DriveReplay
    from simpick.config.studies import Calibration
    from simpick.real.settings import StepReplay
    from simpick.studies.calibration.settings import CalibrationSplit

    def shape(field):
        return (repr(field.annotation), field.default, repr(field.metadata), field.description)

    assert issubclass(DriveReplay, StepReplay) and set(DriveReplay.model_fields) == set(StepReplay.model_fields)
    assert shape(Calibration.model_fields["test_fraction"]) == shape(CalibrationSplit.model_fields["test_fraction"])


def test_the_split_s_strata_validate_and_are_what_they_were_before_typing(replay_plan):
    from simpick.studies.calibration.split import SplitStrata

    plan = replay_plan
    strata = plan.calibration_strata()
    rules = plan.config["real_data"]["segment_rules"]
    before = canonical(
        {
            "track": plan.config["robot"]["track"],
            "steady": {"tolerance": rules["tolerance"], "min_turn": rules["min_turn"]},
            "duration": plan.config["calibration"]["replay_seconds"],
        }
    )
    assert strata == before and SplitStrata.model_validate(strata).duration == before["duration"]


def test_the_verdict_answer_and_drive_compare_params_keep_their_content(default_plan, tmp_path):
    """Built from the typed study, they hold what the plain slices gave (the answer's basis gains its noun,
    None where the sentences say "real runs"); DRIVE's comparison's are what simpick.sources.drive gave."""
    from simpick.real.steps import SIMILAR

    plan = default_plan
    old_verdict = {
        "engines": sorted(plan.engines),
        "baselines": sorted(plan.baselines),
        "statistics": plan.statistics_params(),
        "seed": plan.config["seed"],
        "accuracy_set": plan.accuracy_source()["set"],
        "verdict": plan.config["verdict"],
    }
    assert plan.verdict_settings() == canonical(old_verdict)
    answer = plan.answer_settings()
    assert answer["weights"] == canonical(plan.config["weights"]) and answer["basis"]["noun"] is None
    engines = ["mujoco", "ode"]
    config = plan.config
    old_drive = {  # what simpick.sources.drive.compare_settings gave from the plain settings
        "verdict": config["verdict"],
        "statistics": config["statistics"],
        "unit": config["drive_replay"]["unit"],
        "tolerance": SIMILAR,
        "seed": config["seed"],
    }
    assert source_module("drive").compare_settings(plan.settings) == canonical(old_drive)
    assert plan.drive_compare_params(engines) == canonical(old_drive | {"engines": engines})


def test_only_the_answer_s_params_hold_the_weights(default_plan):
    """The rerun contract: a weight edit reruns the answer, not the verdict nor DRIVE's comparison."""
    assert "weights" in default_plan.answer_settings()
    assert "weights" not in default_plan.verdict_settings()
    assert "weights" not in default_plan.drive_compare_params(default_plan.engines)


def test_only_the_report_s_params_hold_the_weights_of_the_report_s_jobs(default_plan):
    """The rerun contract: a weight edit reruns the report, neither a figure nor the evidence."""
    assert default_plan.report_params()["weights"] == canonical(default_plan.config["weights"])
    assert "weights" not in default_plan.evidence_params()
    for rule in draw.RULES:
        assert "weights" not in default_plan.figure_params(rule), rule


def test_the_benchmark_s_page_params_validate_against_its_job_s_model():
    """Rule robots (rules/robots.smk) is given simpick.config.robots.robots_params: each robot's name, label,
    command, settings and files, and the pooling, as rule robots' job reads them."""
    import yaml

    from simpick.config.robots import benchmark, robots_params
    from simpick.report.robots import RobotsParams

    robots, pooling = benchmark(yaml.safe_load((ROOT / "config/robots.yaml").read_text()), ROOT)
    params = robots_params(robots, pooling)
    typed = RobotsParams.model_validate(params)
    assert [r.name for r in typed.robots] == list(robots) and typed.pooling.min_robots == pooling["min_robots"]
    assert typed.model_dump(mode="json") == params


# --- the simulate, compare and summarise families and DRIVE's replay: typed, their params unchanged ---


def test_the_real_data_simulate_params_are_what_they_were_before_typing(default_plan, replay_plan):
    """A replay unit's params, validated at planning, are passed exactly as before typing (the same content in the
    same key order: their repr is what Snakemake fingerprints), so no trace is simulated again."""
    plan, source = replay_plan, "yard"
    config = plan.config
    group, name = plan.sources[source]["cases"][0]
    for model in plan.sources[source]["models"]:
        before = simulation_before_typing(config, model) | canonical(
            {"terrain_class": group, "class": config["real_data"]["classes"][group]}
        )
        before |= {"kind": plan.sources[source]["kind"], "source": source, "cases": [name]}
        params = plan.simulate_params(source, model, group, [name])
        assert repr(params) == repr(before), (source, model)
        RealUnitParams.model_validate(params)


def test_a_segment_reads_what_its_class_s_job_read(default_plan, replay_plan):
    """The committed segments run in one job per model (its unit holds every class's ground); what each segment
    reads, its class's case params, is what a job of its class read (the plan's real_params): the same simulation.
    A derived table's segment, one job each, holds its own class's ground only."""
    cases = default_plan.sources["segments"]["cases"]
    names = [name for _, name in cases]
    for model in default_plan.sources["segments"]["models"]:
        unit = SegmentsUnitParams.model_validate(default_plan.simulate_params("segments", model, None, names))
        assert unit.cases == names and list(unit.classes) == list(dict.fromkeys(c for c, _ in cases))
        for terrain_class in unit.classes:
            case = unit.case(terrain_class).model_dump(mode="json", by_alias=True)
            assert canonical(case) == default_plan.real_params(model, terrain_class), (model, terrain_class)
    spec = {"cases": None}
    params = source_module("segments").case_params(
        replay_plan.settings, "yard-segments", spec, "mujoco", replay_plan.model_settings("mujoco"), "flooring", ["a"]
    )
    assert list(SegmentsUnitParams.model_validate(params).classes) == ["flooring"]


def test_the_drive_replay_params_are_what_they_were_before_typing(default_plan, robot_plan):
    """Built from the typed study, they equal, repr and all, what rules/drive.smk passed before (the DRIVE
    source module's case_params from the plain settings), as does the typed source module's: no session is
    replayed again."""
    drive = source_module("drive")
    for plan in (default_plan, robot_plan):
        config = plan.config
        for model in plan.real_models:
            before = canonical(
                simulation_before_typing(config, model)
                | {"classes": config["real_data"]["classes"], "replay": config["drive_replay"], "session": "a-session"}
            )
            assert repr(plan.drive_replay_params(model, "a-session")) == repr(before), model
            typed = drive.case_params(plan.settings, "drive", {}, model, plan.model_settings(model), "a-session", [])
            assert repr(typed) == repr(before), model
            SessionReplayParams.model_validate(typed)


def test_the_compare_and_summarise_settings_are_what_they_were_before_typing(default_plan, replay_plan):
    for plan in (default_plan, replay_plan):
        for source in plan.sources:
            assert repr(plan.compare_params(source)) == repr(plan.compare_settings(source)), source
            assert repr(plan.summarise_params(source)) == repr(plan.summarise_settings(source)), source


def test_a_replay_s_noise_seed_is_the_plain_params_one(replay_plan):
    """The jobs hashed the params' seed as the plan gives it (a float) into a replay's noise seed; read typed
    (an int), it is hashed as that float still, so a replayed trace's noise is unchanged."""
    from simpick.seeds import stable_seed
    from simpick.simulate.real import noise_seed_of

    group, name = replay_plan.sources["yard"]["cases"][0]
    params = replay_plan.simulate_params("yard", "mujoco", group, [name])
    typed = RealUnitParams.model_validate(params)
    assert isinstance(typed.seed, int) and isinstance(params["seed"], float)
    assert noise_seed_of(typed, "mujoco", name) == stable_seed(params["seed"], "mujoco", name)


def test_a_unit_s_params_the_plan_and_its_kind_s_model_disagree_on_stop_the_planning(default_plan, monkeypatch):
    names = [name for _, name in default_plan.sources["segments"]["cases"]]
    good = default_plan.case_params("segments", "mujoco", None, names)
    monkeypatch.setattr(type(default_plan), "case_params", lambda *args: {k: v for k, v in good.items() if k != "seed"})
    with pytest.raises(PlanError, match=r"simulate \(segments\): .*SegmentsUnitParams.*seed"):
        default_plan.simulate_params("segments", "mujoco", None, names)


def test_a_dataset_folder_s_runs_are_simulated_a_job_per_model_and_terrain_class(tmp_path):
    """A replayed folder's runs share a process per model and class (plan.sources.BATCHED_KINDS): a rule per
    class whose outputs are that class's runs, its inputs their logs in the same order, its params the class's
    ground; a job's prepare step replays each run from its own log, whatever the order."""
    from simpick.plan.sources import BATCHED_KINDS
    from simpick.simulate.real import prepare_replay

    folder = write_dataset(tmp_path / "yard", {"FLOORING": ["7", "12"], "ICE": ["3"]}, seconds=2.0)
    config = tiny_config(tmp_path)
    config["real_data"]["datasets"]["yard"] = {"label": "Husky yard", "imu_hz": 100, "commands_hz": 6.5}
    config["borealtc_dir"] = str(folder)
    plan = plan_of(config)
    assert BATCHED_KINDS["replay"] == "class" and plan.batching("yard") == "class"
    units = {name: (outputs, fixed) for name, outputs, _, fixed in plan.simulate_units()}
    assert not [f for _, f in units.values() if "sources" in f and "yard" in f["sources"]]  # no one-case jobs
    outputs, fixed = units["simulate_yard_flooring"]
    assert outputs == [
        "results/traces/yard/{engine}/flooring/7.parquet",
        "results/traces/yard/{engine}/flooring/12.parquet",
    ]
    assert units["simulate_yard_ice"][0] == ["results/traces/yard/{engine}/ice/3.parquet"]

    class Wildcards:
        engine = "mujoco"

    source, engine, group, names = plan.unit(Wildcards, fixed)
    assert (source, engine, group, names) == ("yard", "mujoco", "flooring", ["7", "12"])
    inputs = plan.case_inputs(source, group, names)
    assert inputs["logs"] == ["results/real/yard/logs/flooring/7.parquet", "results/real/yard/logs/flooring/12.parquet"]
    params = plan.simulate_params(source, engine, group, names)
    assert RealUnitParams.model_validate(params).terrain_class == "flooring"

    # the prepare step reads each case's own log: two canonical logs told apart by their run ids
    from simpick.real.logs import borealtc, write_canonical

    logs = []
    for run in names:
        log = borealtc.read_run(
            folder / "FLOORING" / f"imu_{run}.csv", folder / "FLOORING" / f"pro_{run}.csv", "flooring"
        )
        path = tmp_path / f"{run}.parquet"
        write_canonical(log, path)
        logs.append(str(path))
    for name in reversed(names):
        which, _ = prepare_replay(str(ROOT / config["robot"]["urdf"]), {"logs": logs}, params, name)
        assert which["run"] == name and which["test"] == f"flooring-{name}"
