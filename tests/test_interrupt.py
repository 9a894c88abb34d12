"""A run killed mid-way and restarted ends with the same results as an uninterrupted run."""

import os
import signal
import subprocess
import sys
import time

import pandas as pd
import pytest

from conftest import ROOT, TINY_STUDY, snakemake, tiny_config, write_config
from simpick.simulate.traces import read_trace

# every test here runs Snakemake, against the session's uninterrupted tiny study (conftest.tiny_study)
pytestmark = [pytest.mark.workflow, pytest.mark.xdist_group(TINY_STUDY)]


def start(workdir):
    cmd = [
        sys.executable,
        "-m",
        "snakemake",
        "--snakefile",
        str(ROOT / "Snakefile"),
        "--directory",
        str(workdir),
        "--configfile",
        str(workdir / "config.yaml"),
        "--cores",
        "2",
    ]
    # SIGINT as a user's Ctrl-C delivers it: a process started in the background by a non-interactive
    # shell (nohup, a CI runner's job) inherits SIGINT ignored, and Snakemake would then run on to the end
    return subprocess.Popen(
        cmd,
        cwd=workdir,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )


def traces(workdir):
    return sorted(p.relative_to(workdir) for p in (workdir / "results").rglob("*.parquet"))


@pytest.fixture(scope="module")
def reference(tiny_study):
    """The uninterrupted run: the session's tiny study (read, never edited)."""
    return tiny_study[0]


def interrupt(workdir, how, more_than: int) -> None:
    """Start the study in ``workdir`` and send ``how`` to its process group (Snakemake and its running jobs) once
    more than ``more_than`` traces exist: in the middle of the run. Whatever carries a trace's name afterwards is
    complete and readable (traces are written to a ``.partial`` file and renamed; a truncated one would raise)."""
    proc = start(workdir)
    deadline = time.time() + 120
    while time.time() < deadline and len(traces(workdir)) <= more_than and proc.poll() is None:
        time.sleep(0.05)
    # it got there: a run refused (a lock left by the previous one) writes nothing
    made = len(traces(workdir))
    if made <= more_than:
        proc.kill()
        pytest.fail(f"the run wrote {made} traces, not more than {more_than}, before {how.name} (exit {proc.wait()})")
    os.killpg(proc.pid, how)
    proc.wait(timeout=120)  # a hang guard, not a timing check
    assert proc.returncode != 0, f"the run had finished before {how.name} could interrupt it"
    for path in traces(workdir):
        frame, meta = read_trace(workdir / path)
        assert len(frame) > 0 and meta["config_hash"], path


def test_interrupted_killed_and_restarted_run_equals_an_uninterrupted_one(reference, tmp_path):
    """A run stopped by Ctrl-C (SIGINT) and restarted, the restart killed (SIGKILL) in its middle and restarted
    again, ends with the traces and scores of the uninterrupted run. One run serves both ways of stopping it
    (each was a run of its own, the same cost each): after SIGINT Snakemake releases its lock and the restart
    just runs; after SIGKILL the lock stays, the next run refuses and names --unlock."""
    config = tiny_config(tmp_path)
    config["real_data"]["segments"] = str(reference / "segments.csv")  # the very same cases
    write_config(tmp_path, config)
    interrupt(tmp_path, signal.SIGINT, more_than=1)
    interrupt(tmp_path, signal.SIGKILL, more_than=len(traces(tmp_path)) + 1)
    # a killed Snakemake cannot release its lock; it says so and names --unlock
    refused = snakemake(tmp_path)
    assert refused.returncode != 0 and "--unlock" in refused.stdout + refused.stderr
    assert snakemake(tmp_path, "--unlock").returncode == 0
    restart = snakemake(tmp_path)
    assert restart.returncode == 0, restart.stderr[-3000:]
    assert traces(tmp_path) == traces(reference)
    for rel in traces(reference):
        a, meta_a = read_trace(reference / rel)
        b, meta_b = read_trace(tmp_path / rel)
        pd.testing.assert_frame_equal(a, b, check_exact=True)
        assert meta_a["config_hash"] == meta_b["config_hash"]
    ref = pd.read_csv(reference / "results/scores/weighted.csv", index_col="engine")
    got = pd.read_csv(tmp_path / "results/scores/weighted.csv", index_col="engine")
    qualitative = [c for c in ref.columns if not c.startswith(("real_time", "cpu_"))]
    # rows are in rank order, and the rank includes the timing scores: compare engine by engine
    pd.testing.assert_frame_equal(
        ref[qualitative].drop(columns=["total", "rank"]).sort_index(),
        got[qualitative].drop(columns=["total", "rank"]).sort_index(),
    )
