"""Sources of cases: one module per kind of source, behind one interface (:class:`base.Source`).

A source yields a case table: engine-independent (group, name) rows, each simulated once per model
of the source and compared with its reference. A source module says, at planning time, what its
cases are and what their jobs read and depend on; the jobs drive a case by its kind's function in
the simulate stage (:data:`simpick.simulate.jobs.PREPARE`) and compare its traces by its kind's
function in the compare stage (:data:`simpick.compare.kinds.BY_KIND`). Five kinds, one module each:

- ``lab`` (:mod:`simpick.sources.lab`): the paper's tests, terrain x motion, against its Table 8/9;
- ``segments`` (:mod:`simpick.sources.segments`): constant-command segments of real runs (the
  committed table, or one derived from a dataset folder), against each segment's window statistics;
- ``replay`` (:mod:`simpick.sources.replay`): a dataset folder's runs, driven by their recorded wheel
  speeds and compared with the real log window by window;
- ``own`` (:mod:`simpick.sources.own`): the user's own logs, replayed like a dataset folder's runs;
- ``drive`` (:mod:`simpick.sources.drive`): a DRIVE folder's sessions (``drive_dir``), each step a unit
  replayed from its warm-up by its measured wheel speeds, paired by its command.

A kind is *driven* (its ``DRIVEN``) as itself or as another kind whose jobs it shares (``own`` as
``replay``); DRIVE's steps are driven as ``steps``, a step unit's replay, which any dataset whose reader
yields step units shares.

The plan (:mod:`simpick.plan`) reaches a kind through :func:`module` (a source's cases, inputs and
parameters); no job imports this package.

A new kind of source is a module here with the names of :class:`base.Source` and an entry in
:data:`KINDS`; a new way of driving or comparing its cases, an entry in ``PREPARE`` and ``BY_KIND``;
if its cases come from a new kind of input, an import rule (``rules/real.smk``).
"""

from __future__ import annotations

import importlib

# kind -> module, imported by name when the plan asks for a kind
KINDS = {
    "lab": "simpick.sources.lab",
    "segments": "simpick.sources.segments",
    "replay": "simpick.sources.replay",
    "own": "simpick.sources.own",
    "drive": "simpick.sources.drive",
}


def module(kind: str):
    """The module of a kind of source (a job's params' ``kind``, or a source's kind when planning)."""
    try:
        return importlib.import_module(KINDS[kind])
    except KeyError:
        raise ValueError(f"no source kind {kind!r}; known: {sorted(KINDS)}") from None
