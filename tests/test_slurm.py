"""The tiny study through a real SLURM scheduler (profiles/slurm) gives what the local run gives.

The local run is the session's tiny study (conftest.tiny_study); only the run through the scheduler is made here.

Needs a running SLURM whose jobs see this file system: ``cluster/local-slurm.sh start`` (root)
starts a one-node cluster on this machine; ``.ci/run`` does so and sets SIMPICK_SLURM=1, which
makes this test mandatory (it fails instead of skipping when the scheduler cannot be reached).
Without SIMPICK_SLURM the test is skipped, with the reason in pytest's summary (-rs).
"""

import os
import shutil
import subprocess
import time

import pandas as pd
import pytest

from conftest import ROOT, TINY_STUDY, snakemake, tiny_config, write_config
from simpick.simulate.traces import read_trace

# every test here runs Snakemake, and compares with the session's tiny study (run once, on one worker)
pytestmark = [pytest.mark.workflow, pytest.mark.xdist_group(TINY_STUDY)]

REQUIRED = os.environ.get("SIMPICK_SLURM") == "1"


def _slurm_up() -> str | None:
    """None if a SLURM node is ready for jobs, else why not."""
    if shutil.which("sinfo") is None:
        return "sinfo not found (no SLURM client installed)"
    out = subprocess.run(["sinfo", "-h", "-o", "%t"], capture_output=True, text=True)
    if out.returncode != 0:
        return f"sinfo failed: {out.stderr.strip()[:200]}"
    if not any(state.strip("*~#") in {"idle", "mix", "alloc"} for state in out.stdout.split()):
        return f"no SLURM node is up (sinfo: {out.stdout.strip()})"
    return None


@pytest.fixture(scope="module")
def runs(tmp_path_factory, tiny_study):
    problem = _slurm_up()
    if problem:
        if REQUIRED:
            pytest.fail(
                f"SIMPICK_SLURM=1 but SLURM is not usable: {problem}; start it with cluster/local-slurm.sh start"
            )
        pytest.skip(f"no SLURM here ({problem}); cluster/local-slurm.sh start, then SIMPICK_SLURM=1")
    workdir = tmp_path_factory.mktemp("slurm")
    config = tiny_config(workdir)
    config["real_data"]["segments"] = str(tiny_study[0] / "segments.csv")  # the very same cases
    write_config(workdir, config)
    start = time.perf_counter()
    run = snakemake(
        workdir,
        "--profile",
        str(ROOT / "profiles" / "slurm"),
        # the test cluster has no accounting database and no accounts (cluster/local-slurm.sh)
        "--slurm-status-command",
        "squeue",
        "--slurm-no-account",
        # the plugin waits 40 s after each round of submissions before it asks for their states, and 10 s more
        # each round nothing finished: sized for a busy cluster. On the one-node test cluster every layer of the
        # study's graph would wait that long (the run took 860 s for a 3-minute study); ask after 1 s instead.
        "--slurm-init-seconds-before-status-checks",
        "1",
    )
    assert run.returncode == 0, "slurm:\n" + run.stdout[-3000:] + run.stderr[-3000:]
    return {
        "local": (tiny_study[0], None, ""),
        "slurm": (workdir, time.perf_counter() - start, run.stdout + run.stderr),
    }


def test_every_job_went_through_the_scheduler(runs):
    workdir, _, log = runs["slurm"]
    submitted = log.count("submitted with SLURM jobid")
    local_jobs = log.count("localrule ")
    assert submitted > 20 and local_jobs == 1, (submitted, local_jobs)  # only rule all runs locally
    assert any((workdir / ".snakemake" / "slurm_logs").rglob("*.log"))


def test_slurm_results_equal_the_local_ones(runs):
    local, slurm = runs["local"][0], runs["slurm"][0]
    traces = sorted(p.relative_to(local) for p in (local / "results").rglob("*.parquet"))
    assert len(traces) >= 20
    assert traces == sorted(p.relative_to(slurm) for p in (slurm / "results").rglob("*.parquet"))
    for path in traces:
        a, meta_a = read_trace(local / path)
        b, meta_b = read_trace(slurm / path)
        pd.testing.assert_frame_equal(a, b, check_exact=True, obj=str(path))
        assert meta_a["steps"] == meta_b["steps"] and meta_a["config_hash"] == meta_b["config_hash"]
    # figures computed from the traces; timing columns (steps_per_s, wall) legitimately differ
    for path, keys, values in (
        (
            "results/validation/summary.csv",
            ["engine", "case", "quantity"],
            ["engine_value", "analytic_value", "passed"],
        ),
        ("results/metrics/lab/imu_errors.csv", None, None),
        ("results/metrics/segments/per_test.csv", None, None),
    ):
        a, b = pd.read_csv(local / path), pd.read_csv(slurm / path)
        if keys:
            a, b = a.set_index(keys)[values].sort_index(), b.set_index(keys)[values].sort_index()
        pd.testing.assert_frame_equal(a, b, obj=path)
    for path in ("results/report/report.html", "results/report/report.pdf"):
        assert (slurm / path).stat().st_size > 0
