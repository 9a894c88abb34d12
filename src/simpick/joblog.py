"""How every job runs: its stderr to its log, a bad input as one clear line (``scripts/*.py`` only
unpack ``snakemake.input/params/output`` into one job function of a stage, inside :class:`logged`).

A job that ends well closes its log with one line of what it cost, :data:`COST` (CPU seconds of the
job's process and the children it waited for, from its start, imports included, and its wall seconds
since the process started). Snakemake's ``benchmark:`` file samples a job's CPU every half second for
15 s and every 30 s after, so it misses a job's last seconds and most of a short job; the benchmark of
a study's overhead (bench/packing.py) reads this line instead.
"""

from __future__ import annotations

from pathlib import Path

from simpick.errors import InputError

COST = "simpick: job cost: cpu_s={cpu:.3f} wall_s={wall:.3f}"


def read_cost(text: str) -> tuple[float, float] | None:
    """(cpu_s, wall_s) of a job log's closing cost line (:data:`COST`), or None where it has none (a failed job,
    or a script outside :class:`logged`)."""
    import re

    pattern = re.escape(COST).replace(r"\{cpu:\.3f\}", r"([\d.]+)").replace(r"\{wall:\.3f\}", r"([\d.]+)")
    found = re.search(f"^{pattern}$", text, re.M)
    return None if found is None else (float(found.group(1)), float(found.group(2)))


def cost_line() -> str:
    """This process's cost so far, as :data:`COST` formats it."""
    import resource
    import time

    import psutil

    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime
    return COST.format(cpu=cpu, wall=time.time() - psutil.Process().create_time())


class logged:
    """Send a job's stderr to its log; report a bad input as one clear line, not a traceback."""

    def __init__(self, log_path: str, append: bool = False):
        self.log_path = Path(log_path)
        # append: a process that takes over a job's work (simpick.simulate.jobs.take_over) goes on with its log
        self.mode = "a" if append else "w"

    def __enter__(self):
        import sys

        self.log_path.parent.mkdir(parents=True, exist_ok=True)
        self._stderr = sys.stderr
        sys.stderr = self.log_path.open(self.mode)
        return self

    def __exit__(self, exc_type, exc, tb):
        import sys

        log, sys.stderr = sys.stderr, self._stderr
        if exc_type is not None and issubclass(exc_type, InputError):
            print(f"simpick: {exc}", file=log)
            print(f"simpick: {exc}", file=sys.stderr)
            log.close()
            raise SystemExit(1)
        if exc_type is not None:
            import traceback

            traceback.print_exception(exc_type, exc, tb, file=log)
        else:
            print(cost_line(), file=log)
        log.close()
        return False
