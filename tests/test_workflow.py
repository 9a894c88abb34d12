"""The workflow end to end on a tiny config, and the rerun contract.

The contract (what a user relies on to iterate cheaply): nothing edited -> nothing runs;
a weight edited -> only the answer (which writes the weighted table) and the report's body (not the printed tree, which
reads no weight, nor its
evidence's sections 2-5 nor its appendices: rule report_evidence); a report
template edited -> only the report and its figures; one engine's settings or code edited -> only that
engine's simulations and what depends on them; a library module edited -> only the jobs that can import
it (their code versions: the modules reachable through import statements, wherever they stand:
simpick.codeversion) and what depends on them.
"""

import pandas as pd
import pytest
import yaml

from conftest import TINY_STUDY, copy_study, planned_jobs, snakemake, tiny_config, write_config
from simpick.simulate.traces import read_trace

pytestmark = pytest.mark.xdist_group(TINY_STUDY)  # the session's tiny study (conftest.tiny_study)


@pytest.fixture(scope="module")
def study(tiny_study, tmp_path_factory):
    """A copy of the session's tiny study, which this module's tests edit and restore."""
    workdir, config = tiny_study
    return copy_study(workdir, tmp_path_factory.mktemp("study") / "study"), config


@pytest.mark.workflow
def test_tiny_study_writes_every_output(study):
    workdir, config = study
    traces = sorted((workdir / "results" / "traces" / "lab").rglob("*.parquet"))
    assert len(traces) == len(config["engines"]) * 2 * 1
    for path in ("scores/weighted.csv", "published/table11.csv", "report/report.html", "report/report.pdf"):
        assert (workdir / "results" / path).stat().st_size > 0, path
    weighted = pd.read_csv(workdir / "results/scores/weighted.csv", index_col="engine")
    assert sorted(weighted.index) == sorted(config["engines"])
    assert weighted["total"].between(0, 56).all()
    # every engine finished its real segments, so every accuracy and speed score is a number: an
    # all-NaN column would pass the total's range check as zeros
    for metric in ("imu_angular", "imu_linear", "real_time_factor", "cpu_average", "cpu_intense"):
        assert weighted[metric].between(0, 1).all() and (weighted[metric] == 1).any(), metric
    assert weighted["excluded"].isna().all(), weighted["excluded"]  # empty cells: nothing left out
    frame, meta = read_trace(traces[0])
    assert len(frame) == 150  # 1.5 s at 100 Hz
    for key in ("engine_version", "timestep", "seed", "wall_time", "cpu_time", "steps", "config_hash", "units"):
        assert key in meta, key
    assert meta["units"]["ax"] == "m/s^2" and meta["steps"] == 1500


@pytest.mark.workflow
def test_validation_and_reference_models_are_in_the_study(study):
    workdir, config = study
    summary = pd.read_csv(workdir / "results/validation/summary.csv")
    assert sorted(summary.engine.unique()) == sorted(config["engines"])
    assert set(summary.case) == set(config["validation"]["cases"])
    assert summary.engine_value.notna().all() and summary.analytic_value.notna().all()
    html = (workdir / "results/report/report.html").read_text()
    assert "Engines against analytic mechanics" in html
    per_test = pd.read_csv(workdir / "results/metrics/segments/per_test.csv")
    assert {"kinematic", "coulomb"} <= set(per_test.engine)
    kinematic = per_test[(per_test.engine == "kinematic") & (per_test.kind == "turning")]
    assert ((kinematic.yaw_rate_gain_sim - 1).abs() < 0.02).all()  # no slip: yaw rate = commanded w


@pytest.mark.workflow
def test_tolerance_edit_rejudges_without_stepping_an_engine(study):
    workdir, config = study
    edited = yaml.safe_load(yaml.safe_dump(config))
    edited["validation"]["tolerances"]["yaw_rate_gain"] = 0.2
    write_config(workdir, edited)
    try:
        rules = sorted({rule for rule, _ in planned_jobs(workdir)})
        # the validation is re-judged; the verdict's mechanics gate rests on it (and the answer, which the
        # report job writes, its figure, the decision tree and its figure on the verdict): no engine steps,
        # no lab or real-data job
        assert rules == [
            "all",
            "decision_tree",
            "figure_answer",
            "figure_tree",
            "figure_validation",
            "report",
            "report_evidence",  # section 4 and appendix G: the validation case by case
            "validation_summary",
            "verdict",
        ]
    finally:
        write_config(workdir, config)


@pytest.mark.workflow
def test_nothing_edited_nothing_runs(study):
    workdir, _ = study
    assert planned_jobs(workdir) == []


@pytest.mark.workflow
def test_weight_edit_reruns_only_scoring_and_report(study):
    workdir, config = study
    edited = yaml.safe_load(yaml.safe_dump(config))
    edited["weights"]["ui"] = 1
    write_config(workdir, edited)
    try:
        rules = sorted({rule for rule, _ in planned_jobs(workdir)})
        # the page draws weight x score from the scores' contributions (no figure of them); the answer gives
        # the weighted total its interval over real runs and flags it; the report's table under the printed tree
        # orders each leaf's engines by the weighted total (the figure reads no weight: figure_tree does not
        # rerun); the verdict's tests (each engine against the best) read no weight.
        # The scores and the record of what they rest on (rule scores) read no weight; the report job weighs
        # them (it writes weighted.csv, contributions.csv, drivers.csv and the answer before the page: no job
        # of their own before it); the evidence's sections 2-5 and the appendices (report_evidence) read no
        # weight either: the report job lays out its body and joins the evidence's PDF
        assert rules == ["all", "report"]
    finally:
        write_config(workdir, config)


@pytest.mark.workflow
def test_margin_edit_reruns_only_the_verdict_and_the_report(study):
    workdir, config = study
    edited = yaml.safe_load(yaml.safe_dump(config))
    edited.setdefault("verdict", {}).setdefault("margins", {})["heading_error"] = {"basis": "absolute", "value": 0.2}
    write_config(workdir, edited)
    try:
        rules = sorted({rule for rule, _ in planned_jobs(workdir)})
        # the margin reaches the verdict's rule through its params; the answer's figure (the margin shaded),
        # the decision tree and its figure, and the report (with the answer it writes) read its outcomes; the
        # evidence's section 3 what the accuracy scores can tell apart, which the verdict job writes: no
        # score, no simulation, no other figure
        assert rules == [
            "all",
            "decision_tree",
            "figure_answer",
            "figure_tree",
            "report",
            "report_evidence",
            "verdict",
        ]
    finally:
        write_config(workdir, config)


@pytest.mark.workflow
def test_template_edit_reruns_only_the_report(study, tmp_path):
    """A template edit reruns the report, its PDF and the figures (the figure rules import the
    report package, whose build module reads the templates), nothing else. The edit is made to a
    copy of the library (first on PYTHONPATH, so the workflow's code fingerprints read it), not to
    tracked files."""
    import shutil

    from conftest import ROOT

    workdir, _ = study
    copy = tmp_path / "src"
    shutil.copytree(ROOT / "src" / "simpick", copy / "simpick", ignore=shutil.ignore_patterns("__pycache__"))
    env = {"PYTHONPATH": str(copy)}
    assert planned_jobs(workdir, env) == []  # the copy fingerprints like the original
    template = copy / "simpick" / "report" / "templates" / "report.html.j2"
    template.write_text(template.read_text() + "\n{# edited #}\n")
    assert reporting_only(planned_jobs(workdir, env))


def reporting_only(jobs) -> bool:
    """The jobs are the report's (HTML and PDF in one job), its appendices' and figures' (at least the
    report), nothing else."""
    rules = {rule for rule, _ in jobs}
    reporting = ("all", "report", "report_evidence")
    return "report" in rules and all(r in reporting or r.startswith("figure_") for r in rules)


def edited_library(tmp_path, module: str, old: str | None, new: str) -> dict:
    """A copy of src/simpick with one edit in ``module`` (first on PYTHONPATH, so the workflow's code
    versions read it; simpick.codeversion), as the environment of a dry run; ``old`` None appends ``new``.
    Tracked files are not touched."""
    import shutil

    from conftest import ROOT

    copy = tmp_path / "src"
    shutil.copytree(ROOT / "src" / "simpick", copy / "simpick", ignore=shutil.ignore_patterns("__pycache__"))
    path = copy / "simpick" / module
    text = path.read_text()
    if old is None:
        path.write_text(text + new)
        return {"PYTHONPATH": str(copy)}
    assert text.count(old) == 1, f"{module}: {old!r} is not there once"
    path.write_text(text.replace(old, new))
    return {"PYTHONPATH": str(copy)}


SIMULATING = ("simulate", "cpu_load", "validate", "terrain")  # and the batched simulate_<source>


def simulated(jobs):
    return sorted((rule, w) for rule, w in jobs if rule in SIMULATING or rule.startswith("simulate_"))


@pytest.mark.workflow
def test_a_segments_module_edit_reruns_the_segment_jobs_and_no_lab_simulation(study, tmp_path):
    """real/segments.py is imported by how the segments are driven (simulate.real) and by the
    comparison (compare.real): editing it reruns every model's segment simulations and what depends
    on them, and no lab simulation (the lab's comparison, which shares compare/, may rerun)."""
    workdir, config = study
    env = edited_library(tmp_path, "real/segments.py", "\nCOLUMNS = ", "\nEDITED = True\nCOLUMNS = ")
    jobs = planned_jobs(workdir, env)
    models = sorted([*config["engines"], *config["baselines"]])
    assert simulated(jobs) == [("simulate_segments", f"engine={m}") for m in models]
    assert ("compare", "source=segments") in jobs and ("summarise", "source=segments") in jobs
    assert not {rule for rule, _ in jobs} & {"validation_summary", "published_table11"}


@pytest.mark.workflow
def test_how_one_kind_is_driven_reruns_that_kinds_simulations_only(study, tmp_path):
    """simulate/real.py drives the segments (and replays), simulate/lab.py the lab tests (simulate_job
    imports a kind's module by name): editing one reruns that kind's simulations and what depends on
    them, no other kind's simulation. A source module (simpick.sources) is planning: no job imports it."""
    workdir, config = study
    env = edited_library(tmp_path / "segments", "simulate/real.py", None, "\nEDITED = True\n")
    jobs = planned_jobs(workdir, env)
    models = sorted([*config["engines"], *config["baselines"]])
    assert simulated(jobs) == [("simulate_segments", f"engine={m}") for m in models]
    assert ("compare", "source=segments") in jobs
    assert not [job for job in jobs if "source=lab" in job[1] or job[0] == "simulate_lab"], jobs
    env = edited_library(tmp_path / "lab", "simulate/lab.py", None, "\nEDITED = True\n")
    jobs = planned_jobs(workdir, env)
    assert {rule for rule, _ in simulated(jobs)} == {"simulate_lab"}
    assert ("compare", "source=lab") in jobs
    assert not [job for job in jobs if "source=segments" in job[1] or job[0] == "simulate_segments"], jobs
    env = edited_library(tmp_path / "source", "sources/segments.py", None, "\nEDITED = True\n")
    assert planned_jobs(workdir, env) == []


@pytest.mark.workflow
def test_a_report_edit_simulates_nothing(study, tmp_path):
    workdir, _ = study
    env = edited_library(tmp_path, "report/render.py", "\nTEMPLATE = ", "\nEDITED = True\nTEMPLATE = ")
    assert reporting_only(planned_jobs(workdir, env))


@pytest.mark.workflow
def test_an_rtf_edit_reruns_the_summaries_not_the_simulations(study, tmp_path):
    """equal_rtf lies in compare/jobs.py: the compare stage's jobs rerun (the whole module counts),
    no simulation and no validation."""
    workdir, _ = study
    env = edited_library(
        tmp_path,
        "compare/jobs.py",
        "    engines = sorted(runs.engine.unique())\n",
        "    engines = sorted(runs.engine.unique())  # edited\n    assert engines is not None\n",
    )
    jobs = planned_jobs(workdir, env)
    assert simulated(jobs) == [] and not {rule for rule, _ in jobs} & {"validation_summary", "validate"}
    assert {("summarise", "source=lab"), ("summarise", "source=segments")} <= set(jobs)


@pytest.mark.workflow
def test_moving_an_import_reruns_nothing(study, tmp_path):
    """An import moved from the top of a module into the function that uses it: no job reruns."""
    workdir, _ = study
    env = edited_library(tmp_path, "compare/jobs.py", "from simpick.compare.kinds import BY_KIND\n", "")
    path = tmp_path / "src" / "simpick" / "compare" / "jobs.py"
    text = path.read_text()
    anchor = "    per_test, detail, runs = BY_KIND[kind]("
    assert text.count(anchor) == 1
    path.write_text(text.replace(anchor, "    from simpick.compare.kinds import BY_KIND\n\n" + anchor))
    assert planned_jobs(workdir, env) == []


@pytest.mark.workflow
def test_an_engine_code_edit_reruns_only_that_engine(study, tmp_path):
    """An edit to one adapter module reruns that engine's simulations, validation and CPU load (and
    what depends on them), no other model's."""
    workdir, config = study
    env = edited_library(tmp_path, "engines/mujoco_engine.py", None, "\nEDITED = True\n")
    jobs = planned_jobs(workdir, env)
    stepping = [
        (rule, w) for rule, w in jobs if rule in ("simulate", "cpu_load", "validate") or rule.startswith("simulate_")
    ]
    assert stepping and all("engine=mujoco" in w for _, w in stepping), stepping
    assert not {rule for rule, _ in jobs} & {"terrain", "published_table11"}


@pytest.mark.workflow
def test_engine_edit_reruns_only_that_engine(study):
    workdir, config = study
    edited = yaml.safe_load(yaml.safe_dump(config))
    edited["engines"]["mujoco"]["solver_iterations"] = 60
    write_config(workdir, edited)
    try:
        jobs = planned_jobs(workdir)
        simulated = sorted(w for rule, w in jobs if rule in ("simulate", "cpu_load") or rule.startswith("simulate_"))
        assert simulated and all("engine=mujoco" in w for w in simulated), simulated
        # the lab's 2 terrains, a job each (its motions in one), and the segments in one job
        assert sorted(w for rule, w in jobs if rule == "simulate_lab") == [
            "engine=mujoco, group=bumps",
            "engine=mujoco, group=grass",
        ]
        assert [rule for rule, _ in jobs if rule.startswith("simulate_segments")] == ["simulate_segments"]
        # its validation cases, all in its one job, and no other engine's
        assert [w for rule, w in jobs if rule == "validate"] == ["engine=mujoco"]
        assert not {rule for rule, _ in jobs} & {"terrain", "published_table11"}
    finally:
        write_config(workdir, config)


@pytest.mark.workflow
@pytest.mark.parametrize(
    "key,value,message",
    [
        # 1/100 s is not a whole number of 3 ms steps (a check across keys: pydantic runs it only once
        # every field is valid, so it gets a config of its own)
        (("physics", "timestep"), 0.003, "physics.timestep 0.003 s does not divide the IMU period"),
        (("weights", "free"), -1, "weights.free: Input should be greater than or equal to 0"),
        (("statistics", "min_runs"), 5, "statistics.min_runs 5: a sign-flip test over 5 runs cannot give p below"),
    ],
)
def test_bad_config_is_refused_before_any_job(tmp_path, key, value, message):
    config = tiny_config(tmp_path)
    config[key[0]][key[1]] = value
    write_config(tmp_path, config)
    run = snakemake(tmp_path, "-n")
    assert run.returncode != 0
    text = run.stdout + run.stderr
    assert message in text
    assert "Traceback" not in text


@pytest.mark.workflow
def test_a_new_engine_runs_only_its_own_simulations(tiny_study, tmp_path):
    """Adding an engine to a finished study steps no other engine again: no other model's simulation, validation
    or CPU-load job depends on which engines there are. Shown on a copy of the session's study with one engine
    taken out of its config, a dry run then plans no job that steps an engine (had the others' parameters,
    inputs or code depended on the set of engines, their jobs would rerun, the same as when one is added), and
    neither the terrains nor the paper's table."""
    workdir, config = tiny_study
    workdir = copy_study(workdir, tmp_path / "study")
    without = yaml.safe_load(yaml.safe_dump(config))
    without["engines"].pop("ode")
    write_config(workdir, without)
    jobs = planned_jobs(workdir)
    assert jobs, "taking an engine out reruns what compares the engines"
    assert simulated(jobs) == [], simulated(jobs)
    assert not {rule for rule, _ in jobs} & {"terrain", "published_table11"}


def test_fetching_the_dataset_offline_says_how_to_use_a_local_copy(tmp_path, monkeypatch):
    from simpick.errors import InputError
    from simpick.real import jobs as realjobs

    monkeypatch.setattr(realjobs, "BOREALTC_ARCHIVES", ("http://127.0.0.1:9/BorealTC.zip",))
    with pytest.raises(InputError, match=r"could not download BorealTC.*borealtc_dir=PATH"):
        realjobs.fetch_borealtc(tmp_path / "borealtc", timeout=2)
    assert not (tmp_path / "borealtc").exists()
