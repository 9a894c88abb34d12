"""A job's log: its stderr, a bad input as one line, and the line of what the job cost."""

import re
import sys

import pytest

from simpick.errors import InputError
from simpick.joblog import COST, logged

COST_LINE = re.compile(r"^simpick: job cost: cpu_s=([\d.]+) wall_s=([\d.]+)$", re.M)


def test_a_job_that_ends_well_closes_its_log_with_its_cost(tmp_path):
    """The closing line carries the process's CPU (its work included: a busy loop of ~0.2 s CPU shows) and
    its wall time since it started, at least the CPU on one core; stderr goes to the log before it."""
    log = tmp_path / "logs/job.log"
    with logged(str(log)):
        print("a warning", file=sys.stderr)
        total = 0
        for i in range(2_000_000):
            total += i
    text = log.read_text()
    assert text.startswith("a warning\n")
    (match,) = COST_LINE.finditer(text)
    cpu, wall = float(match.group(1)), float(match.group(2))
    assert 0.1 < cpu < 600 and wall > 0.1
    assert COST.split(":")[0] == "simpick"


def test_a_failed_job_writes_no_cost_line(tmp_path):
    """A bad input ends the job with one line naming it and no cost: the benchmark of a study's overhead
    counts only jobs that did their work."""
    log = tmp_path / "job.log"
    with pytest.raises(SystemExit), logged(str(log)):
        raise InputError("results/x.csv", "column 'v' missing")
    text = log.read_text()
    assert text == "simpick: results/x.csv: column 'v' missing\n" and not COST_LINE.search(text)
