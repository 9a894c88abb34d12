"""A job's log: its stderr, a bad input as one line, and the line of what the job cost."""

import sys

import pytest

from simpick.errors import InputError
from simpick.joblog import logged, read_cost

JOB = """
import sys
from simpick.joblog import logged
with logged(sys.argv[1]):
    print("a warning", file=sys.stderr)
    total = 0
    for i in range(2_000_000):
        total += i
"""


def test_a_job_that_ends_well_closes_its_log_with_its_cost(tmp_path):
    """The closing line carries the job process's CPU (its work included: a busy loop of ~0.2 s CPU shows) and
    its wall time since it started; stderr goes to the log before it. A job is a
    process of its own, so the job runs in a fresh interpreter: inside the test runner the figure would be the
    whole test session's CPU."""
    import subprocess

    log = tmp_path / "logs/job.log"
    subprocess.run([sys.executable, "-c", JOB, str(log)], check=True)
    text = log.read_text()
    assert text.startswith("a warning\n")
    assert text.count("simpick: job cost:") == 1
    cpu, wall = read_cost(text)
    assert 0.1 < cpu < 60 and wall >= 0.5 * cpu


def test_a_failed_job_writes_no_cost_line(tmp_path):
    """A bad input ends the job with one line naming it and no cost: the benchmark of a study's overhead
    counts only jobs that did their work."""
    log = tmp_path / "job.log"
    with pytest.raises(SystemExit), logged(str(log)):
        raise InputError("results/x.csv", "column 'v' missing")
    text = log.read_text()
    assert text == "simpick: results/x.csv: column 'v' missing\n" and read_cost(text) is None
