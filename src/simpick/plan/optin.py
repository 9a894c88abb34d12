"""The opt-in engines: registered engines the default study leaves out that a config file of
``config/engines/`` adds, each with the switch that runs it and the time it would add.

It stands apart because it reads files beside the study's config (those configs, the Makefile's
targets) only to tell the report what the study did not run; no job depends on it.
"""

from __future__ import annotations

import os

from simpick.engines import ADAPTERS

# Config files that add engines the default study leaves out (each a --configfile beside config.yaml)
OPT_IN_CONFIGS = "config/engines"


def _make_target(makefile: str, configfile: str) -> str | None:
    """The Makefile target whose recipe runs the study with ``configfile``, if one does."""
    if not os.path.exists(makefile):
        return None
    target = None
    with open(makefile) as handle:
        for line in handle:
            if line[:1] not in ("\t", "#", " ", "\n") and ":" in line and "=" not in line.split(":")[0]:
                target = line.split(":")[0].strip()
            elif line.startswith("\t") and configfile in line and "snakemake" in line:
                return target
    return None


class OptInPlanning:
    """The opt-in engines (a mixin of :class:`simpick.plan.Plan`, set up after its costs)."""

    def __init__(self):
        # Registered engines this study leaves out that an opt-in config file adds (config/engines/):
        # named in the report as not run, with the switch and the time they would add
        self.opt_in = self._opt_in()

    def _opt_in(self):
        """engine -> {switch, seconds, study_seconds} for each registered engine that this study does not
        configure and an opt-in file (config/engines/*.yaml) adds; ``switch`` is the command that runs
        it (with the Makefile target that does where one does), ``seconds`` its jobs' measured wall
        seconds on one core, ``study_seconds`` the configured engines' (None where unmeasured)."""
        import glob

        import yaml

        found = {}
        configured = self.settings.engines.model_fields_set  # the engines the study's config names
        study = [self.engine_seconds(e) for e in self.engines]
        for path in sorted(glob.glob(os.path.join(self.basedir, OPT_IN_CONFIGS, "*.yaml"))):
            relative = os.path.relpath(path, self.basedir)
            with open(path) as handle:
                engines = (yaml.safe_load(handle) or {}).get("engines") or {}
            target = _make_target(os.path.join(self.basedir, "Makefile"), relative)
            switch = f"snakemake --cores 2 --configfile config.yaml {relative}" + (
                f" (make {target})" if target else ""
            )
            for engine in engines:
                if engine in ADAPTERS and engine not in configured and engine not in found:
                    found[engine] = {
                        "switch": switch,
                        "seconds": self.engine_seconds(engine),
                        "study_seconds": None if None in study else round(sum(study), 1),
                    }
        return found
