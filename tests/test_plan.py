"""The plan (simpick.plan): built from the validated config, it hands the rules
typed settings with every default filled in by its model, and the rules read nothing else."""

import copy
import re

import pytest
import yaml

from conftest import ROOT, tiny_config
from simpick.config import Study, plain
from simpick.engines import get_engine
from simpick.inputs.terrain import TILES
from simpick.plan import Plan
from simpick.studies.validation.measures import DEFAULT_HEADING


def plan_of(config: dict) -> Plan:
    return Plan(config, Study.model_validate(config), basedir=str(ROOT))


@pytest.fixture
def config(tmp_path):
    return tiny_config(tmp_path)


def test_a_default_left_out_of_the_config_reaches_the_jobs_from_its_model(config):
    for spec in config["terrains"].values():
        spec.pop("tiles", None)
    config["validation"]["cases"]["gain_v0.5_w0.5_mu0.8"].pop("heading", None)
    config["engines"]["ode"] = None  # an empty entry: the adapter's defaults
    plan = plan_of(config)

    assert {t: s["tiles"] for t, s in plan.config["terrains"].items()} == {"grass": TILES, "bumps": TILES}
    case = plan.validation_params("ode")["cases"]["gain_v0.5_w0.5_mu0.8"]
    assert case["heading"] == DEFAULT_HEADING
    params = plan.simulation_params("ode", "grass", "straight")
    defaults = get_engine("ode").settings_model().model_dump(mode="json")
    assert set(params["engine_settings"]) == set(defaults) and defaults  # every setting, from the adapter's model
    assert params["engine_settings"]["erp"] == pytest.approx(defaults["erp"])


def test_a_setting_written_as_a_string_reaches_the_job_as_its_type(config):
    # YAML 1.1 reads 5.0e3 as a string; the raw dict handed it on as one, the validated settings as a number
    config["engines"]["pybullet"] = yaml.safe_load("contact_damping: 5.0e3")
    assert config["engines"]["pybullet"]["contact_damping"] == "5.0e3"
    params = plan_of(config).simulation_params("pybullet", "grass", "straight")
    assert params["engine_settings"]["contact_damping"] == 5000.0


def test_the_engines_keep_the_config_order_and_only_the_configured_ones(config):
    config["engines"] = {"mujoco": None, "ode": {}, "pybullet": None}
    config["baselines"] = {"coulomb": None}
    plan = plan_of(config)
    assert plan.engines == ["mujoco", "ode", "pybullet"]
    assert plan.baselines == ["coulomb"]
    assert list(plain(Study.model_validate(config), config)["engines"]) == ["mujoco", "ode", "pybullet"]
    assert plan.sources["lab"]["models"] == ["mujoco", "ode", "pybullet"]
    assert plan.sources["segments"]["models"] == ["mujoco", "ode", "pybullet", "coulomb"]


def test_the_plan_does_not_change_the_config_it_was_given(config):
    before = copy.deepcopy(config)
    plan_of(config)
    assert config == before


def test_the_rules_read_the_validated_settings_not_the_raw_config():
    """Every `config[...]` / `config.get(...)` in the rules goes through the plan (PLAN.config)."""
    raw = []
    for path in [ROOT / "Snakefile", *sorted((ROOT / "rules").glob("*.smk"))]:
        for number, line in enumerate(path.read_text().splitlines(), 1):
            if re.search(r"(?<![.\w])config(\[|\.get\()", line):
                raw.append(f"{path.name}:{number}: {line.strip()}")
    assert not raw, "rules reading the raw config (use PLAN.config):\n" + "\n".join(raw)


def _cost_table(path, rows):
    from simpick.plan import costs

    costs.write([{"job": j, "engine": e, "wall_s": s, "jobs": 1} for j, e, s in rows], path, "measured in a test")


def test_the_longest_measured_jobs_get_the_highest_priority(config, tmp_path):
    from simpick.plan import costs

    _cost_table(
        tmp_path / "costs.csv", [("validate", "dart", 71.7), ("validate", "mujoco", 4.8), ("lab", "dart", 10.4)]
    )
    plan = plan_of(config)
    plan.costs = costs.load(tmp_path / "costs.csv")
    assert plan.job_priority("validate", "dart") == 72 > plan.job_priority("validate", "mujoco") == 5
    # a simulate job's: the measured cost of a case times its cases
    assert plan.simulate_priority("lab", "dart", 1) == 10 and plan.simulate_priority("lab", "dart", 2) == 21
    # not measured: no priority, nothing invented
    assert plan.job_priority("cpu_load", "dart") == 0 and plan.simulate_priority("segments", "dart", 4) == 0


def test_a_cost_measured_over_several_cases_is_a_case_s_times_the_job_s_cases(config, tmp_path):
    from simpick.plan import costs

    rows = [{"job": "segments", "engine": "dart", "wall_s": 13.4, "jobs": 5, "cases": 4}]
    costs.write(rows, tmp_path / "costs.csv", "measured in a test")
    plan = plan_of(config)
    plan.costs = costs.load(tmp_path / "costs.csv")
    assert plan.costs[("segments", "dart")] == pytest.approx(13.4 / 4)
    assert plan.simulate_priority("segments", "dart", 18) == round(18 * 13.4 / 4)


def test_the_committed_cost_table_measures_every_registered_engine():
    from simpick.engines import ADAPTERS
    from simpick.plan import costs
    from simpick.plan.scheduling import COST_TABLE

    table = costs.load(ROOT / COST_TABLE)
    for engine in ADAPTERS:
        for job in ("validate", "cpu_load", "lab", "segments"):
            assert table.get((job, engine), 0) > 0, (job, engine)


def test_the_cost_table_is_measured_from_a_study_s_benchmark_files(tmp_path):
    from simpick.plan import costs

    header = "s\th:m:s\tmax_rss\tmax_vms\tmax_uss\tmax_pss\tio_in\tio_out\tmean_load\tcpu_time\n"
    benchmarks = tmp_path / "benchmarks"
    for path, seconds in [
        ("validate/dart.tsv", 70.0),
        ("simulate/lab/dart/grass.tsv", 9.0),  # a terrain's motions in one job
        ("simulate/lab/dart/bumps.tsv", 13.0),
        ("simulate/lab/dart/gravel.tsv", 11.0),
        ("simulate/segments/coulomb.tsv", 1.5),  # every segment of a model in one job
        ("drive/drive/replay/dart/warthog_wheels_asphalt.tsv", 1200.0),  # a DRIVE folder's replay
        ("drive/drive/replay/dart/warthog_wheels_grass_2024_7_29_14h46s15.tsv", 230.0),
        ("drive/drive/replay/dart/warthog_wheels_gravel_2024_8_6_11h37s32.tsv", 1250.0),
    ]:
        (benchmarks / path).parent.mkdir(parents=True, exist_ok=True)
        (benchmarks / path).write_text(header + f"{seconds}\t0:00:00\t1\t1\t1\t1\t0\t0\t90\t{seconds}\n")
    # the jobs' traces, beside the benchmarks: how many cases each ran
    for trace in ["lab/dart/grass/straight", "lab/dart/grass/circle", "lab/dart/bumps/straight"]:
        (tmp_path / "traces" / f"{trace}.parquet").parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / "traces" / f"{trace}.parquet").write_bytes(b"")
    for cls, segment in [("ice", "a"), ("ice", "b"), ("snow", "c")]:
        (tmp_path / "traces/segments/coulomb" / cls).mkdir(parents=True, exist_ok=True)
        (tmp_path / "traces/segments/coulomb" / cls / f"{segment}.parquet").write_bytes(b"")
    rows = {(r["job"], r["engine"]): (r["wall_s"], r["jobs"], r["cases"]) for r in costs.measure(benchmarks)}
    assert rows == {
        ("validate", "dart"): (70.0, 1, 1),
        ("lab", "dart"): (11.0, 3, 1),  # 2, 1 and (no traces: unknown) 1 cases
        ("segments", "coulomb"): (1.5, 1, 3),
        ("drive_replay", "dart"): (1200.0, 3, 1),
    }


def test_the_default_study_names_the_opt_in_engines_with_their_switch_and_measured_cost(config):
    plan = plan_of(config)  # the default study's six engines
    assert set(plan.opt_in) == {"newton", "genesis"}
    for entry in plan.opt_in.values():
        assert "--configfile config.yaml config/engines/newton_genesis.yaml" in entry["switch"]
        assert "make study-eight" in entry["switch"]
        assert entry["seconds"] > 0 and entry["study_seconds"] > 0
    # the eight-engine study names none
    config["engines"] |= yaml.safe_load((ROOT / "config/engines/newton_genesis.yaml").read_text())["engines"]
    assert plan_of(config).opt_in == {}


def test_an_engine_whose_venv_failed_to_build_is_left_out_with_pip_s_error(config, tmp_path, monkeypatch):
    monkeypatch.setenv("SIMPICK_ENGINE_VENVS", str(tmp_path))  # no venv here
    monkeypatch.setattr("simpick.engines.isolated.in_process", lambda engine: False)
    (tmp_path / ".venv-genesis.failed").write_text("ERROR: No matching distribution found for torch==2.13.0\n")
    config["engines"] |= {"newton": None, "genesis": None}
    plan = plan_of(config)
    assert "newton" not in plan.engines and "genesis" not in plan.engines
    assert "make engine-venvs" in plan.unavailable["newton"] and "build failed" not in plan.unavailable["newton"]
    assert plan.unavailable["genesis"].endswith(
        "its build failed: ERROR: No matching distribution found for torch==2.13.0"
    )


def test_the_answer_rests_on_the_verdicts_runs_else_on_drives_steps(config, tmp_path):
    """Rule answer, its figure and the decision tree read one comparison's tables (Plan.answer_tables): the
    verdict's where the study has real runs of its robot, else the DRIVE comparison's; the answer's basis
    names the dataset, its unit and the study's other real data."""
    (tmp_path / "drive").mkdir()
    config["drive_dir"] = str(tmp_path / "drive")
    plan = plan_of(config)
    assert plan.answer_source == "verdict" and plan.answer_tables()["outcomes"] == "results/verdict/outcomes.csv"
    basis = plan.answer_settings()["basis"]
    assert basis["unit"] == "run" and basis["others"] == ["DRIVE"]

    config["real_data"]["robot"] = "another_robot"  # the committed segments are not this robot's: no verdict
    config["accuracy"]["reference"] = "paper"
    plan = plan_of(config)
    assert not plan.verdict and plan.answer_source == "drive"
    tables = plan.answer_tables()
    assert tables["outcomes"] == "results/drive/drive/outcomes.csv" and "discrimination" not in tables
    assert set(plan.answer_inputs()) == {"outcomes", "mechanics", "table", "per_test"}
    assert plan.answer_settings()["basis"] | {"title": ""} == {
        "dataset": "DRIVE",
        "unit": "step",
        "noun": "DRIVE steps",
        "title": "",
        "others": [],
    }
    assert "results/report/figures/answer.png" in plan.report_figures()
    assert plan.report_real_inputs()["verdict_outcomes"] == tables["outcomes"]

    del config["drive_dir"]
    plan = plan_of(config)
    assert plan.answer_source is None and plan.answer_tables() == {}
    assert "results/report/figures/answer.png" not in plan.report_figures()


def test_the_scheduler_s_pending_timers_are_cancelled_when_the_workflow_ends():
    """Snakemake's scheduler leaves a non-daemon threading.Timer after each scheduling pass, which the
    interpreter would wait for at exit; the Snakefile's onsuccess/onerror cancel every pending one."""
    import threading

    from simpick.plan.scheduling import release_scheduler_timers

    fired = []
    timer = threading.Timer(60.0, lambda: fired.append(True))
    timer.start()
    assert release_scheduler_timers() >= 1
    timer.join(timeout=5)
    assert not timer.is_alive() and not fired
    assert release_scheduler_timers() == 0
