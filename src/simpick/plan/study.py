"""The study's plan: models, sources of cases, and what each job of the simulate, compare, summarise,
validation, sweep and scores families depends on (:class:`Plan`).

A source yields a case table: engine-independent (group, name) rows, each simulated once per model of
the source; its kind's module (:mod:`simpick.sources`: lab, segments, replay, own) says what a case's
simulation needs and how the source's traces are compared. ``lab``: terrain x motion (config);
``segments``: terrain class x segment id (the committed table); a dataset folder's name or ``own``:
terrain class x run (its canonical logs). A case's trace is
``results/traces/<source>/<model>/<group>/<name>.parquet``; the source's tables lie in
``results/metrics/<source>/``. A dataset folder's derived segment table (rule real_segments, a
checkpoint) is a source too, ``<dataset>-segments``: its cases are known once the table is written.
"""

from __future__ import annotations

import csv
import os
import re
import sys
from collections.abc import Callable

from simpick.codeversion import job_code, modules, script_roots
from simpick.config import Study, plain, timestep_label
from simpick.engines import ADAPTERS, REFERENCE_MODELS, get_engine, unavailable
from simpick.engines.catalog import load_catalog
from simpick.engines.simulators import MODEL_SETTINGS, engine_of, model_name
from simpick.inputs.robot import load_from_config
from simpick.plan import costs
from simpick.plan.calibration import CalibrationPlanning
from simpick.plan.report import ReportPlanning
from simpick.real.datasets import open_dataset_or_exit
from simpick.simulate.jobs import PREPARE
from simpick.sources import base as source_base
from simpick.sources import lab as lab_source
from simpick.sources import module as source_module
from simpick.sources import own as own_source
from simpick.sources import replay as replay_source
from simpick.sources import segments as segments_source
from simpick.sources.base import canonical, model_settings

# The unit of work of the simulate family: one case, except where a source's case table is batched
# by group (the committed segments, per terrain class): 18 short runs, where a job per segment cost
# about 1.2 s of fixed cost each (process, imports, robot) and the default study some 50 s more
# on 2 cores than a job per class sharing one import (measured; see the commit that made this).
BATCHED = {"segments"}


# Measured wall time per kind of job and model (bench/job_costs.py writes it from a finished study)
COST_TABLE = "resources/engines/job_costs.csv"


# Config files that add engines the default study leaves out (each a --configfile beside config.yaml)
OPT_IN_CONFIGS = "config/engines"


def _build_failure(engine: str) -> str:
    """Why an engine's own virtual environment could not be built, where `make engine-venvs` kept pip's
    last error lines (``.venv-<engine>.failed`` beside the venv); empty otherwise."""
    from simpick.engines import isolated

    if engine not in isolated.MODULES:
        return ""
    failed = isolated.venv_python(engine).parents[2] / f".venv-{engine}.failed"
    if not failed.exists():
        return ""
    lines = [line.strip() for line in failed.read_text(errors="replace").splitlines() if line.strip()]
    return f"; its build failed: {' / '.join(lines)}" if lines else ""


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


class PlanError(ValueError):
    """A config the study cannot be planned from (the rules stop before any job, naming it)."""


class Plan(ReportPlanning, CalibrationPlanning):
    """Everything the rules ask of a study, from its validated config (:class:`simpick.config.Study`),
    worked out once at planning time. ``config``: the raw dict Snakemake holds (its ``engines`` and
    ``baselines`` order); ``self.config`` is the validated settings as plain data.

    ``basedir`` is the workflow's folder (scripts/ lie there); ``derived_table`` gives the path of
    the dataset folder's derived segment table once its checkpoint has run (Snakemake's
    ``checkpoints.real_segments.get().output.csv``).
    """

    def __init__(self, config: dict, settings: Study, basedir: str, derived_table: Callable[[], str] | None = None):
        # the validated settings as plain data (defaults filled in), not the raw dict: what the
        # rules pass on and the jobs receive
        self.config = config = plain(settings, config)
        self.settings = settings
        self.basedir = basedir
        self._derived_table = derived_table

        # The study's robot, read again here (the config check has read it and stopped on any
        # problem). The committed segments and a dataset folder were recorded on real_data.robot
        # (BorealTC: a Husky A200): they are compared with the study only when its robot is that one
        # (else the config check has refused every part that rests on them).
        self.robot = load_from_config(config["robot"])
        self.real_data_robot = self.robot.name == (config["real_data"].get("robot") or self.robot.name)

        # Engines this machine cannot run (simpick.engines.unavailable: not installed): the study
        # runs without them, and its report lists them.
        self.unavailable = {e: why + _build_failure(e) for e, why in unavailable(config["engines"]).items()}
        self.engines = [e for e in config["engines"] if e not in self.unavailable]
        if not self.engines:
            raise PlanError(f"none of the configured engines can run here: {self.unavailable}")
        # Simulators as rows (simpick.engines.simulators): each simulator's profiles whose engine this study runs,
        # as models of their own. They run the validation and every real-data source like an engine, never
        # the lab scenario or the CPU load (their engine's figures), and their settings are the catalog's.
        self.catalog = load_catalog(config["simulators"]["catalog"])
        self.simulators, self.simulators_left_out = self._simulators()
        config["profiles"] = {
            model_name(sim, variant): self._profile_settings(sim, variant)
            for sim in self.simulators
            for variant in config["simulators"]["variants"]
        }
        # A profile whose settings are exactly its engine's in this study (MuJoCo and Drake as tuned: every
        # setting simpick's engine block makes is an MJCF attribute or a Drake tag) runs nothing of its own:
        # its figures are the engine's, the same traces (a run is deterministic in its settings).
        # The same holds between profiles: a tuned profile the search left at its shipped settings reads those.
        self.profile_results = {}
        for p, settings in config["profiles"].items():
            same = [
                m
                for m, s in [
                    (engine_of(p), config["engines"].get(engine_of(p))),
                    *((q, config["profiles"][q]) for q in self.profile_results if self.profile_results[q] == q),
                ]
                if s == settings
            ]
            self.profile_results[p] = same[0] if same else p
        self.profiles = [p for p, model in self.profile_results.items() if model == p]
        # Reference models (kinematic, coulomb) join the real-data comparison only, never the scores.
        self.baselines = list(config.get("baselines") or {})
        self.real_models = self.engines + self.profiles + self.baselines
        self.validated = self.engines + self.profiles
        self.terrains = list(config["terrains"])
        self.motions = list(config["motions"])
        self.validation_cases = list(config["validation"]["cases"])

        # --- real robot data ---
        self.dataset = config["real_data"]["dataset"]  # the committed segment table's dataset
        self.real = f"results/real/{self.dataset}"
        # terrain class -> segment ids of the committed table (the config check has made sure it
        # exists; no run ever writes it)
        try:
            self.segments = segments_source.by_class(config["real_data"]["segments"], config["real_data"]["classes"])
        except ValueError as exc:
            raise PlanError(str(exc)) from None

        # Speed-accuracy sweep: timesteps as wildcard labels ("0.5ms")
        self.sweep = config.get("sweep")
        self.sweep_dir = f"results/sweeps/{self.sweep['name']}" if self.sweep else None
        self.sweep_labels = [timestep_label(t) for t in self.sweep["timesteps"]] if self.sweep else []

        # The full replay's dataset folder (--config borealtc_dir=PATH [real_dataset=NAME]), checked
        # now: a folder that is not a dataset, an empty class folder, an unpaired file or a class with
        # no ground model stops the run here with one `simpick:` line each, before any job.
        self.replay_set = None
        if config.get("borealtc_dir"):
            self.replay_set = open_dataset_or_exit(
                config["borealtc_dir"], classes=config["real_data"]["classes"], name=config.get("real_dataset")
            )
        self.replay = f"results/real/{self.replay_set.name}" if self.replay_set else None
        self.runs = replay_source.cases(self.replay_set) if self.replay_set else []

        self.own = "results/real/own"
        self.own_logs = {entry["name"]: entry for entry in config.get("own_logs") or []}

        # The replay sources and their case tables: a source is the dataset folder (its name) or the
        # user's own logs ("own"); a case is one (terrain class, run) whose canonical log lies at
        # results/real/<source>/logs/<class>/<run>.parquet. Each kind of source has its import rule
        # (rules/real.smk); from the log on, every source is one entry of ``sources``.
        # No dataset is called "own" (simpick.real.datasets.RESERVED_NAMES).
        self.replay_cases = {self.replay_set.name: self.runs} if self.replay_set else {}
        if self.own_logs:
            self.replay_cases["own"] = own_source.cases(config)

        self.sources = {"lab": self._spec("lab", self.engines, lab_source.cases(config))}
        if self.real_data_robot:
            self.sources["segments"] = self._spec(
                "segments",
                self.real_models,
                [(c, s) for c, ids in self.segments.items() for s in ids],
                table=config["real_data"]["segments"],
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

        # Measured cost of each kind of job per model: the longest start first (simpick.plan.costs)
        self.costs = costs.load(os.path.join(basedir, COST_TABLE))
        # Registered engines this study leaves out that an opt-in config file adds (config/engines/):
        # named in the report as not run, with the switch and the time they would add
        self.opt_in = self._opt_in()

        # simpick's verdict rests on real runs: none where the study's robot has no real data
        self.verdict = self.verdict_source() in self.sources
        # The real data the first page's answer rests on (rule answer, its figure, the decision tree): the
        # verdict's runs where the study has them, else the DRIVE comparison's steps (--config drive_dir=PATH),
        # which replay the study's own robot; None: no real data of this robot, no answer table.
        self.drive = source_module("drive").root(config) if config.get("drive_dir") else None
        self.answer_source = "verdict" if self.verdict else ("drive" if self.drive else None)
        CalibrationPlanning.__init__(self)
        ReportPlanning.__init__(self)

    # --- sources ---

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

    def real_logs(self, source):
        return [source_base.log_path(source, c, run) for c, run in self.replay_cases[source]]

    @staticmethod
    def metrics_file(source, table):
        return f"results/metrics/{source}/{table}.csv"

    def replay_dataset(self):
        """The replay dataset as the rules see it: name, label, source and declared rates."""
        declared = (self.config["real_data"].get("datasets") or {}).get(self.replay_set.name) or {}
        return {
            "name": self.replay_set.name,
            "folder": str(self.replay_set.folder),
            "label": declared.get("label") or self.replay_set.name,
            "source": declared.get("source") or f"dataset folder {self.replay_set.folder}",
            "declared": {k: declared[k] for k in ("imu_hz", "commands_hz") if declared.get(k)},
        }

    def maintained_table(self, wildcards=None):
        """maintain_segments' inputs: the BorealTC folder's derived table. Asked for on any other
        dataset (or none), it stops the run while the DAG is built, before any job."""
        if self.replay_set is None:
            problem = (
                "maintain_segments derives the committed segment table from the BorealTC folder "
                "(fix: pass --config borealtc_dir=PATH/TO/borealtc)"
            )
        elif self.replay_set.name != self.dataset:
            problem = (
                f"maintain_segments rewrites {self.config['real_data']['segments']}, the table of dataset "
                f"{self.dataset!r}, but {self.replay_set.folder} is dataset {self.replay_set.name!r} (fix: pass "
                f"--config real_dataset={self.dataset} if that folder holds {self.dataset}; its own table is "
                f"{self.replay}/segments.csv)"
            )
        else:
            return {"csv": f"{self.replay}/segments.csv", "provenance": f"{self.replay}/segments.provenance.yaml"}
        print(f"simpick: {problem}", file=sys.stderr)
        sys.exit(1)

    # --- the simulate family ---

    def simulate_units(self):
        """(name, output patterns, fixed values) for each rule of the simulate family; one rule over
        the {source} wildcard for the one-case units, one per group of a batched source."""
        single = [s for s in self.sources if s not in BATCHED]
        units = (
            [("simulate", ["results/traces/{source}/{engine}/{group}/{name}.parquet"], {"sources": single})]
            if single
            else []
        )
        for source in sorted(BATCHED & set(self.sources)):
            groups = {}
            for group, name in self.sources[source]["cases"]:
                groups.setdefault(group, []).append(name)
            for group, names in groups.items():
                outputs = [f"results/traces/{source}/{{engine}}/{group}/{name}.parquet" for name in names]
                units.append(
                    (f"simulate_{source}_{group}", outputs, {"source": source, "group": group, "names": names})
                )
        return units

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

    @staticmethod
    def unit(wildcards, fixed):
        """source, engine, group and the case names of one simulate job."""
        if "names" in fixed:
            return fixed["source"], wildcards.engine, fixed["group"], list(fixed["names"])
        return wildcards.source, wildcards.engine, wildcards.group, [wildcards.name]

    def case_inputs(self, source, group, names):
        """The files a unit's cases read (its source module's case_inputs)."""
        return self.source_of(source).case_inputs(self.config, source, self.sources[source], group, names)

    def case_params(self, source, engine, group, names):
        """Everything a unit's cases on one model depend on, and nothing else."""
        return self.source_of(source).case_params(self.config, source, self.sources[source], engine, group, names)

    def case_code(self, source, engine):
        """The library code a case runs: simulate_job, the model's adapter, and how its source's kind
        is driven (PREPARE, which simulate_job imports by name: no other kind's code)."""
        return self.script_code("simulate", *self.engine_modules(engine), self.prepare_module(source))

    def prepare_module(self, source):
        """The module that drives a source's cases (simpick.simulate.jobs.PREPARE of its DRIVEN kind)."""
        return PREPARE[self.source_of(source).DRIVEN].split(":")[0]

    def job_priority(self, job: str, engine: str) -> int:
        """Snakemake priority of a validate, cpu_load or simulate job of ``engine``: its measured wall
        seconds (simpick.plan.costs), so that on few cores the long jobs start first."""
        return costs.priority(self.costs, job, engine_of(engine))

    def simulate_priority(self, source: str, engine: str) -> int:
        """A simulate job's priority: the measured cost of its source's kind (lab, segments, replay)."""
        kind = self.sources[source]["kind"]
        return self.job_priority("replay" if kind == "own" else kind, engine)

    def engine_seconds(self, engine: str) -> float | None:
        """Measured wall seconds of one engine's jobs in this study (validation, CPU load, the lab cases,
        the committed segments per class), from the cost table; None where a kind of job is unmeasured."""
        jobs = {"validate": 1, "cpu_load": 1, "lab": len(self.terrains) * len(self.motions)}
        if "segments" in self.sources:
            jobs["segments"] = len({group for group, _ in self.sources["segments"]["cases"]})
        if any((kind, engine) not in self.costs for kind in jobs):
            return None
        return sum(n * self.costs[(kind, engine)] for kind, n in jobs.items())

    def _opt_in(self):
        """engine -> {switch, seconds, study_seconds} for each registered engine that this study does not
        configure and an opt-in file (config/engines/*.yaml) adds; ``switch`` is the command that runs
        it (with the Makefile target that does where one does), ``seconds`` its jobs' measured wall
        seconds on one core, ``study_seconds`` the configured engines' (None where unmeasured)."""
        import glob

        import yaml

        found = {}
        configured = set(self.config["engines"])
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

    def simulate_runtime(self, cases: int) -> int:
        """Minutes for a job of ``cases`` cases: each is stopped by the watchdog at health.timeout
        (its hard fallback 30 s later)."""
        return cases * (1 + int(self.config["health"]["timeout"]) // 60)

    def simulation_params(self, engine, terrain, motion_name):
        """Everything one lab-study simulation depends on (simpick.sources.lab; cpu_load's too)."""
        return lab_source.lab_params(self.config, engine, terrain, motion_name)

    def cpu_load_params(self, engine):
        cpu = self.config["cpu_load"]
        return self.simulation_params(engine, cpu["terrain"], cpu["motion"]) | {"cpu_load": canonical(cpu)}

    def real_params(self, engine, terrain_class):
        return source_base.real_params(self.config, engine, terrain_class)

    # --- compare and summarise ---

    def compare_inputs(self, wildcards):
        """A source's traces and what they are compared with."""
        spec = self.sources[wildcards.source]
        compared = self.source_of(wildcards.source).compare_inputs(self.config, wildcards.source, spec, spec["cases"])
        return {"traces": self.source_traces(wildcards.source)} | compared

    def compare_settings(self, source):
        return self.source_of(source).compare_settings(self.config)

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

    # --- validation against analytic mechanics ---

    def _profile_settings(self, simulator: str, variant: str) -> dict:
        """A profile's full adapter settings: the adapter's defaults, the study's robot-model settings of that
        engine (its wheel actuators: simpick.engines.simulators.MODEL_SETTINGS), then the catalog's profile."""
        engine = engine_of(model_name(simulator, variant))
        block = self.config["engines"].get(engine) or {}
        model = {k: value for k, value in block.items() if k in MODEL_SETTINGS.get(engine, ())}
        settings = model | self.catalog.settings(simulator, variant, self.robot.name)
        return get_engine(engine).settings_model.model_validate(settings).model_dump(mode="json")

    def _simulators(self):
        """(simulators whose profiles run, {simulator: why not} for the catalog's others)."""
        wanted = self.config["simulators"]["run"]
        run, out = [], {}
        for name, sim in self.catalog.simulators.items():
            if wanted is not None and name not in wanted:
                out[name] = "not in simulators.run"
            elif sim.engine is None:
                out[name] = sim.not_reproduced
            elif sim.engine in self.unavailable:
                out[name] = f"its engine {sim.engine} cannot run here: {self.unavailable[sim.engine]}"
            elif sim.engine not in self.engines:
                out[name] = f"its engine {sim.engine} is not among this study's engines"
            else:
                run.append(name)
        return run, out

    def simulators_params(self):
        """What rule simulators depends on: which profiles ran and what each reads, the engines beside them,
        and the verdict's statistics and margins (no weight)."""
        return canonical(
            {
                "profile_results": self.profile_results,
                "engines": self.engines,
                "simulators": self.simulators,
                "left_out": self.simulators_left_out,
                "settings_files": {p: f"results/simulators/settings/{p}" for p in self.profile_results},
                "statistics": self.statistics_params(),
                "seed": self.config["seed"],
                "verdict": self.config["verdict"],
            }
        )

    def simulator_settings_params(self):
        """Each run profile's full settings and the robot's wheel links (the files' <gazebo reference>, pairs)."""
        return canonical(
            {
                "profiles": {p: self.config["profiles"][p] for p in self.profile_results},
                "robot": self.robot.name,
                "wheel_links": [w.link for w in self.robot.driven],
            }
        )

    def validation_params(self, engine):
        """What an engine's validation job depends on: the engine's settings, the robot, the timestep
        and the cases (not the IMU model, the health limits or the tolerances)."""
        config = self.config
        return canonical(
            {
                "engine": engine,
                "engine_settings": model_settings(config, engine),
                "physics": {"timestep": config["physics"]["timestep"]},
                "robot": {k: v for k, v in config["robot"].items() if k != "urdf"},
                "cases": {
                    name: {k: v for k, v in case.items() if v is not None}
                    for name, case in config["validation"]["cases"].items()
                },
            }
        )

    def validation_results(self, engines=None):
        """Every case's record of ``engines`` (all; ``"{engine}"``: one job's outputs)."""
        engines = [engines] if isinstance(engines, str) else engines or self.validated
        return [f"results/validation/{e}/{c}.json" for e in engines for c in self.validation_cases]

    def validation_runtime(self):
        """Minutes for an engine's validation job: a case's share as a lab case's (1 + health.timeout
        // 60); the watchdog stops a case at 90 % of its share (simpick.studies.validation.validate_job)."""
        return self.simulate_runtime(len(self.validation_cases))

    # --- the sweep ---

    def sweep_params(self, engine, terrain_class, label):
        """The segments source's job of a class on ``engine`` (case_params) at the sweep point's timestep."""
        params = self.case_params("segments", engine, terrain_class, self.segments[terrain_class])
        dt = dict(zip(self.sweep_labels, self.sweep["timesteps"]))[label]
        return canonical(params | {"physics": params["physics"] | {"timestep": float(dt)}})

    def sweep_code(self, engine):
        """A sweep point's code: its job (which runs the compare stage's code), the model's adapter,
        and how the segments source's cases are driven (no other source's)."""
        return self.script_code(
            "sweep_segments",
            *self.engine_modules(engine),
            self.prepare_module("segments"),
        )

    def sweep_runs(self):
        return [
            f"{self.sweep_dir}/runs/{engine}/{cls}/{label}.csv"
            for engine in self.engines
            for cls in self.segments
            for label in self.sweep_labels
        ]

    # --- what the scores and the verdict rest on ---

    def accuracy_source(self):
        """What the accuracy scores rest on (accuracy.reference in the config): the set of tests
        (lab, segments, replay or own), its dataset, its Eq. 7 totals and the per-test table beside
        them. Only the rules use this; the scores job records it in results/scores/provenance.yaml,
        which is what the report reads."""
        reference = self.config["accuracy"]["reference"]
        if reference == "paper":
            kind, source, dataset = "lab", "lab", None
        elif reference == "own":
            kind, source, dataset = "own", "own", "own"
        elif self.replay_set:
            kind, source, dataset = "replay", self.replay_set.name, self.replay_set.name
        else:
            kind, source, dataset = "segments", "segments", self.dataset
        return {
            "reference": reference,
            "set": kind,
            "dataset": dataset,
            "source": source,
            "errors": self.metrics_file(source, "imu_errors"),
            "per_test": self.metrics_file(source, "per_test"),
        }

    def accuracy_errors(self):
        """The Eq. 7 totals the accuracy scores rest on."""
        return self.accuracy_source()["errors"]

    def verdict_source(self):
        """The real data simpick's verdict rests on: the accuracy scores' real set, else the committed
        segments."""
        src = self.accuracy_source()
        return src["source"] if src["set"] != "lab" else "segments"

    def verdict_source_title(self):
        """How the report names the verdict's real data."""
        if self.sources[self.verdict_source()]["kind"] == "segments":
            label = (self.config["real_data"].get("datasets") or {}).get(self.dataset, {}).get("label") or self.dataset
            return f"committed constant-command segments of {label}"
        return f"full replay of {self.verdict_source()}"

    def verdict_settings(self):
        """What the verdict's tests depend on: no weight (a weight edit reruns the answer, not them)."""
        return canonical(
            {
                "engines": sorted(self.engines),
                "baselines": sorted(self.baselines),
                "statistics": self.statistics_params(),
                "seed": self.config["seed"],
                "accuracy_set": self.accuracy_source()["set"],
                "verdict": self.config["verdict"],
            }
        )

    def _dataset_label(self, name):
        return ((self.config["real_data"].get("datasets") or {}).get(name) or {}).get("label") or name

    def answer_basis(self):
        """The real data the answer rests on, as its sentence names them: the dataset, its unit (a DRIVE
        step, or the step's session where the verdict pairs by session; a real run) and the study's other
        real data, which the report compares in their own section."""
        robot = self.config["robot"].get("label") or self.robot.name
        if self.answer_source not in (None, "verdict"):  # a source whose own comparison the answer rests on
            name = self.config["drive_dataset"]
            return source_module(self.answer_source).answer_basis(self.config, self._dataset_label(name), robot)
        source = self.verdict_source()
        name = self.dataset if self.sources[source]["kind"] == "segments" else source
        label = "own-log" if source == "own" else self._dataset_label(name)
        return {
            "dataset": label,
            "unit": "run",
            "title": self.verdict_source_title(),
            "others": [self._dataset_label(self.config["drive_dataset"])] if self.drive else [],
        }

    def answer_settings(self):
        """What the answer and the paper's ranking with its interval depend on: the weights, and
        the words the sentences use."""
        drive = self.answer_source == "drive"
        return canonical(
            {
                "engines": sorted(self.engines),
                "statistics": self.statistics_params(),
                "weights": self.config["weights"],
                "seed": self.config["seed"],
                "source": self.config["drive_dataset"] if drive else self.verdict_source(),
                "source_title": self.answer_basis()["title"] if drive else self.verdict_source_title(),
                "robot": self.config["robot"].get("label") or self.robot.name,
                "basis": self.answer_basis(),
            }
        )

    def answer_tables(self):
        """The real-data comparison's tables the answer, its figure and the decision tree read, by name:
        the verdict's (results/verdict/) where the study has one, else the comparison of the source the
        answer rests on (DRIVE's, written in the same form beside its outcomes: its source module's
        answer_tables); {} without real data of this robot.
        ``discrimination`` (what the paper's accuracy scores separate) is the verdict's alone."""
        if self.answer_source == "verdict":
            tables = {t: f"results/verdict/{t}.csv" for t in ("outcomes", "mechanics", "metrics", "table")}
            tables["discrimination"] = "results/verdict/discrimination.csv"
            tables["per_test"] = self.metrics_file(self.verdict_source(), "per_test")
            return tables
        if self.answer_source is not None:
            return source_module(self.answer_source).answer_tables(self.config)
        return {}

    def answer_inputs(self, wildcards=None):
        """The comparison's tables the answer reads (answer_tables, less the per-run values only its
        figure draws), and the calibration's turning table where the calibration is part of the study and the
        answer rests on its runs (the DRIVE calibration's table has another form: not read here)."""
        inputs = {k: v for k, v in self.answer_tables().items() if k != "metrics"}
        if self.answer_source == "verdict" and self.calibration and self.calibration.get("enabled"):
            inputs["calibration_turning"] = f"{self.cal_dir}/turning.csv"
        return inputs

    def all_targets(self):
        """What the default target asks for (rule all)."""
        targets = ["results/validation/summary.csv"]
        targets += [self.metrics_file(s, t) for s in self.sources for t in ("imu_errors", "summary")]
        if self.replay_set:
            targets += [
                f"{self.replay}/segments.csv",
                f"{self.replay}/dataset.yaml",
                f"{self.replay}/turning/summary.csv",
            ]
        if self.sweep:
            targets.append(f"{self.sweep_dir}/summary.csv")
        targets += self.calibration_all
        if self.simulators:
            targets += [
                "results/simulators/table.csv",
                "results/simulators/settings",
                "results/simulators/weighted.csv",
                "results/simulators/tree.json",
            ]
        targets += [
            "results/scores/weighted.csv",
            "results/published/table11.csv",
            "results/report/report.html",
            "results/report/report.pdf",
        ]
        return targets

    # --- library code as a rerun trigger ---
    # Snakemake reruns a job when its params change, not when imported library code does: each rule
    # carries the version of the code its job can run (simpick.codeversion): the modules its script
    # imports, what they import wherever the import stands, and what the job reaches by name only
    # (a model's adapter, a source kind's module), which is declared here.

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
        ADAPTERS, REFERENCE_MODELS), every module of simpick.engines named after the engine
        (``<engine>_*``, ``_<engine>*``, a ``<engine>`` package), and the engines' shared base and
        runner. What these import counts too (simpick.codeversion); no other engine's adapter does."""
        engine = engine_of(engine)
        adapter = {**ADAPTERS, **REFERENCE_MODELS}[engine].split(":")[0]
        found = {adapter}
        for name in modules():
            parts = name.split(".")
            if parts[:2] != ["simpick", "engines"] or len(parts) < 3:
                continue
            stem = parts[2].lstrip("_")
            if stem == engine or stem.startswith(f"{engine}_") or parts[2] in ("base", "runner"):
                found.add(name)
        return tuple(sorted(found))
