"""Library code as a rerun trigger: the code version each rule carries as a param.

Snakemake reruns a job when its params change, not when imported library code does: each rule
carries the version of the code its job can run (:mod:`simpick.codeversion`): the modules its script
imports, what they import wherever the import stands, and what the job reaches by name only (a
model's adapter, a source kind's module), which is declared here. It stands apart from what a job's
settings are: it rests on the source tree, not on the config.
"""

from __future__ import annotations

import os

from simpick.codeversion import job_code, modules, script_roots
from simpick.engines import ADAPTERS, PROFILE_ADAPTERS, REFERENCE_MODELS
from simpick.engines.simulators import engine_of


class CodePlanning:
    """The code versions of the rules' jobs (a mixin of :class:`simpick.plan.Plan`)."""

    def script_code(self, script, *roots):
        """The code version of a job of scripts/<script>.py: the simpick modules the script imports,
        ``roots`` (modules a job reaches by name only: :meth:`engine_modules`, a source kind's
        module) and every module they import."""
        path = os.path.join(self.basedir, "scripts", f"{script}.py")
        return job_code(*script_roots(path), *roots)

    def figure_code(self, rule):
        """A figure rule's code: that of scripts/figure.py, which holds every figure's drawing
        (simpick.report.draw.RULES maps ``rule`` to its function), the same for every figure."""
        return self.script_code("figure")

    @staticmethod
    def engine_modules(engine):
        """The modules of a model that the registry reaches by name only: its adapter (simpick.engines
        ADAPTERS, PROFILE_ADAPTERS, REFERENCE_MODELS), every module of simpick.engines named after the engine
        (``<engine>_*``, ``_<engine>*``, a ``<engine>`` package), and the engines' shared base and
        runner. What these import counts too (simpick.codeversion); no other engine's adapter does."""
        engine = engine_of(engine)
        adapter = {**ADAPTERS, **PROFILE_ADAPTERS, **REFERENCE_MODELS}[engine].split(":")[0]
        found = {adapter}
        for name in modules():
            parts = name.split(".")
            if parts[:2] != ["simpick", "engines"] or len(parts) < 3:
                continue
            stem = parts[2].lstrip("_")
            if stem == engine or stem.startswith(f"{engine}_") or parts[2] in ("base", "runner"):
                found.add(name)
        return tuple(sorted(found))
