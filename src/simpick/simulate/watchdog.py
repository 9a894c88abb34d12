"""Stop a simulation job that hangs, and leave a record that says so.

A soft timer writes a trace marked failed ("hung") and ends the process; it needs the
interpreter, so an engine stuck inside a C call that holds the GIL is ended by the hard
fallback (faulthandler), which kills the process a little later and makes the job fail.
Either way Snakemake's other jobs go on (keep-going in the workflow profile).
"""

from __future__ import annotations

import faulthandler
import os
import sys
import threading
from collections.abc import Callable

HARD_MARGIN_S = 30.0


class Watchdog:
    def __init__(self, seconds: float, on_timeout: Callable[[], None]):
        self.seconds = seconds
        self._timer = threading.Timer(seconds, self._fire, args=(on_timeout,))
        self._timer.daemon = True

    def _fire(self, on_timeout: Callable[[], None]) -> None:
        try:
            on_timeout()
        finally:
            sys.stderr.flush()
            os._exit(0)

    def __enter__(self):
        self._timer.start()
        faulthandler.dump_traceback_later(self.seconds + HARD_MARGIN_S, exit=True)
        return self

    def __exit__(self, *exc):
        self._timer.cancel()
        faulthandler.cancel_dump_traceback_later()
        return False


# A job that declares no runtime (minutes, the rule's resources) gets the lab simulations' default.
DEFAULT_TIMEOUT_S = 300.0
RUNTIME_SHARE = 0.9


def runtime_timeout(runtime_min: float | None) -> float:
    """The hang limit of a job that steps an engine many times (CPU load, a calibration; a sweep
    point's cases each have the simulate job's ``health.timeout``): 90 % of the runtime its rule
    declares, the wall time it is budgeted (and, on a cluster, granted: profiles/slurm), so the job
    records itself as hung before a scheduler that enforces that runtime kills it without a word."""
    if runtime_min is None or float(runtime_min) <= 0:
        return DEFAULT_TIMEOUT_S
    return RUNTIME_SHARE * 60.0 * float(runtime_min)


def hung_reason(timeout: float) -> str:
    """The reason every hung job records (the lab traces' wording: simpick.simulate.jobs.write_hung_trace)."""
    return f"hung: no result after {timeout:g} s of wall time; the job was stopped"
