# Helpers shared by the rules: the config slices each rule may see, canonicalised.
import csv
import os
import re
import sys

from simpick.config import timestep_label, validate_or_exit
from simpick.robot import load_from_config
from simpick.sources import entry as source_entry, module as source_module
from simpick.sources import lab as lab_source, own as own_source, replay as replay_source, segments as segments_source
from simpick.sources.base import canonical
from simpick.sources import base as source_base

# the typed, validated settings (defaults filled in): what the statistics-bearing rules pass on
SETTINGS = validate_or_exit(config, files=workflow.configfiles)

# The study's robot, read again here (the config check above has read it and stopped on any
# problem). The committed segments and a dataset folder were recorded on real_data.robot (BorealTC:
# a Husky A200): they are compared with the study only when its robot is that one (else the
# config check has refused every part that rests on them).
ROBOT = load_from_config(config["robot"])
REAL_DATA_ROBOT = ROBOT.name == (config["real_data"].get("robot") or ROBOT.name)

# Engines this machine cannot run (simpick.engines.unavailable: not installed): the study runs
# without them, says so here at planning time, and its report lists them.
from simpick.engines import unavailable as _unavailable

UNAVAILABLE = _unavailable(config["engines"])
for _engine, _why in UNAVAILABLE.items():
    print(f"simpick: engine {_engine!r} is left out of this study: {_why}", file=sys.stderr)
ENGINES = [e for e in config["engines"] if e not in UNAVAILABLE]
if not ENGINES:
    raise WorkflowError(f"none of the configured engines can run here: {UNAVAILABLE}")
# Reference models (kinematic, coulomb) join the real-data comparison only, never the scores.
BASELINES = list(config.get("baselines") or {})
REAL_MODELS = ENGINES + BASELINES
TERRAINS = list(config["terrains"])
MOTIONS = list(config["motions"])


VALIDATION_CASES = list(config["validation"]["cases"])


wildcard_constraints:
    engine="|".join(REAL_MODELS),
    case="|".join(re.escape(c) for c in VALIDATION_CASES),
    terrain="|".join(TERRAINS),
    motion="|".join(MOTIONS),


def simulation_params(engine, terrain, motion_name):
    """Everything one lab-study simulation depends on (simpick.sources.lab; cpu_load's too)."""
    return lab_source.lab_params(config, engine, terrain, motion_name)


def validation_params(engine):
    """What an engine's validation job depends on: the engine's settings, the robot, the timestep
    and the cases (not the IMU model, the health limits or the tolerances)."""
    return canonical(
        {
            "engine": engine,
            "engine_settings": config["engines"][engine] or {},
            "physics": {"timestep": config["physics"]["timestep"]},
            "robot": {k: v for k, v in config["robot"].items() if k != "urdf"},
            "cases": {
                name: {k: v for k, v in case.items() if v is not None}
                for name, case in config["validation"]["cases"].items()
            },
        }
    )


def validation_results(engines=None):
    """Every case's record of ``engines`` (all; "{engine}": one job's outputs)."""
    return expand("results/validation/{engine}/{case}.json", engine=engines or ENGINES, case=VALIDATION_CASES)


# --- real robot data (rules/real.smk) ---

DATASET = config["real_data"]["dataset"]  # the committed segment table's dataset
REAL = f"results/real/{DATASET}"


def real_params(engine, terrain_class):
    return source_base.real_params(config, engine, terrain_class)


# terrain class -> segment ids of the committed table (the config check has made sure it exists;
# no run ever writes it)
try:
    SEGMENTS = segments_source.by_class(config["real_data"]["segments"], config["real_data"]["classes"])
except ValueError as _exc:
    raise WorkflowError(str(_exc))


# Speed-accuracy sweep (rules/sweep.smk): timesteps as wildcard labels ("0.5ms")
SWEEP = config.get("sweep")
SWEEP_DIR = f"results/sweeps/{SWEEP['name']}" if SWEEP else None
SWEEP_LABELS = [timestep_label(t) for t in SWEEP["timesteps"]] if SWEEP else []


def sweep_params(engine, terrain_class, label):
    """A segment job's parameters with the physics timestep of the sweep point."""
    params = real_params(engine, terrain_class)
    dt = dict(zip(SWEEP_LABELS, SWEEP["timesteps"]))[label]
    return canonical(params | {"physics": params["physics"] | {"timestep": float(dt)}})


def sweep_runs():
    return [
        f"{SWEEP_DIR}/runs/{engine}/{cls}/{label}.csv"
        for engine in ENGINES
        for cls in SEGMENTS
        for label in SWEEP_LABELS
    ]


# The full replay's dataset folder (--config borealtc_dir=PATH [real_dataset=NAME]), checked
# now: a folder that is not a dataset, an empty class folder, an unpaired file or a class with
# no ground model stops the run here with one `simpick:` line each, before any job.
REPLAY_SET = None
if config.get("borealtc_dir"):
    from simpick.datasets import open_dataset_or_exit

    REPLAY_SET = open_dataset_or_exit(
        config["borealtc_dir"],
        classes=config["real_data"]["classes"],
        name=config.get("real_dataset"),
    )
REPLAY = f"results/real/{REPLAY_SET.name}" if REPLAY_SET else None
RUNS = replay_source.cases(REPLAY_SET) if REPLAY_SET else []


def replay_dataset():
    """The replay dataset as the rules see it: name, label, source and declared rates."""
    declared = (config["real_data"].get("datasets") or {}).get(REPLAY_SET.name) or {}
    return {
        "name": REPLAY_SET.name,
        "folder": str(REPLAY_SET.folder),
        "label": declared.get("label") or REPLAY_SET.name,
        "source": declared.get("source") or f"dataset folder {REPLAY_SET.folder}",
        "declared": {k: declared[k] for k in ("imu_hz", "commands_hz") if declared.get(k)},
    }


def maintained_table(wildcards):
    """maintain_segments' inputs: the BorealTC folder's derived table. Asked for on any other
    dataset (or none), it stops the run while the DAG is built, before any job."""
    if REPLAY_SET is None:
        problem = (
            "maintain_segments derives the committed segment table from the BorealTC folder "
            "(fix: pass --config borealtc_dir=PATH/TO/borealtc)"
        )
    elif REPLAY_SET.name != DATASET:
        problem = (
            f"maintain_segments rewrites {config['real_data']['segments']}, the table of dataset "
            f"{DATASET!r}, but {REPLAY_SET.folder} is dataset {REPLAY_SET.name!r} (fix: pass --config "
            f"real_dataset={DATASET} if that folder holds {DATASET}; its own table is {REPLAY}/segments.csv)"
        )
    else:
        return {"csv": f"{REPLAY}/segments.csv", "provenance": f"{REPLAY}/segments.provenance.yaml"}
    print(f"simpick: {problem}", file=sys.stderr)
    sys.exit(1)


OWN = "results/real/own"
OWN_LOGS = {entry["name"]: entry for entry in config.get("own_logs") or []}

# The replay sources and their case tables: a source is the dataset folder (its name) or the
# user's own logs ("own"); a case is one (terrain class, run) whose canonical log lies at
# results/real/<source>/logs/<class>/<run>.parquet. Each kind of source has its import rule
# (rules/real.smk); from the log on, every source is one entry of SOURCES below.
# No dataset is called "own" (simpick.datasets.RESERVED_NAMES).
REPLAY_CASES = {REPLAY_SET.name: RUNS} if REPLAY_SET else {}
if OWN_LOGS:
    REPLAY_CASES["own"] = own_source.cases(config)


def real_logs(source):
    return [source_base.log_path(source, c, run) for c, run in REPLAY_CASES[source]]


# --- the case tables and the one simulate / compare / summarise path (rules/simulate.smk, metrics.smk) ---
# A source yields a case table: engine-independent (group, name) rows, each one simulation per model
# of the source; its kind's module (simpick.sources: lab, segments, replay, own) says what a case's
# simulation needs and how the source's traces are compared. "lab": terrain x motion (config);
# "segments": terrain class x segment id (the committed table); a dataset folder's name or "own":
# terrain class x run (its canonical logs). A case's trace is
# results/traces/<source>/<model>/<group>/<name>.parquet; the source's tables lie in
# results/metrics/<source>/. Sources "lab" and "segments" are no dataset's name (simpick.datasets.RESERVED_NAMES).
# A dataset folder's derived segment table (rule real_segments, a checkpoint) is a source too,
# "<dataset>-segments": its cases are known once the table is written (source_cases).
def source_spec(kind, models, cases, **more):
    return {"kind": kind, "models": models, "group": source_module(kind).GROUP, "cases": cases, **more}


SOURCES = {
    "lab": source_spec("lab", ENGINES, lab_source.cases(config)),
    **(
        {
            "segments": source_spec(
                "segments",
                REAL_MODELS,
                [(c, s) for c, ids in SEGMENTS.items() for s in ids],
                table=config["real_data"]["segments"],
            )
        }
        if REAL_DATA_ROBOT
        else {}
    ),
    **{
        source: source_spec("own" if source == "own" else "replay", REAL_MODELS, cases)
        for source, cases in REPLAY_CASES.items()
    },
}


# Not for the folder the committed table was derived from (dataset DATASET): its derived table is the
# committed one (maintain_segments keeps them equal; tests/test_realdata checks a fresh derivation
# against it), already simulated as source "segments"; as a source of its own it would simulate the
# same 18 segments x 6 models a second time (108 jobs of the full BorealTC replay).
if REPLAY_SET and REPLAY_SET.name != DATASET:
    DERIVED = f"{REPLAY_SET.name}-segments"  # no dataset name ends so and is also replayed: one folder a run
    SOURCES[DERIVED] = source_spec(
        "segments", REAL_MODELS, None, table=f"{REPLAY}/segments.csv", classes=list(REPLAY_SET.classes)
    )


def source_of(source):
    """The module of a source's kind (simpick.sources)."""
    return source_module(SOURCES[source]["kind"])


def source_cases(source):
    """A source's (group, name) cases; a derived segment table's once its checkpoint has run."""
    cases = SOURCES[source]["cases"]
    if cases is not None:
        return cases
    with open(checkpoints.real_segments.get().output.csv, newline="") as handle:
        return [(row["terrain_class"], row["segment"]) for row in csv.DictReader(handle)]


def source_traces(source):
    return [
        f"results/traces/{source}/{model}/{group}/{name}.parquet"
        for model in SOURCES[source]["models"]
        for group, name in source_cases(source)
    ]


def all_traces():
    """The lab study's traces (engine x terrain x motion)."""
    return source_traces("lab")


def replay_traces(source):
    return source_traces(source)


def metrics_file(source, table):
    return f"results/metrics/{source}/{table}.csv"


# The unit of work of the simulate family: one case, except where a source's case table is batched
# by group (the committed segments, per terrain class): 18 short runs, where a job per segment cost
# about 1.2 s of fixed cost each (process, imports, robot) and the default study some 50 s more
# on 2 cores than a job per class sharing one import (measured; see the commit that made this).
BATCHED = {"segments"}


def simulate_units():
    """(name, output patterns, fixed values) for each rule of the simulate family; one
    rule over the {source} wildcard for the one-case units, one per group of a batched source."""
    single = [s for s in SOURCES if s not in BATCHED]
    units = (
        [("simulate", ["results/traces/{source}/{engine}/{group}/{name}.parquet"], {"sources": single})]
        if single
        else []
    )
    for source in sorted(BATCHED & set(SOURCES)):
        groups = {}
        for group, name in SOURCES[source]["cases"]:
            groups.setdefault(group, []).append(name)
        for group, names in groups.items():
            outputs = [f"results/traces/{source}/{{engine}}/{group}/{name}.parquet" for name in names]
            units.append((f"simulate_{source}_{group}", outputs, {"source": source, "group": group, "names": names}))
    return units


def one_case_constraints(sources):
    known = [SOURCES[s] for s in sources if SOURCES[s]["cases"] is not None]
    groups = {g for s in known for g, _ in s["cases"]} | {g for s in sources for g in SOURCES[s].get("classes", [])}
    names = {n for s in known for _, n in s["cases"]}
    # a derived table's segment ids are known only after its checkpoint: any name, the source pins it
    unknown = len(known) < len(sources)
    return {
        "source": "|".join(re.escape(s) for s in sources),
        "group": "|".join(sorted(re.escape(g) for g in groups)),
        "name": "[^/]+" if unknown else "|".join(sorted(re.escape(n) for n in names)),
    }


def unit(wildcards, fixed):
    """source, engine, group and the case names of one simulate job."""
    if "names" in fixed:
        return fixed["source"], wildcards.engine, fixed["group"], list(fixed["names"])
    return wildcards.source, wildcards.engine, wildcards.group, [wildcards.name]


def case_inputs(source, group, names):
    """The files a unit's cases read (its source module's case_inputs)."""
    return source_of(source).case_inputs(config, source, SOURCES[source], group, names)


def case_params(source, engine, group, names):
    """Everything a unit's cases on one model depend on, and nothing else."""
    return source_of(source).case_params(config, source, SOURCES[source], engine, group, names)


def case_code(source, engine):
    """The library code a case runs: simulate_job, the model's adapter, and how its source drives it
    (its module's prepare_case, which simulate_job imports by name: no other kind's code)."""
    entry = source_entry(SOURCES[source]["kind"], "prepare_case")
    return script_code("simulate", engine_module(engine), entry)


def compare_inputs(wildcards):
    """A source's traces and what they are compared with."""
    spec = SOURCES[wildcards.source]
    compared = source_of(wildcards.source).compare_inputs(config, wildcards.source, spec, spec["cases"])
    return {"traces": source_traces(wildcards.source)} | compared


def compare_settings(source):
    return source_of(source).compare_settings(config)


def compare_code(source):
    """compare_job and its source's comparison (imported by name: a job of one kind runs no other's)."""
    return script_code("compare", source_entry(SOURCES[source]["kind"], "compare"))


def statistics_params():
    """How many independent runs an interval, a verdict, a rank or an improvement needs, and at what
    level: the validated ``statistics`` settings (SETTINGS), the one rule of every summary (real
    data, calibration, sweep, verdict, report)."""
    return canonical(SETTINGS.statistics.model_dump())


def report_config():
    """The slice of the config the report shows and reads: terrains (strip geometry), motions
    (commanded paths, test order) and the track."""
    return {
        "terrains": config["terrains"],
        "motions": config["motions"],
        "robot": {
            "track": config["robot"]["track"],
            "name": ROBOT.name,
            "label": config["robot"].get("label") or ROBOT.name,
            "real_data_robot": config["real_data"].get("robot") if not REAL_DATA_ROBOT else None,
        },
    }


def accuracy_source():
    """What the accuracy scores rest on (accuracy.reference in the config): the set of tests
    (lab, segments, replay or own), its dataset, its Eq. 7 totals and the per-test table beside
    them. Only the rules use this; the scores job records it in results/scores/provenance.yaml,
    which is what the report reads."""
    reference = config["accuracy"]["reference"]
    if reference == "paper":
        kind, source, dataset = "lab", "lab", None
    elif reference == "own":
        kind, source, dataset = "own", "own", "own"
    elif REPLAY_SET:
        kind, source, dataset = "replay", REPLAY_SET.name, REPLAY_SET.name
    else:
        kind, source, dataset = "segments", "segments", DATASET
    return {
        "reference": reference,
        "set": kind,
        "dataset": dataset,
        "source": source,
        "errors": metrics_file(source, "imu_errors"),
        "per_test": metrics_file(source, "per_test"),
    }


def verdict_source():
    """The real data simpick's verdict rests on: the accuracy scores' real set, else the committed segments."""
    src = accuracy_source()
    return src["source"] if src["set"] != "lab" else "segments"


def verdict_source_title():
    """How the report names the verdict's real data."""
    if SOURCES[verdict_source()]["kind"] == "segments":
        label = (config["real_data"].get("datasets") or {}).get(DATASET, {}).get("label") or DATASET
        return f"committed constant-command segments of {label}"
    return f"full replay of {verdict_source()}"


VERDICT_TABLES = ("metrics", "table", "separation", "ranking", "discrimination", "headings")
# simpick's verdict rests on real runs: none where the study's robot has no real data (real_data.robot)
VERDICT = verdict_source() in SOURCES


def accuracy_errors():
    """The Eq. 7 totals the accuracy scores rest on."""
    return accuracy_source()["errors"]


def report_real_inputs(wildcards):
    """The real-robot inputs of the report: the accuracy scores' errors file, the committed
    segments' comparison always, the full replay of the dataset folder when one is given."""
    segments = config["real_data"]["segments"]
    provenance = segments.replace(".csv", ".provenance.yaml")
    inputs = {
        "accuracy_errors": accuracy_errors(),
    }
    if REAL_DATA_ROBOT:  # the committed segments are real_data.robot's
        inputs["segments"] = segments
        inputs.update(
            {
                f"segments_{table}": metrics_file("segments", table)
                for table in ("per_test", "summary", "pairwise", "imu_errors")
            }
        )
    if accuracy_source()["set"] != "lab":  # its per-test table: how much of each error a rigid model leaves
        inputs["accuracy_per_test"] = accuracy_source()["per_test"]
    if os.path.exists(provenance) and REAL_DATA_ROBOT:
        inputs["segments_provenance"] = provenance
    if REPLAY_SET:
        inputs.update(
            {
                f"replay_{table}": metrics_file(REPLAY_SET.name, table)
                for table in ("per_test", "summary", "pairwise", "imu_errors")
            }
        )
        inputs["replay_per_window"] = metrics_file(REPLAY_SET.name, "detail")
        inputs["real_turning"] = f"{REPLAY}/turning/summary.csv"
    if VERDICT:
        inputs.update({f"verdict_{t}": f"results/verdict/{t}.csv" for t in VERDICT_TABLES})
        inputs["verdict_headline"] = "results/verdict/headline.yaml"
    if SWEEP:
        inputs["sweep"] = f"{SWEEP_DIR}/summary.csv"
    if CALIBRATION and CALIBRATION.get("enabled"):  # rules/calibration.smk
        inputs["calibration"] = f"{CAL_DIR}/summary.csv"
        inputs["calibration_turning"] = f"{CAL_DIR}/turning.csv"
        inputs["calibration_target"] = f"{CAL_DIR}/target.csv"
    return inputs


def report_datasets():
    """Which dataset each real-data set comes from, and its declared rates (the report states them)."""
    declared = config["real_data"].get("datasets") or {}
    committed = declared.get(DATASET) or {}
    return canonical(
        {
            "segments": {
                "name": DATASET,
                "label": committed.get("label") or DATASET,
                "source": committed.get("source") or "",
                "declared": {k: committed[k] for k in ("imu_hz", "commands_hz") if committed.get(k)},
                "simulated_imu_hz": config["imu"]["rate_hz"],
            },
            "replay": replay_dataset() if REPLAY_SET else None,
        }
    )


# --- library code as a rerun trigger ---
# Snakemake reruns a job when its params change, not when imported library code does: each rule
# carries the version of the code its job runs (simpick.codeversion): computed from the functions
# its script calls and what they import and name, so an edited metric or engine adapter reruns
# what runs it, and nothing else.
from simpick.codeversion import dispatch_entry, job_code, script_roots
from simpick.engines import ADAPTERS, REFERENCE_MODELS


def script_code(script, *roots, opaque=()):
    """The code version of a job of scripts/<script>.py: the simpick functions the script calls,
    ``roots`` (modules or functions it reaches by name only: an engine adapter, a dispatch entry)
    and what they use, less the ``opaque`` names (dispatch tables whose entry is a root)."""
    path = os.path.join(workflow.basedir, "scripts", f"{script}.py")
    return job_code(*script_roots(path), *roots, opaque=opaque)


def figure_code(rule):
    """A figure rule's code: figure_job and the drawing function simpick.report.draw.RULES gives it."""
    entry = dispatch_entry("simpick.report.draw", "RULES", rule)
    return script_code("figure", entry, opaque=("simpick.report.draw:RULES",))


def engine_module(engine):
    """The adapter module of a model (the registry imports it by name, so it is named here)."""
    return {**ADAPTERS, **REFERENCE_MODELS}[engine].split(":")[0]


# Calibration (rules/calibration.smk, config `calibration:`): units, settings and targets
CALIBRATION = config.get("calibration")

if CALIBRATION:
    from simpick.engines import get_engine as _get_engine

    CAL_SOURCE = "replay" if REPLAY_SET else "segments"
    CAL_DIR = (
        f"results/calibration/replay-{REPLAY_SET.name}" if REPLAY_SET else f"results/calibration/segments-{DATASET}"
    )
    CAL_MODELS = [
        m for m in (CALIBRATION.get("models") or REAL_MODELS) if m not in UNAVAILABLE and _get_engine(m).calibratable
    ]
    CAL_CLASSES = sorted({c for c, _ in RUNS}) if REPLAY_SET else sorted(SEGMENTS)

    def calibration_units():
        """(terrain class, run, unit) of every real unit the split divides; a segment's with whether it
        turns (the split stratifies by it; a replayed run's is read from its log by the split job)."""
        if REPLAY_SET:
            return [[c, run, run] for c, run in RUNS]
        with open(config["real_data"]["segments"], newline="") as handle:
            return [
                [r["terrain_class"], r["run"], r["segment"], r["kind"] == "turning"] for r in csv.DictReader(handle)
            ]

    def calibration_split_inputs(wildcards):
        """The table the units come from; for a replay its logs too (which runs turn)."""
        if REPLAY_SET:
            return {
                "dataset": f"{REPLAY}/dataset.yaml",
                "logs": [source_base.log_path(REPLAY_SET.name, c, run) for c, run in RUNS],
            }
        return {"segments": config["real_data"]["segments"]}

    def calibration_strata():
        """How the split job tells a replayed run that turns: the calibration's steady windows within
        its compared seconds (None for segments: their kind says it)."""
        if not REPLAY_SET:
            return None
        settings = calibration_settings(None, search=False)
        return canonical(
            {"track": config["robot"]["track"], "steady": settings["steady"], "duration": settings["replay_seconds"]}
        )

    def calibration_data(wildcards):
        """The real data a class's jobs read: the committed table, or the class's canonical logs."""
        if REPLAY_SET:
            return {
                "logs": [
                    source_base.log_path(REPLAY_SET.name, c, run) for c, run in RUNS if c == wildcards.terrain_class
                ]
            }
        return {"segments": config["real_data"]["segments"]}

    def calibration_settings(engine, search=True):
        """What a class's errors depend on; with ``search`` also the optimiser's budget, seed and
        this model's bounds (so an evaluation does not rerun on a budget edit unless the best
        parameters change)."""
        window = (
            {"segment_seconds": CALIBRATION.get("segment_seconds")}
            if not REPLAY_SET
            else {
                "replay_seconds": CALIBRATION.get("replay_seconds"),
                # the steady-command turning windows of the real turning analysis (rule real_turning;
                # window and settle: simpick.realturning.turning_windows' own)
                "steady": {k: config["real_data"]["segment_rules"][k] for k in ("tolerance", "min_turn")},
            }
        )
        out = {"source": CAL_SOURCE, "scales": CALIBRATION["scales"], **window}
        if search:
            out.update(
                {
                    "n_trials": CALIBRATION["n_trials"],
                    "startup_trials": CALIBRATION["startup_trials"],
                    "seed": CALIBRATION["seed"],
                    "bounds": {engine: (CALIBRATION.get("bounds") or {}).get(engine) or {}},
                }
            )
        return canonical(out)

    def calibration_outputs():
        return [f"{CAL_DIR}/{e}/{c}/evaluation.csv" for e in CAL_MODELS for c in CAL_CLASSES]

    CALIBRATION_ALL = [f"{CAL_DIR}/summary.csv"] if CALIBRATION.get("enabled") else []
else:
    CALIBRATION_ALL = []


# --- the report's figures (rules/report.smk) ---

FIGURES = "results/report/figures"
# engine -> colour follows this list (simpick.report.draw.colors): sorted, so reordering the
# config's engines neither recolours nor redraws a figure
FIGURE_ENGINES = sorted(ENGINES) + sorted(BASELINES)


def lab_figure_tests():
    """The lab tests with an IMU-statistics figure: every simulated test, and every test the
    paper gives a real reference for (drawn with the reference alone when no engine ran it)."""
    from simpick.published import load_published
    from simpick.reference import lab_reference

    tests = [(t, m) for t in TERRAINS for m in MOTIONS]
    return tests + [tm for tm in lab_reference(load_published(config["reference"]["published"])) if tm not in tests]


LAB_FIGURE_TESTS = lab_figure_tests()


def report_figures():
    """Every figure file the report embeds (and the notes beside the replay figures)."""
    out = [
        f"{FIGURES}/contributions.png",
        f"{FIGURES}/paths.png",
        f"{FIGURES}/validation_gain.png",
        f"{FIGURES}/real_gain.png",
    ]
    out += [f"{FIGURES}/imu_stats/{t}/{m}.png" for t, m in LAB_FIGURE_TESTS]
    out += expand(f"{FIGURES}/traces/{{terrain}}/{{motion}}.png", terrain=TERRAINS, motion=MOTIONS)
    if SWEEP:
        out.append(f"{FIGURES}/sweep.png")
    if REPLAY_SET:
        out += expand(
            f"{FIGURES}/replay/{{terrain_class}}.{{ext}}", terrain_class=REPLAY_SET.classes, ext=("png", "json")
        )
        out.append(f"{FIGURES}/real_turning.png")
    return out


def lab_test_traces(wildcards):
    return expand(
        "results/traces/lab/{engine}/{terrain}/{motion}.parquet",
        engine=ENGINES,
        terrain=wildcards.terrain,
        motion=wildcards.motion,
    )


def real_gain_inputs(wildcards):
    """The real-data tables whose yaw-rate gains the figure shows: the committed segments', and
    the full replay's when a dataset folder is given."""
    names = ("per_test", "summary", "pairwise")
    inputs = {f"segments_{n}": metrics_file("segments", n) for n in names} if REAL_DATA_ROBOT else {}
    if REPLAY_SET:
        inputs.update({f"replay_{n}": metrics_file(REPLAY_SET.name, n) for n in names})
    return inputs


def replay_class_inputs(wildcards):
    """One terrain class of the full replay: its canonical logs, every model's replay of them,
    and the per-test table that picks the run drawn."""
    runs = [run for c, run in RUNS if c == wildcards.terrain_class]
    return {
        "real_logs": [log for log in real_logs(REPLAY_SET.name) if f"/logs/{wildcards.terrain_class}/" in log],
        "replay_traces": [
            f"results/traces/{REPLAY_SET.name}/{e}/{wildcards.terrain_class}/{run}.parquet"
            for e in REAL_MODELS
            for run in runs
        ],
        "replay_per_test": metrics_file(REPLAY_SET.name, "per_test"),
    }
