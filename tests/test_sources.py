"""A source is a module (simpick.sources): every kind gives the same interface, read at planning
time only; a simulate job reaches only its own kind's prepare code, so an edit to how one kind is
driven changes no other kind's simulations, and an edit to a comparison changes no simulation
(what reruns: tests/test_workflow.py)."""

import shutil

import pytest

from conftest import ROOT
from simpick import sources
from simpick.codeversion import clear_cache, job_code, job_files
from simpick.sources.base import Source


@pytest.mark.parametrize("kind", sorted(sources.KINDS))
def test_every_kind_gives_the_interface(kind):
    module = sources.module(kind)
    wanted = [n for n in (*Source.__annotations__, *vars(Source)) if not n.startswith("_")]
    assert isinstance(module, Source), [n for n in wanted if not hasattr(module, n)]
    assert len(wanted) == 8
    assert module.KIND == kind
    if module.DRIVEN in sources.KINDS:  # driven by a kind that drives itself (own as replay)
        assert sources.module(module.DRIVEN).DRIVEN == module.DRIVEN
    assert module.GROUP in ("terrain", "terrain_class")


def test_an_unknown_kind_is_refused_by_name():
    known = r"\['drive', 'lab', 'own', 'replay', 'segments'\]"
    with pytest.raises(ValueError, match=rf"no source kind 'moon'; known: {known}"):
        sources.module("moon")


def test_own_logs_run_the_replay_jobs():
    from simpick.compare.kinds import BY_KIND
    from simpick.simulate.jobs import PREPARE

    assert sources.module("own").DRIVEN == "replay"
    # every kind a source is driven as has its prepare function and its comparison
    driven = {sources.module(kind).DRIVEN for kind in sources.KINDS}
    assert driven == set(PREPARE) == set(BY_KIND)


def roots(kind, step):
    """What the plan (simpick.plan) hashes for a kind's simulate (case_code, less the adapter) or compare job."""
    from simpick.simulate.jobs import PREPARE

    if step == "compare":
        return ("simpick.compare.jobs:compare_job",)
    return ("simpick.simulate.jobs:simulate_job", PREPARE[sources.module(kind).DRIVEN])


def test_no_job_reaches_a_source_module():
    """A source module is planning: what a job runs is its kind's prepare function and comparison."""
    src = ROOT / "src" / "simpick" / "sources"
    for kind in ("lab", "segments", "replay"):
        for step in ("prepare_case", "compare"):
            assert not [p for p in job_files(*roots(kind, step)) if p.parent == src], (kind, step)


def test_a_lab_simulation_reaches_no_real_data_code():
    files = {p.relative_to(ROOT / "src" / "simpick").parts[0] for p in job_files(*roots("lab", "prepare_case"))}
    assert "real" not in files and "compare" not in files, files
    files = {p.relative_to(ROOT / "src" / "simpick").as_posix() for p in job_files(*roots("segments", "prepare_case"))}
    assert {"simulate/real.py", "real/segments.py"} <= files and "simulate/lab.py" not in files


@pytest.fixture()
def library(tmp_path):
    copy = tmp_path / "simpick"
    shutil.copytree(ROOT / "src" / "simpick", copy, ignore=shutil.ignore_patterns("__pycache__"))
    clear_cache()
    yield copy
    clear_cache()


def versions(root):
    return {
        (kind, step): job_code(*roots(kind, step), root=root)
        for kind in ("lab", "segments", "replay", "own")
        for step in ("prepare_case", "compare")
    }


def edited(library, module, old, new):
    before = versions(library)
    path = library / module
    text = path.read_text()
    assert text.count(old) == 1, (module, old)
    path.write_text(text.replace(old, new))
    clear_cache()
    after = versions(library)
    return sorted({k for k in before if before[k] != after[k]})


def test_an_edit_to_how_one_kind_is_driven_changes_that_kinds_simulations_only(library):
    line = "    motion = p.motions[name]\n"
    assert edited(library, "simulate/lab.py", line, line + "    motion = motion\n") == [("lab", "prepare_case")]
    assert edited(library, "real/segments.py", "\nCOLUMNS = ", "\nEDITED = True\nCOLUMNS = ") == [
        ("lab", "compare"),
        ("own", "compare"),
        ("own", "prepare_case"),
        ("replay", "compare"),
        ("replay", "prepare_case"),
        ("segments", "compare"),
        ("segments", "prepare_case"),
    ]


def test_an_edit_to_a_comparison_changes_no_simulation(library):
    changed = edited(
        library, "compare/kinds.py", "    reference = lab_reference(", "    reference = {} | lab_reference("
    )
    assert changed == [(k, "compare") for k in ("lab", "own", "replay", "segments")]


def test_the_sources_params_from_the_typed_study_are_what_the_plain_settings_gave(tmp_path):
    """The sources read the typed study; their params are the plain settings' slices as before (a simulation
    whose params change reruns): every unit of the default study, and the DRIVE source's."""
    from conftest import tiny_config
    from simpick.config import Study
    from simpick.plan import Plan
    from simpick.real.steps import SIMILAR
    from simpick.sources.base import canonical, model_settings, simulation_params

    config = tiny_config(tmp_path)
    plan = Plan(config, Study.model_validate(config), basedir=str(ROOT))
    plain = plan.config

    def engine_params(plain: dict, engine: str) -> dict:
        """What every simulation on ``engine`` was given from the plain settings before typing."""
        robot = {k: v for k, v in plain["robot"].items() if k != "urdf"}
        return canonical(
            {
                "engine": engine,
                "engine_settings": model_settings(plain, engine),
                "physics": plain["physics"],
                "robot": robot,
                "imu": plain["imu"],
                "health": plain["health"],
                "seed": plain["seed"],
            }
        )

    for engine in plan.real_models:
        assert simulation_params(plan.settings, engine, plan.model_settings(engine)) == engine_params(plain, engine)
    motions = list(plan.motions)
    for terrain in plan.terrains:
        for engine in plan.engines:
            # a lab unit: a terrain's motions on one engine
            before = engine_params(plain, engine) | canonical(
                {"terrain": terrain, "motions": {m: plain["motions"][m] for m in motions}}
            )
            before |= {"kind": "lab", "source": "lab", "cases": motions}
            assert plan.case_params("lab", engine, terrain, motions) == before
    names = [name for _, name in plan.sources["segments"]["cases"]]
    grounds = {c: plain["real_data"]["classes"][c] for c in plan.segments}
    for engine in plan.real_models:
        for terrain_class in plan.segments:
            before = engine_params(plain, engine) | canonical(
                {"terrain_class": terrain_class, "class": plain["real_data"]["classes"][terrain_class]}
            )
            assert plan.real_params(engine, terrain_class) == before
        # the committed segments: every class's on one model
        unit = engine_params(plain, engine) | canonical({"classes": grounds})
        unit |= {"kind": "segments", "source": "segments", "cases": names}
        assert plan.case_params("segments", engine, None, names) == unit
    assert plan.compare_settings("segments") == canonical({"track": plain["robot"]["track"]})
    assert plan.compare_inputs(type("W", (), {"source": "lab"})())["published"] == plain["reference"]["published"]
    # the DRIVE source: its replay's params, inputs and comparison's settings as the plain settings gave them
    drive = sources.module("drive")
    study = plan.settings
    for engine in plan.real_models:
        before = engine_params(plain, engine) | canonical(
            {"classes": plain["real_data"]["classes"], "replay": plain["drive_replay"], "session": "s"}
        )
        assert drive.case_params(study, "drive", {}, engine, plan.model_settings(engine), "s", []) == before
    root = f"results/drive/{plain['drive_dataset']}"
    assert drive.case_inputs(study, "drive", {}, "", []) == {
        "cases": f"{root}/cases.csv",
        "wheels": f"{root}/{drive.WHEELS}",
        "urdf": plain["robot"]["urdf"],
    }
    judged = {"verdict": plain["verdict"], "statistics": plain["statistics"], "seed": plain["seed"]}
    judged |= {"unit": plain["drive_replay"]["unit"], "tolerance": SIMILAR}
    assert drive.compare_settings(study) == canonical(judged)
