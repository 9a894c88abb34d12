"""A source is a module (simpick.sources, issue 21): every kind gives the same interface, and a
job reaches only its own kind's code, so an edit to one source module changes no other source's
code version (what reruns: tests/test_workflow.py)."""

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
    assert len(wanted) == 10
    assert module.KIND == kind
    assert sources.module(module.DRIVEN).DRIVEN == module.DRIVEN  # driven by a kind that drives itself
    assert module.GROUP in ("terrain", "terrain_class")


def test_an_unknown_kind_is_refused_by_name():
    with pytest.raises(ValueError, match=r"no source kind 'moon'; known: \['lab', 'own', 'replay', 'segments'\]"):
        sources.module("moon")


def test_own_logs_run_the_replay_jobs():
    assert sources.entry("own", "prepare_case") == "simpick.sources.replay:prepare_case"
    assert sources.entry("own", "compare") == "simpick.sources.replay:compare"
    assert sources.entry("lab", "compare") == "simpick.sources.lab:compare"


def roots(kind, step, root=None):
    """What the plan (simpick.plan) hashes for a kind's simulate (case_code, less the adapter) or compare job."""
    job = {"prepare_case": "simpick.simulate.jobs:simulate_job", "compare": "simpick.compare.jobs:compare_job"}[step]
    return (job, sources.entry(kind, step))


def test_a_job_reaches_its_own_source_module_only():
    src = ROOT / "src" / "simpick" / "sources"
    for kind in ("lab", "segments", "replay"):
        for step in ("prepare_case", "compare"):
            files = {p.name for p in job_files(*roots(kind, step)) if p.parent == src}
            assert files == {"__init__.py", "base.py", f"{kind}.py"}, (kind, step, files)


@pytest.fixture()
def library(tmp_path):
    copy = tmp_path / "simpick"
    shutil.copytree(ROOT / "src" / "simpick", copy, ignore=shutil.ignore_patterns("__pycache__"))
    clear_cache()
    yield copy
    clear_cache()


def versions(root):
    return {(kind, step): job_code(*roots(kind, step), root=root)
            for kind in ("lab", "segments", "replay", "own") for step in ("prepare_case", "compare")}


@pytest.mark.parametrize("kind", ["lab", "segments", "replay"])
def test_an_edit_to_one_source_module_changes_that_sources_versions_only(library, kind):
    before = versions(library)
    path = library / "sources" / f"{kind}.py"
    text = path.read_text()
    path.write_text(text.replace("\nMEM_MB = ", "\nEDITED = True\nMEM_MB = ", 1))
    assert path.read_text() != text
    clear_cache()
    after = versions(library)
    changed = sorted({k for k in before if before[k] != after[k]})
    driven_by = {"lab": ["lab"], "segments": ["segments"], "replay": ["own", "replay"]}[kind]
    assert changed == [(k, step) for k in driven_by for step in ("compare", "prepare_case")]


def test_an_edit_to_a_comparison_changes_no_simulation(library):
    before = versions(library)
    path = library / "sources" / "lab.py"
    path.write_text(path.read_text().replace("    reference = lab_reference(", "    reference = (lab_reference)(", 1))
    clear_cache()
    after = versions(library)
    assert sorted(k for k in before if before[k] != after[k]) == [("lab", "compare")]
