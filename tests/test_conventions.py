"""Snakemake workflow catalogue conventions: `snakemake --lint` and `snakefmt --check` clean, the
Python code clean under `ruff check` and `ruff format --check` (configured in pyproject.toml), a
caption for every output registered with report(), the .test configuration run end to end, a
licence and citation metadata that say the same as pyproject.toml."""

import os
import re
import shutil
import subprocess
import sys

import pandas as pd
import pytest
import yaml

from conftest import ROOT, SNAKEMAKE, study_config, tiny_config, write_config

RULE_FILES = [ROOT / "Snakefile", *sorted((ROOT / "rules").glob("*.smk"))]


def run(args, cwd, **kwargs):
    return subprocess.run(
        args, cwd=cwd, capture_output=True, text=True, env=os.environ | {"PYTHONHASHSEED": "0"}, **kwargs
    )


@pytest.mark.workflow
@pytest.mark.parametrize("configfile", [None, "config/sweeps/timestep.yaml", ".test/config.yaml"])
def test_snakemake_lint_is_clean(configfile, tmp_path):
    """The default config (calibration's rules included), the sweep's and the .test one each
    define a different set of rules; a lint is one line per rule or file, so none may appear."""
    args = [*SNAKEMAKE, "--lint", "--snakefile", str(ROOT / "Snakefile"), "--directory", str(tmp_path)]
    if configfile == ".test/config.yaml":
        workdir = dot_test_copy(tmp_path)
        args[-1] = str(workdir)
    elif configfile:
        merged = study_config(configfile)
        write_config(tmp_path, merged | tiny_paths(tmp_path))
        args += ["--configfile", str(tmp_path / "config.yaml")]
    else:
        write_config(tmp_path, study_config() | tiny_paths(tmp_path))
        args += ["--configfile", str(tmp_path / "config.yaml")]
    out = run(args, ROOT)
    assert out.returncode == 0, out.stderr[-3000:]
    assert "Congratulations, your workflow is in a good condition!" in out.stdout + out.stderr, out.stdout + out.stderr


def tiny_paths(workdir):
    """The config keys that name files, made absolute (the lint runs in a scratch directory)."""
    config = tiny_config()
    return {
        "robot": config["robot"],
        "reference": config["reference"],
        "qualitative": config["qualitative"],
        "real_data": config["real_data"] | {"segments": str(ROOT / config["real_data"]["segments"])},
        # every simulator the engines allow
        "simulators": {
            "catalog": config["simulators"]["catalog"],
            "calibration": str(ROOT / "resources/simulators/calibration.yaml"),
        },
    }


def test_snakefmt_check_is_clean():
    out = run([sys.executable, "-m", "snakefmt", "--check", *map(str, RULE_FILES)], ROOT)
    assert out.returncode == 0, "run .venv/bin/snakefmt Snakefile rules/\n" + out.stderr[-3000:]


PYTHON_TREES = ["src", "tests", "scripts", "bench"]


def test_ruff_check_is_clean():
    out = run([sys.executable, "-m", "ruff", "check", "--no-cache", *PYTHON_TREES], ROOT)
    assert out.returncode == 0, "run .venv/bin/ruff check --fix src tests scripts bench\n" + out.stdout[-3000:]


def test_ruff_format_check_is_clean():
    out = run([sys.executable, "-m", "ruff", "format", "--check", "--no-cache", *PYTHON_TREES], ROOT)
    assert out.returncode == 0, "run .venv/bin/ruff format src tests scripts bench\n" + out.stdout[-3000:]


GUARDED = """
import subprocess, sys
import pytest

def test_unmarked():
    subprocess.run([sys.executable, "-m", "snakemake", "--version"], capture_output=True)

@pytest.mark.workflow
def test_marked():
    assert subprocess.run([sys.executable, "-m", "snakemake", "--version"], capture_output=True).returncode == 0

def test_other_commands():
    assert subprocess.run([sys.executable, "-c", "pass"]).returncode == 0
"""


def test_a_test_that_starts_snakemake_unmarked_fails(tmp_path):
    """The fast tier's guard (tests/conftest.py): a test that starts Snakemake must carry the workflow marker."""
    (tmp_path / "test_guarded.py").write_text(GUARDED)
    env = os.environ | {"PYTHONPATH": os.pathsep.join([str(ROOT / "tests"), os.environ.get("PYTHONPATH", "")])}
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "pytest",
            "-q",
            "-p",
            "conftest",
            "-p",
            "no:cacheprovider",
            "-W",
            "ignore::pytest.PytestUnknownMarkWarning",
            "--rootdir",
            str(tmp_path),
            "-c",
            os.devnull,
            str(tmp_path / "test_guarded.py"),
        ],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env=env,
    )
    assert "1 failed, 2 passed" in out.stdout, out.stdout[-3000:] + out.stderr[-3000:]
    assert "test_unmarked starts Snakemake but is not marked @pytest.mark.workflow" in out.stdout


def test_every_report_output_has_a_caption():
    registered = 0
    for path in RULE_FILES:
        for call in re.finditer(r"report\((?P<args>[^()]*(?:\([^()]*\)[^()]*)*)\)", path.read_text()):
            args = call.group("args")
            if not args.strip() or "`" in args:  # prose mentions report() in comments
                continue
            registered += 1
            if "caption=caption" in args:  # the plan's table of the report job's weighed outputs: below
                continue
            caption = re.search(r'caption="([^"]+)"', args)
            assert caption, f"{path.name}: report({args.strip()[:60]}...) has no caption="
            assert (path.parent / caption.group(1)).is_file(), f"{path.name}: {caption.group(1)} does not exist"
    assert registered >= 13
    from simpick.plan.report import ANSWERED, SIMULATORS_WEIGHED, WEIGHED

    for name, (_path, caption, category) in (WEIGHED | ANSWERED | SIMULATORS_WEIGHED).items():
        assert (ROOT / "rules" / caption).is_file() and category, f"{name}: {caption} does not exist"


def dot_test_copy(tmp_path):
    """The .test configuration in a scratch directory beside a link to the project's resources/
    (its paths are relative to .test/, the working directory: ../resources/...)."""
    workdir = tmp_path / ".test"
    shutil.copytree(ROOT / ".test", workdir, ignore=shutil.ignore_patterns("results", ".snakemake"))
    (tmp_path / "resources").symlink_to(ROOT / "resources")
    return workdir


@pytest.mark.workflow
def test_the_dot_test_configuration_runs_end_to_end(tmp_path):
    workdir = dot_test_copy(tmp_path)
    out = run([*SNAKEMAKE, "--snakefile", str(ROOT / "Snakefile"), "--directory", str(workdir), "--cores", "2"], ROOT)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-3000:]
    config = yaml.safe_load((ROOT / ".test/config.yaml").read_text())
    weighted = pd.read_csv(workdir / "results/scores/weighted.csv", index_col="engine")
    assert sorted(weighted.index) == sorted(config["engines"])
    assert weighted["total"].gt(0).all()
    per_test = pd.read_csv(workdir / "results/metrics/segments/per_test.csv")
    profiles = ["coppeliasim-shipped", "coppeliasim-tuned"]
    assert sorted(per_test.engine) == sorted([*config["engines"], *config["baselines"], *profiles])
    assert (workdir / "results/report/report.pdf").stat().st_size > 0
    # the simulators' rows, their files to paste and the report's section
    table = pd.read_csv(workdir / "results/simulators/table.csv")
    ran = table[table.status.str.startswith("run")]
    # CoppeliaSim exposes no setting that moves the turning: its calibrated row reads its tuned profile's results
    rows = sorted(["coppeliasim-calibrated", *profiles])
    assert sorted(ran.simulator + "-" + ran.variant) == rows
    assert table.set_index("variant").loc["calibrated"].query("simulator == 'coppeliasim'").model.tolist() == [
        "coppeliasim-tuned"
    ]
    assert ran.mechanics.isin(["pass", "fail"]).all()  # (.test has no turning case: no flat-ground gain)
    files = sorted(p.name for p in (workdir / "results/simulators/settings").glob("*.lua"))
    assert files == [f"{p}.lua" for p in rows]
    assert 'id="simulators-table"' in (workdir / "results/report/report.html").read_text()
    again = run([*SNAKEMAKE, "--snakefile", str(ROOT / "Snakefile"), "--directory", str(workdir), "-n"], ROOT)
    assert "Nothing to be done" in again.stdout + again.stderr  # same code and config: nothing reruns


def test_the_licence_and_citation_agree_with_the_package():
    pyproject = (ROOT / "pyproject.toml").read_text()
    assert re.search(r'^license = \{ text = "MIT" \}', pyproject, re.M)
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")
    citation = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    assert citation["cff-version"] == "1.2.0" and citation["license"] == "MIT"
    version = re.search(r'^version = "([^"]+)"', pyproject, re.M).group(1)
    assert citation["version"] == version
    (paper,) = citation["references"]
    assert paper["doi"] == "10.1016/j.simpat.2022.102629" and paper["volume"] == 120 and paper["year"] == 2022
    assert [a["family-names"] for a in paper["authors"]] == ["Farley", "Wang", "Marshall"]
