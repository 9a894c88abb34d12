"""The Newton and Genesis models rule simulator_models writes (simpick.studies.simulator_models) run as they are and
do what they claim. Each is a Python script beside the URDF it loads: copied alone with its URDF into an empty
folder and run there by its simulator's interpreter (the engine's venv, ``python -I``: no PYTHONPATH, so nothing of
simpick can be imported), it builds the robot with the simulator's own API, drives it at each command it claims and
prints the yaw-rate gain it measures; that gain is the one the job took from simpick's validation (``run_case``, the
validate job's function) on simpick's adapter.

Without an engine's venv (``make engine-venvs``) its test is skipped with that reason in pytest's summary, and in CI
(``CI=true``) it fails, as tests/test_new_engines.py treats them."""

from __future__ import annotations

import ast
import json
import os
import shutil
import subprocess

import pytest

from conftest import ISOLATED_ENGINES, ROOT, study_config
from simpick.config import Study
from simpick.engines import isolated, unavailable
from simpick.plan import Plan
from simpick.studies.simulator_models import simulator_models_job
from test_new_engines import needs

# one worker steps Newton and Genesis (tests/conftest.py): each engine's start is paid once
pytestmark = pytest.mark.xdist_group(ISOLATED_ENGINES)

# s: each claimed case cut from its 6 s to 1 s. Measured (Newton 1.8.0, genesis-world 1.4.5; Husky, mu 0.8), each
# script at 6 s gave its adapter's gains to 1e-15 (Newton bit for bit), and its gains at 1 s differ from the 6-s
# ones by at most 1.8e-4 (Newton; spin, spin right, v 0.5 with w -0.2, -0.5, 0.2, 0.5: 0.46703 0.46704 0.47036
# 0.47241 0.46448 0.46167 at 6 s, 0.46705 0.46707 0.47018 0.47246 0.46437 0.46171 at 1 s) and 1.3e-6 (Genesis:
# 0.47227 0.47228 0.47108 0.47700 0.46734 0.46770 at both): the wheels have settled before the measured second half
# begins. A claim is tested at the duration its script states.
DURATION = 1.0
STEMS = {"newton": "isaac_lab_newton-tuned", "genesis": "genesis-tuned"}
# what a script may import: its simulator's packages, numpy and the standard library's
IMPORTS = {"newton": {"newton", "warp"}, "genesis": {"genesis"}}
STANDARD = {"__future__", "argparse", "json", "pathlib", "numpy"}
# skipped where not installed, with the reason (in CI run, so that a missing venv fails): test_new_engines.needs
ENGINES = [pytest.param(engine, marks=needs(engine)) for engine in STEMS]


def _config() -> dict:
    return study_config("config/engines/newton_genesis.yaml")


@pytest.fixture(scope="module")
def plan():
    config = _config()
    return Plan(config, Study.model_validate(config), basedir=str(ROOT))


@pytest.fixture(scope="module")
def models(tmp_path_factory, plan):
    """The job's models of the tuned profiles of the installed engines, from the plan's params with the claimed
    cases cut to DURATION; and the claims the job measured, per model."""
    tmp = tmp_path_factory.mktemp("models")
    params = plan.simulator_models_params()
    params["profiles"] = {s: params["profiles"][s] for s in STEMS.values() if s in params["profiles"]}
    params["cases"] = {name: dict(case, duration=DURATION) for name, case in params["cases"].items()}
    inputs = {"urdf": str(ROOT / plan.config["robot"]["urdf"]), "calibrations": []}
    claims = simulator_models_job(inputs, params, str(tmp / "models"))
    return tmp / "models", claims


def _require(engine: str) -> None:
    """A clear failure where the engine is not installed (in CI, where ``needs`` lets the test run)."""
    reason = unavailable([engine]).get(engine)
    if reason:
        pytest.fail(f"{engine}'s model cannot be run: {reason}", pytrace=False)


@pytest.mark.parametrize("engine", ENGINES)
def test_the_script_alone_reproduces_every_gain_it_claims(models, engine, tmp_path):
    _require(engine)
    folder, claims = models
    stem = STEMS[engine]
    script = folder / f"{stem}.py"
    text = script.read_text()
    # the script and its URDF, alone in an empty folder
    for suffix in ("py", "urdf"):
        shutil.copy(folder / f"{stem}.{suffix}", tmp_path / f"{stem}.{suffix}")
    assert sorted(p.name for p in tmp_path.iterdir()) == [f"{stem}.py", f"{stem}.urdf"]
    # its claims are the job's, at the test's duration
    stated = ast.literal_eval(next(n.value for n in ast.parse(text).body if _assigns(n, "CLAIMS")))
    measured = {c.case: c for c in claims[stem]}
    assert stated and sorted(c["case"] for c in stated) == sorted(measured)
    for c in stated:
        assert (c["v"], c["w"], c["duration"], c["gain"]) == pytest.approx(
            (measured[c["case"]].v, measured[c["case"]].w, DURATION, measured[c["case"]].gain)
        )
    # one process runs every claimed command (Genesis compiles its kernels once)
    python = str(isolated.venv_python(engine))
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
    run = subprocess.run(
        [python, "-I", f"{stem}.py", "--duration", str(DURATION)],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert run.returncode == 0, run.stderr[-3000:]
    printed = {r["case"]: r for r in (json.loads(line) for line in run.stdout.splitlines() if line.startswith("{"))}
    assert sorted(printed) == sorted(measured), run.stdout[-3000:]
    for case, claim in measured.items():
        got = printed[case]
        assert (got["v"], got["w"], got["duration"]) == (claim.v, claim.w, DURATION)
        print(f"{stem} {case}: claimed {claim.gain:.6f}, the script alone {got['gain']:.6f}")
        assert abs(got["gain"] - claim.gain) < 0.01, f"{stem} {case}: ran {got['gain']:.4f}, claimed {claim.gain:.4f}"


def _assigns(node, name: str) -> bool:
    return isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == name for t in node.targets)


@pytest.mark.parametrize("engine", ENGINES)
def test_the_script_imports_only_its_simulator_numpy_and_the_standard_library(models, engine):
    _require(engine)
    folder, _ = models
    text = (folder / f"{STEMS[engine]}.py").read_text()
    roots = set()
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Import):
            roots |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            roots.add((node.module or "").split(".")[0])
    assert roots <= IMPORTS[engine] | STANDARD, roots
    assert "resources/" not in text and str(ROOT) not in text  # it names none of simpick's files
    # the URDF beside it names no other file (no mesh)
    assert "filename=" not in (folder / f"{STEMS[engine]}.urdf").read_text()


def test_the_models_exist_only_where_newton_and_genesis_are_configured(plan):
    """The default study (six engines) plans no Newton or Genesis model; the eight-engine one plans a script per
    profile of theirs that is run (a machine without an engine's venv leaves the engine, and its models, out)."""
    default = study_config()
    six = Plan(default, Study.model_validate(default), basedir=str(ROOT))
    assert not [p for p in six.model_profiles if p.startswith(("genesis", "isaac_lab_newton"))]
    files = plan.model_files()
    for engine, stem in STEMS.items():
        if engine in plan.engines:
            assert files[stem] == f"results/simulators/models/{stem}.py"
        else:
            assert stem not in files
