"""The README and the documentation pages tell the truth about the workflow: every count they mark
(<!-- n:KEY -->N<!-- /n -->) against the config and a dry run of the default study, the claim about
declared resources against the rules, and the claim that scripts are thin against the scripts. When a
case, an engine or a source is added, this test names the numbers to update and where they are."""

import ast
import collections
import re

import pandas as pd
import pytest
import yaml

from conftest import ROOT, planned_jobs, study_config

MARK = re.compile(r"<!-- n:(\w+) -->([^<]*)<!-- /n -->")


@pytest.fixture(scope="module")
def counts(tmp_path_factory):
    """What the default config and its dry run say."""
    workdir = tmp_path_factory.mktemp("readme")
    (workdir / "resources").symlink_to(ROOT / "resources")
    (workdir / "config.yaml").write_text((ROOT / "config.yaml").read_text())
    jobs = collections.Counter(rule for rule, _ in planned_jobs(workdir))
    config = study_config()
    segments = pd.read_csv(ROOT / config["real_data"]["segments"])
    return {
        "validation_cases": len(config["validation"]["cases"]),
        "engines": len(config["engines"]),
        "reference_models": len(config["baselines"]),
        "terrains": len(config["terrains"]),
        "motions": len(config["motions"]),
        # a lab job runs a terrain's motions on one engine
        "lab_cases": jobs["simulate_lab"] * len(config["motions"]),
        "lab_jobs": jobs["simulate_lab"],
        "segments": len(segments),
        "jobs": sum(jobs.values()),
        "validate_jobs": jobs["validate"],
        "segment_jobs": jobs["simulate_segments"],  # every segment of a model in one job
        "cpu_load_jobs": jobs["cpu_load"],
        # the simulators the default study runs, and their profiles that simulate (not read from an engine)
        "simulators": len(_default_plan().simulators),
        "profiles": len(_default_plan().profiles),
    }


def _default_plan():
    from simpick.config import Study
    from simpick.plan import Plan

    config = study_config()
    return Plan(config, Study.model_validate(config), basedir=str(ROOT))


PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


@pytest.mark.workflow
def test_every_marked_count_is_the_workflows(counts):
    marks = [(page.relative_to(ROOT), key, value) for page in PAGES for key, value in MARK.findall(page.read_text())]
    assert {key for _, key, _ in marks} == set(counts), "a mark with no check, or a check with no mark"
    assert {"engines", "jobs", "lab_cases"} <= {key for page, key, _ in marks if page.name == "README.md"}
    wrong = sorted(
        {
            f"{page}: {key} is {value}, the workflow has {counts[key]}"
            for page, key, value in marks
            if int(value) != counts[key]
        }
    )
    assert not wrong, "stale counts: " + "; ".join(wrong)
    # the dry run agrees with the config it was made from
    assert counts["lab_jobs"] == counts["engines"] * counts["terrains"]
    assert counts["segment_jobs"] == counts["engines"] + counts["profiles"] + counts["reference_models"]
    # one job runs all of an engine's or a simulating profile's cases
    assert counts["validate_jobs"] == counts["engines"] + counts["profiles"]


def rule_blocks():
    """(rule name, text) of every rule in rules/*.smk; the simulate family's rule is stated in a loop."""
    for smk in sorted((ROOT / "rules").glob("*.smk")):
        for block in re.split(r"\n(?=\s*(?:rule|checkpoint)\b)", smk.read_text()):
            m = re.match(r"\s*(?:rule|checkpoint)\s*(\w*):", block)
            if m:
                yield m.group(1) or "simulate", block


def test_the_rules_that_declare_resources_are_the_ones_the_docs_name():
    declared = {
        name for name, block in rule_blocks() if "threads:" in block and "mem_mb=" in block and "runtime=" in block
    }
    named = {
        "simulate",
        "validate",
        "cpu_load",
        "sweep_segments",
        "calibrate",
        "calibration_evaluate",
        "simulator_calibrate",
        "compare",
        "summarise",
        "verdict",
        "scores",
    }
    figures = {name for name, _ in rule_blocks() if name.startswith("figure_")}
    assert declared == named | figures
    page = (ROOT / "docs/running.md").read_text()
    section = page[page.index("## On a cluster") :]
    assert all(f"`{name}`" in section for name in named) and "the figure rules declare" in section
    profile = yaml.safe_load((ROOT / "profiles/slurm/config.yaml").read_text())
    assert profile["default-resources"] == {"mem_mb": 400, "runtime": 10}  # docs/running.md states both
    assert "(`mem_mb` 400, `runtime` 10 minutes" in section


def test_every_script_calls_one_job_function():
    helpers = {"logged", "runtime_timeout", "LIST_INPUTS"}  # the log, the watchdog's limit, a constant
    for script in sorted((ROOT / "scripts").glob("*.py")):
        tree = ast.parse(script.read_text())
        imported = [
            alias.name
            for node in ast.walk(tree)
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("simpick")
            for alias in node.names
        ]
        jobs = [name for name in imported if name not in helpers]
        assert len(jobs) == 1, f"{script.name} calls {jobs}"
