"""How every job runs: its stderr to its log, a bad input as one clear line (``scripts/*.py`` only
unpack ``snakemake.input/params/output`` into one job function of a stage, inside :class:`logged`).
"""

from __future__ import annotations

from pathlib import Path

from simpick.errors import InputError


class logged:
    """Send a job's stderr to its log; report a bad input as one clear line, not a traceback."""

    def __init__(self, log_path: str):
        self.log_path = Path(log_path)

    def __enter__(self):
        import sys

        self.log_path.parent.mkdir(parents=True, exist_ok=True)
        self._stderr = sys.stderr
        sys.stderr = self.log_path.open("w")
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
        log.close()
        return False
