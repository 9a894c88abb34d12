"""Sources of cases: one module per kind of source, behind one interface (:class:`base.Source`).

A source yields a case table: engine-independent (group, name) rows, each simulated once per model
of the source and compared with its reference. Four kinds, one module each:

- ``lab`` (:mod:`simpick.sources.lab`): the paper's tests, terrain x motion, against its Table 8/9;
- ``segments`` (:mod:`simpick.sources.segments`): constant-command segments of real runs (the
  committed table, or one derived from a dataset folder), against each segment's window statistics;
- ``replay`` (:mod:`simpick.sources.replay`): a dataset folder's runs, driven by their recorded wheel
  speeds and compared with the real log window by window;
- ``own`` (:mod:`simpick.sources.own`): the user's own logs, replayed like a dataset folder's runs.

The plan (:mod:`simpick.plan`) reaches a kind through :func:`module` (a source's cases, inputs and
parameters); a job reaches the code of its source's kind through :func:`module` by name, so a job's
code version (:mod:`simpick.codeversion`) holds only its own kind's functions, which the rule names as
roots (:func:`entry`): an edit to one source module reruns that source's jobs, no other's.

A new kind of source is a module here with the names of :class:`base.Source`, an entry in
:data:`KINDS`, and, if its cases come from a new kind of input, an import rule (``rules/real.smk``).
"""

from __future__ import annotations

import importlib

# kind -> module; only these names are imported, by name (not at load time: see the module docstring)
KINDS = {
    "lab": "simpick.sources.lab",
    "segments": "simpick.sources.segments",
    "replay": "simpick.sources.replay",
    "own": "simpick.sources.own",
}


def module(kind: str):
    """The module of a kind of source (a job's ``params["kind"]``, or a source's kind when planning)."""
    try:
        return importlib.import_module(KINDS[kind])
    except KeyError:
        raise ValueError(f"no source kind {kind!r}; known: {sorted(KINDS)}") from None


def entry(kind: str, function: str) -> str:
    """``"module:function"`` of the job-side function a kind's jobs run (``prepare_case``,
    ``compare``): the root of their code version. A kind whose cases are driven as another
    kind's (own logs are replayed) names that kind as its ``DRIVEN``: its jobs run that module."""
    return f"{KINDS[module(kind).DRIVEN]}:{function}"
