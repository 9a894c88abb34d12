"""Laying out the body's second part in a process of its own, forked when the report job starts.

WeasyPrint's import takes about 0.5 s of a report job on this machine and the body's second part about 1 s of
layout; both used to come after the weighing and the HTML (about 1 s), one after the other. A process forked
at the job's start imports WeasyPrint while the job weighs the scores and writes the HTML, then lays out the
part it is sent, beside the job's own layout of the first part (simpick.report.build_report).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path


class LayoutWorker:
    """One forked process that lays out one document (no page footers) when sent it: :meth:`submit`, then
    :meth:`wait`; :meth:`close` ends it whether or not it was used (a job that fails before the PDF)."""

    def __init__(self):
        import multiprocessing

        context = multiprocessing.get_context("fork")
        sys.stdout.flush()
        sys.stderr.flush()  # the child ends with os._exit: nothing buffered here is written twice
        self._conn, child = context.Pipe()
        self._process = context.Process(target=_serve, args=(child,), daemon=True)
        self._process.start()
        child.close()
        self._sent: str | None = None

    def submit(self, document: str, path: str | Path, base_url: str | None) -> None:
        self._conn.send((document, str(path), base_url))
        self._sent = str(path)

    def wait(self) -> None:
        """Wait for the document sent; a failure in the child is raised here, with its message."""
        error = self._conn.recv()
        self._process.join()
        if error:
            raise RuntimeError(f"laying out {self._sent}: {error}")

    def close(self) -> None:
        if self._process.is_alive():
            if self._sent is None:
                try:
                    self._conn.send(None)
                except OSError:
                    pass
            self._process.join(timeout=10)
            if self._process.is_alive():
                self._process.kill()
        self._conn.close()


def _serve(conn) -> None:
    """The child: import WeasyPrint, lay out the one document it is sent (None: nothing to do), answer with
    None or the error's text. It ends with os._exit, so none of the job's exit handlers (the code versions'
    cache) run twice."""
    try:
        import weasyprint  # noqa: F401  (now, while the job weighs and writes the HTML)

        from simpick.report.render import write_pdf

        job = conn.recv()
        if job is not None:
            document, path, base_url = job
            try:
                write_pdf(document, path, base_url=base_url, footers=False)
                conn.send(None)
            except Exception as exc:  # noqa: BLE001  (sent to the job, which raises it)
                conn.send(f"{type(exc).__name__}: {exc}")
    finally:
        conn.close()
        os._exit(0)
