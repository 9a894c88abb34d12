import os
import re
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
import yaml

from simpick.inputs.robot import load_robot

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared"


@pytest.fixture(scope="session")
def robot():
    return load_robot(ROOT / "resources" / "robot" / "husky_a200.urdf")


def flat_terrain(friction: float = 0.95) -> dict:
    """A terrain with no shapes: the robot drives on the ground plane alone."""
    return {"schema": "simpick.inputs.terrain/1", "name": "flat", "boxes": [], "spheres": [], "friction": friction}


def tile_terrain(friction: float, thickness: float = 0.01) -> dict:
    """One large tile under the robot, so every wheel contact is a terrain contact."""
    terrain = flat_terrain(friction)
    terrain["boxes"] = [[0.0, 0.0, thickness / 2, 0.0, 6.0, 6.0, thickness]]
    return terrain


def setup(
    robot,
    *,
    terrain=None,
    ground=0.95,
    torque=50.0,
    starts=((0.0, 0.0, 0.0),),
    v=0.5,
    w=0.0,
    duration=0.3,
    timestep=0.001,
    settings=None,
):
    """A scenario on flat ground (unless ``terrain`` is given) and its constant wheel commands."""
    from simpick.engines.base import Scenario
    from simpick.inputs.motions import constant_commands

    scenario = Scenario(
        robot=robot,
        terrain=flat_terrain(ground) if terrain is None else terrain,
        ground_friction=ground,
        timestep=timestep,
        max_wheel_torque=torque,
        starts=tuple(starts),
        settings=settings or {},
    )
    return scenario, constant_commands(v, w, duration, timestep, 0.555, robot.wheel_radius, len(starts))


def drive(engine: str, robot, **kwargs):
    """Simulate ``engine`` (a registry name) on :func:`setup`'s scenario; returns the record."""
    from simpick.engines import get_engine

    return get_engine(engine).simulate(*setup(robot, **kwargs))


# --- running the workflow on a tiny config (workflow and interruption tests) ---

SNAKEMAKE = [sys.executable, "-m", "snakemake"]

# The fast tier (pytest -m "not workflow") must start no Snakemake run: a test that starts one
# without the workflow marker fails, so the tier stays fast as tests are added.
_RUNNING: list[pytest.Item] = []


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    _RUNNING.append(item)
    try:
        yield
    finally:
        _RUNNING.pop()


def _starts_snakemake(args) -> bool:
    words = (
        args.split()
        if isinstance(args, str)
        else [str(a) for a in (args if isinstance(args, list | tuple) else [args])]
    )
    return any(Path(word).name == "snakemake" for word in words)


_popen_init = subprocess.Popen.__init__


def _popen_init_checked(self, args, *rest, **kwargs):
    if _RUNNING and _starts_snakemake(args) and _RUNNING[-1].get_closest_marker("workflow") is None:
        self._child_created = False  # what Popen.__del__ reads of an object it never started
        pytest.fail(
            f"{_RUNNING[-1].nodeid} starts Snakemake but is not marked @pytest.mark.workflow "
            "(the fast tier, pytest -m 'not workflow', must not run the workflow)",
            pytrace=False,
        )
    _popen_init(self, args, *rest, **kwargs)


subprocess.Popen.__init__ = _popen_init_checked

# The two engines that step this robot at about real time (DART's NSGS friction solve, Drake's hydroelastic
# contact: docs/benchmark.md) take half the CPU of the tests that start no workflow. A test run on either
# is marked slow, so the fast tier (make test-fast: -m "not workflow and not slow") stays under two minutes
# on two cores; the full suite (make test) runs them. Newton and Genesis too: they run in venvs of their own,
# which make test builds and make test-fast does not, and their tests add about 6 minutes on two cores
# (engine start-up included: Genesis builds the gravel strip in 87 s).
SLOW_ENGINES = {"dart", "drake", "newton", "genesis"}


ISOLATED_ENGINES = "newton_genesis"


def _isolated_engine(item, params) -> bool:
    """Whether ``item`` steps Newton or Genesis (in the venvs of their own: simpick.engines.isolated)."""
    return item.path.name == "test_new_engines.py" or any(v in ("newton", "genesis") for v in params)


def _shares_a_fixture(item) -> bool:
    """Whether ``item`` uses a fixture made once for several tests of its module (module, class or package scope,
    or session scope defined in the module itself): such a module's tests must run on one pytest-xdist worker,
    else each worker makes the fixture again."""
    info = getattr(item, "_fixtureinfo", None)
    if info is None:
        return False
    for name in info.names_closure:
        for fixture in info.name2fixturedefs.get(name, ()):
            scope = fixture.scope
            here = getattr(fixture.func, "__module__", None) == item.module.__name__
            if scope in ("module", "class", "package") or (scope == "session" and here):
                return True
    return False


def _name_the_groups(items) -> None:
    """Append each test's group to its id, which is what --dist loadgroup schedules by. pytest-xdist 3.8.0 writes
    it to ``item._nodeid`` (xdist/remote.py, WorkerInteractor.pytest_collection_modifyitems), which pytest 9.2 no
    longer reads: its ``Node.nodeid`` is ``str(item._id)`` (_pytest/nodes.py), so every group would be ignored
    and a shared fixture made on both workers."""
    from _pytest.nodeid import NodeId

    for item in items:
        names = sorted({str(mark.args[0]) for mark in item.iter_markers("xdist_group")})
        if names and not item.nodeid.endswith("@" + "_".join(names)):
            item._id = NodeId.parse(f"{item.nodeid}@{'_'.join(names)}")


@pytest.hookimpl(tryfirst=True)  # before pytest-xdist's own, which reads the groups
def pytest_collection_modifyitems(config, items):
    for item in items:
        params = item.callspec.params.values() if hasattr(item, "callspec") else ()
        # test_gzphysics.py, test_gazebo_models.py: DART under Gazebo's settings, in a program make test builds and
        # make test-fast does not
        slow_file = item.path.name in (
            "test_dart_engine.py",
            "test_new_engines.py",
            "test_gzphysics.py",
            "test_gazebo_models.py",
        )
        if slow_file or any(isinstance(v, str) and v in SLOW_ENGINES for v in params):
            item.add_marker(pytest.mark.slow)
        # make test runs the suite on two pytest-xdist workers with --dist loadgroup: the tests of a module that
        # share a fixture go to one worker (its module's group) unless they name a group of their own
        if _isolated_engine(item, params):
            # one worker steps Newton and Genesis: each process pays an engine's start (its venv's imports, Genesis'
            # kernels) once, about a minute and a half for Genesis on two cores
            item.add_marker(pytest.mark.xdist_group(ISOLATED_ENGINES))
        elif item.get_closest_marker("xdist_group") is None and _shares_a_fixture(item):
            item.add_marker(pytest.mark.xdist_group(item.module.__name__))
    if getattr(config.option, "loadgroup", False):  # on an xdist worker of --dist loadgroup
        _name_the_groups(items)


def study_config(*files: str, overrides: dict | None = None) -> dict:
    """The default config.yaml, then ``files`` (paths from the checkout's root) merged over it, read
    as the workflow reads them (simpick.config.read_study: deep merge, every value checked, defaults
    filled in); a new mapping on every call."""
    from simpick.config import read_study

    return read_study([ROOT / "config.yaml", *(ROOT / f for f in files)], overrides)[1]


def tiny_config(workdir: Path | None = None) -> dict:
    """The default study cut down to seconds: 2 terrains x 1 short motion, 2 real segments."""
    config = study_config()
    config["terrains"] = {"grass": config["terrains"]["grass"], "bumps": config["terrains"]["bumps"]}
    config["terrains"]["bumps"]["pieces_per_tile"] = 2
    config["motions"] = {"straight": dict(config["motions"]["straight"], duration=1.5)}
    config["cpu_load"].update(terrain="grass", duration=0.5, repeats=1, robots_intense=2)
    config["validation"]["cases"] = {
        "gain_v0.5_w0.5_mu0.8": {"kind": "yaw_gain", "v": 0.5, "w": 0.5, "mu": 0.8, "duration": 2.0},
        "rest_mu0.8": {"kind": "rest", "mu": 0.8, "duration": 1.5},
    }
    config["robot"]["urdf"] = str(ROOT / config["robot"]["urdf"])
    config["reference"]["published"] = str(ROOT / config["reference"]["published"])
    config["qualitative"] = str(ROOT / config["qualitative"])
    # no simulator profiles: the engines' tests stay seconds long; tests/test_simulators.py runs them
    config["simulators"] = {"catalog": str(ROOT / "resources/simulators/simulators.yaml"), "run": []}
    segments = pd.read_csv(ROOT / config["real_data"]["segments"], dtype={"run": str})
    segments = segments[segments.terrain_class == "flooring"].groupby("kind").head(1).copy()
    segments["duration"] = 1.0
    if workdir is not None:
        path = workdir / "segments.csv"
        segments.to_csv(path, index=False)
        config["real_data"]["segments"] = str(path)
    return config


def snakemake(workdir: Path, *args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    cmd = SNAKEMAKE + [
        "--snakefile",
        str(ROOT / "Snakefile"),
        "--directory",
        str(workdir),
        "--configfile",
        str(workdir / "config.yaml"),
        "--cores",
        "2",
        *args,
    ]
    return subprocess.run(
        cmd, capture_output=True, text=True, cwd=workdir, env=os.environ | {"PYTHONHASHSEED": "0"} | (env or {})
    )


def planned_jobs(workdir: Path, env: dict | None = None) -> list[tuple[str, str]]:
    """(rule, wildcards) of every job a dry run plans (``env``: extra environment variables)."""
    out = snakemake(workdir, "-n", env=env)
    assert out.returncode == 0, out.stderr
    text = out.stdout + out.stderr
    jobs = []
    for block in re.split(r"\n(?=(?:local)?rule \w+:)", text):
        m = re.match(r"(?:local)?rule (\w+):", block.strip())
        if m:
            w = re.search(r"wildcards: (.*)", block)
            jobs.append((m.group(1), w.group(1).strip() if w else ""))
    return jobs


def write_config(workdir: Path, config: dict) -> None:
    (workdir / "config.yaml").write_text(yaml.safe_dump(config, sort_keys=False))


# The tiny study is run once per test session and read by every test that needs its outputs; a test that edits
# the study (its config, its results) works on a copy (copy_study). Under pytest-xdist a session fixture is a
# worker's: the tests that use it carry @pytest.mark.xdist_group(TINY_STUDY) and so run on one worker (make test:
# --dist loadgroup), which makes the run once.
TINY_STUDY = "tiny_study"


@pytest.fixture(scope="session")
def tiny_study(tmp_path_factory) -> tuple[Path, dict]:
    """(working directory, config) of the tiny study (:func:`tiny_config`) run to the end; read it, never edit it."""
    workdir = tmp_path_factory.mktemp("tiny_study")
    config = tiny_config(workdir)
    write_config(workdir, config)
    run = snakemake(workdir)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    return workdir, config


def copy_study(workdir: Path, target: Path) -> Path:
    """A finished study's working directory copied to ``target`` with its files' times and Snakemake's records
    (.snakemake/), so that the copy is as up to date as the original: nothing reruns in it unless edited."""
    import shutil

    shutil.copytree(workdir, target, symlinks=True, ignore=shutil.ignore_patterns("locks", "incomplete"))
    return target


# --- dataset folders in the BorealTC layout, made up in the test ---


def synthetic_run(
    seconds: float = 12.0, imu_hz: float = 100.0, cmd_hz: float = 6.5, seed: int = 0, gain: float = 0.6
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """One run as (imu, pro) frames in BorealTC's columns: 0.3 m/s straight, then a left turn
    (wheels 0.1 / 0.4 m/s) whose measured yaw rate is ``gain`` x the commanded one."""
    import numpy as np

    rng = np.random.default_rng(seed)
    tp = np.arange(int(round(seconds * cmd_hz))) / cmd_hz
    turning = tp >= seconds / 2
    vel_l, vel_r = np.where(turning, 0.1, 0.3), np.where(turning, 0.4, 0.3)
    pro = pd.DataFrame(
        {"time": tp, "curL": 5 + rng.random(len(tp)), "curR": 5 + rng.random(len(tp)), "velL": vel_l, "velR": vel_r}
    )
    ti = np.arange(int(round(seconds * imu_hz))) / imu_hz
    held = np.clip(np.searchsorted(tp, ti, side="right") - 1, 0, len(tp) - 1)
    n = len(ti)
    imu = pd.DataFrame(
        {
            "time": ti,
            "wx": 0.01 * rng.standard_normal(n),
            "wy": 0.01 * rng.standard_normal(n),
            "wz": gain * (vel_r - vel_l)[held] / 0.555 + 0.01 * rng.standard_normal(n),
            "ax": 0.2 * rng.standard_normal(n),
            "ay": 0.2 * rng.standard_normal(n),
            "az": 9.81 + 0.2 * rng.standard_normal(n),
        }
    )
    return imu, pro


def write_dataset(root: Path, runs: dict[str, list[str]], **options) -> Path:
    """``root/<CLASS>/imu_<run>.csv`` + ``pro_<run>.csv`` for every class and run id given."""
    for i, (cls, ids) in enumerate(runs.items()):
        (root / cls).mkdir(parents=True, exist_ok=True)
        for j, run in enumerate(ids):
            imu, pro = synthetic_run(seed=10 * i + j, **options)
            imu.to_csv(root / cls / f"imu_{run}.csv", index=False)
            pro.to_csv(root / cls / f"pro_{run}.csv", index=False)
    return root
