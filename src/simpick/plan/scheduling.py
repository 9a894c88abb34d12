"""How the rules order and bound the study's jobs: each job's Snakemake priority from the measured cost
table (:mod:`simpick.plan.costs`), an engine's measured seconds in this study, and a job's time limit.

It stands apart from what a job depends on: a priority or a time limit changes when jobs start and when
they are stopped, never what they compute, and it rests on measurements rather than on the config.
"""

from __future__ import annotations

import os
import threading

from simpick.engines.simulators import engine_of
from simpick.plan import costs

# Measured wall time per kind of job and model (bench/job_costs.py writes it from a finished study)
COST_TABLE = "resources/engines/job_costs.csv"


class CostPlanning:
    """Priorities and time limits (a mixin of :class:`simpick.plan.Plan`, set up after its sources)."""

    def __init__(self):
        basedir = self.basedir
        # Measured cost of each kind of job per model: the longest start first (simpick.plan.costs)
        self.costs = costs.load(os.path.join(basedir, COST_TABLE))

    def job_priority(self, job: str, engine: str) -> int:
        """Snakemake priority of a validate, cpu_load or simulate job of ``engine``: its measured wall
        seconds (simpick.plan.costs), so that on few cores the long jobs start first."""
        return costs.priority(self.costs, job, engine_of(engine))

    def simulate_priority(self, source: str, engine: str, cases: int) -> int:
        """A simulate job's priority: the measured cost of a case of its source's kind (lab, segments, replay)
        times the job's ``cases``."""
        kind = self.sources[source]["kind"]
        return costs.priority(self.costs, "replay" if kind == "own" else kind, engine_of(engine), cases)

    def engine_seconds(self, engine: str) -> float | None:
        """Measured wall seconds of one engine's jobs in this study (validation, CPU load, the lab cases,
        the committed segments), from the cost table; None where a kind of job is unmeasured."""
        cases = {"validate": 1, "cpu_load": 1, "lab": len(self.terrains) * len(self.motions)}
        if "segments" in self.sources:
            cases["segments"] = len(self.sources["segments"]["cases"])
        if any((kind, engine) not in self.costs for kind in cases):
            return None
        return sum(n * self.costs[(kind, engine)] for kind, n in cases.items())

    def simulate_runtime(self, cases: int) -> int:
        """Minutes for a job of ``cases`` cases: each is stopped by the watchdog at health.timeout
        (its hard fallback 30 s later)."""
        return cases * (1 + int(self.settings.health.timeout) // 60)


def release_scheduler_timers() -> int:
    """Cancel the threading.Timer threads pending in Snakemake's process; returns how many.

    Called when the workflow has finished (the Snakefile's ``onsuccess`` and ``onerror``). After every
    scheduling pass Snakemake's job scheduler starts a non-daemon ``threading.Timer`` of the job rate limiter's
    timespan (snakemake 9.27.1, scheduling/job_scheduler.py:394-397 and ``_schedule_reevalutation``, :410-414),
    whose only action is to wake the scheduler again. The interpreter waits for non-daemon threads before it
    exits, so every run ended up to one timespan (1 s by default: the ``--max-jobs-per-timespan`` default,
    cli.py:1490) after its last job; measured on this machine after a weight edit, 1.0 s of a 14.5 s run spent
    waiting on it. The option cannot be set below a second: its parser (settings/types.py:66) reads "200ms"
    as 200 minutes, the alternation matching "m" first. Once the workflow has finished nothing is left to wake
    up, so the timers are cancelled here. The project's own code starts no timer in this process (the
    watchdog's runs inside the jobs)."""
    timers = [t for t in threading.enumerate() if isinstance(t, threading.Timer)]
    for timer in timers:
        timer.cancel()
    return len(timers)
