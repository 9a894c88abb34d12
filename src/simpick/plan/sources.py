"""The study's sources of cases and the simulate, compare and summarise units over them.

A source yields a case table: engine-independent (group, name) rows, each simulated once per model of
the source; its kind's module (:mod:`simpick.sources`: lab, segments, replay, own) says what a case's
simulation needs and how the source's traces are compared. ``lab``: terrain x motion (config);
``segments``: terrain class x segment id (the committed table); a dataset folder's name or ``own``:
terrain class x run (its canonical logs). A case's trace is
``results/traces/<source>/<model>/<group>/<name>.parquet``; the source's tables lie in
``results/metrics/<source>/``. A dataset folder's derived segment table (rule real_segments, a
checkpoint) is a source too, ``<dataset>-segments``: its cases are known once the table is written.

This is the plan's bulk (most jobs are a source's cases), kept apart
from where the data come from (:mod:`simpick.plan.realdata`) and from what the answer rests on
(:mod:`simpick.plan.answer`): here only which sources there are, their units, and each unit's inputs,
parameters and code.
"""

from __future__ import annotations

import csv
import re

from simpick.simulate.jobs import PREPARE
from simpick.sources import base as source_base
from simpick.sources import lab as lab_source
from simpick.sources import module as source_module
from simpick.sources.base import canonical

# The unit of work of the simulate family: one case, except for a batched source, whose job runs several cases
# on one model in one process. A job's fixed cost (Snakemake's own, about 0.4 s of CPU, and the job's
# imports, about 0.8 s) is paid once per job; a lab case takes about 3 s of CPU, a segment less.
# "source": every case of the source in one job per model (the committed segments: 18 short runs);
# "group": a group's cases in one job per model and group (the lab: a terrain's motions, whose strip is
# the job's one terrain input), every group having the same case names.
# "class": a terrain class's cases in one job per model and class, a rule per class (a replayed dataset
# folder's runs and own logs, keyed by their kind: the source is named after its dataset). Each job reads
# its class's logs and its class's ground; the full replay of the shared BorealTC's 29 runs is 5 jobs per
# model instead of 29. A source whose cases are known only after a checkpoint (a derived segment table)
# stays one case per job.
BATCHED = {"lab": "group", "segments": "source"}
BATCHED_KINDS = {"replay": "class", "own": "class"}


class SourcePlanning:
    """The sources of cases and their units (a mixin of :class:`simpick.plan.Plan`, set up after its
    models and real data)."""

    def __init__(self):
        self.sources = {"lab": self._spec("lab", self.engines, lab_source.cases(self.settings))}
        if self.real_data_robot:
            self.sources["segments"] = self._spec(
                "segments",
                self.real_models,
                [(c, s) for c, ids in self.segments.items() for s in ids],
                table=self.settings.real_data.segments,
            )
        for source, cases in self.replay_cases.items():
            self.sources[source] = self._spec("own" if source == "own" else "replay", self.real_models, cases)
        # Not for the folder the committed table was derived from (dataset ``dataset``): its derived
        # table is the committed one (maintain_segments keeps them equal; tests/test_realdata checks a
        # fresh derivation against it), already simulated as source "segments"; as a source of its own
        # it would simulate the same 18 segments x 6 models a second time (108 jobs of the full replay).
        self.derived = None
        if self.replay_set and self.replay_set.name != self.dataset:
            self.derived = f"{self.replay_set.name}-segments"  # no dataset name ends so and is also replayed
            self.sources[self.derived] = self._spec(
                "segments",
                self.real_models,
                None,
                table=f"{self.replay}/segments.csv",
                classes=list(self.replay_set.classes),
            )

    @staticmethod
    def _spec(kind, models, cases, **more):
        return {"kind": kind, "models": models, "group": source_module(kind).GROUP, "cases": cases, **more}

    def source_of(self, source):
        """The module of a source's kind (simpick.sources)."""
        return source_module(self.sources[source]["kind"])

    def source_cases(self, source):
        """A source's (group, name) cases; a derived segment table's once its checkpoint has run."""
        cases = self.sources[source]["cases"]
        if cases is not None:
            return cases
        with open(self._derived_table(), newline="") as handle:
            return [(row["terrain_class"], row["segment"]) for row in csv.DictReader(handle)]

    def source_traces(self, source):
        return [
            f"results/traces/{source}/{model}/{group}/{name}.parquet"
            for model in self.sources[source]["models"]
            for group, name in self.source_cases(source)
        ]

    @staticmethod
    def metrics_file(source, table):
        return f"results/metrics/{source}/{table}.csv"

    # --- the simulate family ---

    def simulate_units(self):
        """(name, output patterns, log stem, fixed values) for each rule of the simulate family: one rule over
        the {source} wildcard for the one-case units, one per batched source (:data:`BATCHED`)."""
        single = [s for s in self.sources if self.batching(s) is None]
        units = []
        if single:
            one = "{source}/{engine}/{group}/{name}"
            units.append(("simulate", [f"results/traces/{one}.parquet"], one, {"sources": single}))
        for source in [s for s in self.sources if self.batching(s) == "class"]:
            classes: dict[str, list[str]] = {}
            for group, name in self.sources[source]["cases"]:
                classes.setdefault(group, []).append(name)
            for group, names in classes.items():
                outputs = [f"results/traces/{source}/{{engine}}/{group}/{name}.parquet" for name in names]
                fixed = {"source": source, "group": group, "names": names}
                rule = "simulate_" + re.sub(r"\W", "_", f"{source}_{group}")
                units.append((rule, outputs, f"{source}/{{engine}}/{group}", fixed))
        for source in sorted(set(BATCHED) & set(self.sources)):
            cases = self.sources[source]["cases"]
            if BATCHED[source] == "source":
                outputs = [f"results/traces/{source}/{{engine}}/{group}/{name}.parquet" for group, name in cases]
                units.append(
                    (f"simulate_{source}", outputs, f"{source}/{{engine}}", {"source": source, "cases": cases})
                )
                continue
            groups: dict[str, list[str]] = {}
            for group, name in cases:
                groups.setdefault(group, []).append(name)
            names = next(iter(groups.values()), [])
            if any(found != names for found in groups.values()):
                raise ValueError(f"source {source}: its groups' cases differ, so one rule cannot run each group's")
            outputs = [f"results/traces/{source}/{{engine}}/{{group}}/{name}.parquet" for name in names]
            fixed = {"source": source, "names": names, "groups": list(groups)}
            units.append((f"simulate_{source}", outputs, f"{source}/{{engine}}/{{group}}", fixed))
        return units

    def batching(self, source):
        """How a source's cases are batched into simulate jobs (:data:`BATCHED`), None for one case a job."""
        if source in BATCHED:
            return BATCHED[source]
        if self.sources[source]["cases"] is None:  # known only after its checkpoint
            return None
        return BATCHED_KINDS.get(self.sources[source]["kind"])

    def one_case_constraints(self, sources):
        known = [self.sources[s] for s in sources if self.sources[s]["cases"] is not None]
        groups = {g for s in known for g, _ in s["cases"]} | {
            g for s in sources for g in self.sources[s].get("classes", [])
        }
        names = {n for s in known for _, n in s["cases"]}
        # a derived table's segment ids are known only after its checkpoint: any name, the source pins it
        unknown = len(known) < len(sources)
        return {
            "source": "|".join(re.escape(s) for s in sources),
            "group": "|".join(sorted(re.escape(g) for g in groups)),
            "name": "[^/]+" if unknown else "|".join(sorted(re.escape(n) for n in names)),
        }

    def unit_constraints(self, fixed):
        """The wildcard constraints of a simulate rule (:meth:`simulate_units`' fixed values)."""
        if "sources" in fixed:
            return self.one_case_constraints(fixed["sources"])
        if "groups" in fixed:
            return {"group": "|".join(sorted(re.escape(g) for g in fixed["groups"]))}
        return {}

    @staticmethod
    def unit(wildcards, fixed):
        """source, engine, group and the case names of one simulate job; the group is None for a unit over
        several groups (a source batched whole: each case's group is the source's case table's)."""
        if "cases" in fixed:
            return fixed["source"], wildcards.engine, None, [name for _, name in fixed["cases"]]
        if "names" in fixed:
            group = fixed["group"] if "group" in fixed else wildcards.group
            return fixed["source"], wildcards.engine, group, list(fixed["names"])
        return wildcards.source, wildcards.engine, wildcards.group, [wildcards.name]

    def case_inputs(self, source, group, names):
        """The files a unit's cases read (its source module's case_inputs)."""
        return self.source_of(source).case_inputs(self.settings, source, self.sources[source], group, names)

    def model_settings(self, model):
        """A model's settings: an engine's block, a simulator profile's (the plan's, over the catalog) or a
        reference model's (simpick.sources.base.model_settings)."""
        return source_base.model_settings(self.config, model)

    def case_params(self, source, engine, group, names):
        """Everything a unit's cases on one model depend on, and nothing else."""
        spec = self.sources[source]
        return self.source_of(source).case_params(
            self.settings, source, spec, engine, self.model_settings(engine), group, names
        )

    def case_code(self, source, engine):
        """The library code a case runs: simulate_job, the model's adapter, and how its source's kind
        is driven (PREPARE, which simulate_job imports by name: no other kind's code)."""
        return self.script_code("simulate", *self.engine_modules(engine), self.prepare_module(source))

    def prepare_module(self, source):
        """The module that drives a source's cases (simpick.simulate.jobs.PREPARE of its DRIVEN kind)."""
        return PREPARE[self.source_of(source).DRIVEN].split(":")[0]

    def simulation_params(self, engine, terrain, motion_name):
        """Everything one lab-study simulation depends on (simpick.sources.lab; cpu_load's too)."""
        return lab_source.lab_params(self.settings, engine, self.model_settings(engine), terrain, motion_name)

    def cpu_load_params(self, engine):
        """Rule cpu_load's params: the lab case's of its terrain and motion, and the scenarios; validated against
        the job's model (simpick.plan.jobs)."""
        from simpick.plan.jobs import job_params
        from simpick.simulate.cpuload import CpuLoadParams

        cpu = self.settings.cpu_load
        data = self.simulation_params(engine, cpu.terrain, cpu.motion) | {"cpu_load": cpu.model_dump(mode="json")}
        return job_params("cpu_load", CpuLoadParams, data)

    def real_params(self, engine, terrain_class):
        return source_base.real_params(self.settings, engine, self.model_settings(engine), terrain_class)

    # --- compare and summarise ---

    def compare_inputs(self, wildcards):
        """A source's traces and what they are compared with."""
        spec = self.sources[wildcards.source]
        compared = self.source_of(wildcards.source).compare_inputs(self.settings, wildcards.source, spec, spec["cases"])
        return {"traces": self.source_traces(wildcards.source)} | compared

    def compare_settings(self, source):
        return self.source_of(source).compare_settings(self.settings)

    def compare_code(self, source):
        """compare_job and every kind's comparison (simpick.compare.kinds): the same for every source."""
        return self.script_code("compare")

    def summarise_settings(self, source):
        return canonical({"group": self.sources[source]["group"], "statistics": self.statistics_params()})

    def statistics_params(self):
        """How many independent runs an interval, a verdict, a rank or an improvement needs, and at
        what level: the validated ``statistics`` settings, the one rule of every summary (real data,
        calibration, sweep, verdict, report)."""
        return canonical(self.settings.statistics.model_dump())
