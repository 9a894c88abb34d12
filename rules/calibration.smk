# Calibration (issue 11, config `calibration:`): every real-data model calibrated per terrain class on
# training runs, judged on held-out test runs as configured and as calibrated. Units are the committed
# segments, or the full replay's runs when borealtc_dir is set. Target: `snakemake calibration`; with
# calibration.enabled the default target and the report include it. Library: simpick.calibration.

CALIBRATION = config.get("calibration")

if CALIBRATION:
    from simpick.engines import get_engine as _get_engine

    CAL_SOURCE = "replay" if REPLAY_SET else "segments"
    CAL_DIR = f"results/calibration/replay-{REPLAY_SET.name}" if REPLAY_SET else f"results/calibration/segments-{DATASET}"
    CAL_MODELS = [m for m in (CALIBRATION.get("models") or REAL_MODELS) if _get_engine(m).calibratable]
    CAL_CLASSES = sorted({c for c, _ in RUNS}) if REPLAY_SET else sorted(SEGMENTS)

    def calibration_units():
        """(terrain class, run, unit) of every real unit the split divides."""
        if REPLAY_SET:
            return [[c, run, run] for c, run in RUNS]
        with open(config["real_data"]["segments"], newline="") as handle:
            return [[r["terrain_class"], r["run"], r["segment"]] for r in csv.DictReader(handle)]

    def calibration_data(wildcards):
        """The real data a class's jobs read: the committed table, or the class's canonical logs."""
        if REPLAY_SET:
            return {"logs": [f"{REPLAY}/logs/{c}/{run}.parquet" for c, run in RUNS if c == wildcards.terrain_class]}
        return {"segments": config["real_data"]["segments"]}

    def calibration_settings(engine, search=True):
        """What a class's errors depend on; with ``search`` also the optimiser's budget, seed and
        this model's bounds (so an evaluation does not rerun on a budget edit unless the best
        parameters change)."""
        window = {"segment_seconds": CALIBRATION.get("segment_seconds")} if not REPLAY_SET else {
            "replay_seconds": CALIBRATION.get("replay_seconds")}
        out = {"source": CAL_SOURCE, "scales": CALIBRATION["scales"], **window}
        if search:
            out.update({"n_trials": CALIBRATION["n_trials"], "startup_trials": CALIBRATION["startup_trials"],
                        "seed": CALIBRATION["seed"],
                        "bounds": {engine: (CALIBRATION.get("bounds") or {}).get(engine) or {}}})
        return canonical(out)

    def calibration_outputs():
        return [f"{CAL_DIR}/{e}/{c}/evaluation.csv" for e in CAL_MODELS for c in CAL_CLASSES]

    CALIBRATION_ALL = [f"{CAL_DIR}/summary.csv"] if CALIBRATION.get("enabled") else []

    rule calibration_split:
        input:
            config["real_data"]["segments"] if not REPLAY_SET else f"{REPLAY}/dataset.yaml",
        output:
            f"{CAL_DIR}/split.csv",
        params:
            units=calibration_units(),
            test_fraction=canonical(CALIBRATION["test_fraction"]),
            seed=int(CALIBRATION["seed"]),
        log:
            f"{CAL_DIR}/logs/split.log",
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/calibration_split.py"

    rule calibrate:
        """One model x class: the Optuna study (journal beside best.yaml: a rerun resumes it)."""
        input:
            unpack(calibration_data),
            split=f"{CAL_DIR}/split.csv",
            urdf=config["robot"]["urdf"],
        output:
            best=f"{CAL_DIR}/{{engine}}/{{terrain_class}}/best.yaml",
            trials=f"{CAL_DIR}/{{engine}}/{{terrain_class}}/trials.csv",
        params:
            case=lambda wc: real_params(wc.engine, wc.terrain_class),
            settings=lambda wc: calibration_settings(wc.engine),
        wildcard_constraints:
            engine="|".join(CAL_MODELS),
            terrain_class="|".join(CAL_CLASSES),
        log:
            f"{CAL_DIR}/logs/{{engine}}/{{terrain_class}}/calibrate.log",
        benchmark:
            f"{CAL_DIR}/benchmarks/{{engine}}/{{terrain_class}}/calibrate.tsv"
        threads: 1
        resources:
            mem_mb=600,
            # DART, 12 trials over 2 segments of 5 s: about 2 min; a replayed class: up to an hour
            runtime=120,
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/calibrate.py"

    rule calibration_evaluate:
        """Every unit of the class, as configured and as calibrated (train and test)."""
        input:
            unpack(calibration_data),
            split=f"{CAL_DIR}/split.csv",
            best=f"{CAL_DIR}/{{engine}}/{{terrain_class}}/best.yaml",
            urdf=config["robot"]["urdf"],
        output:
            f"{CAL_DIR}/{{engine}}/{{terrain_class}}/evaluation.csv",
        params:
            case=lambda wc: real_params(wc.engine, wc.terrain_class),
            settings=lambda wc: calibration_settings(wc.engine, search=False),
        wildcard_constraints:
            engine="|".join(CAL_MODELS),
            terrain_class="|".join(CAL_CLASSES),
        log:
            f"{CAL_DIR}/logs/{{engine}}/{{terrain_class}}/evaluate.log",
        benchmark:
            f"{CAL_DIR}/benchmarks/{{engine}}/{{terrain_class}}/evaluate.tsv"
        threads: 1
        resources:
            mem_mb=600,
            runtime=60,
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/calibration_evaluate.py"

    rule calibration_summary:
        input:
            evals=calibration_outputs(),
            bests=[f"{CAL_DIR}/{e}/{c}/best.yaml" for e in CAL_MODELS for c in CAL_CLASSES],
            split=f"{CAL_DIR}/split.csv",
        output:
            summary=f"{CAL_DIR}/summary.csv",
            units=f"{CAL_DIR}/units.csv",
            parameters=f"{CAL_DIR}/parameters.csv",
        log:
            f"{CAL_DIR}/logs/summary.log",
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/calibration_summary.py"

    rule calibration:
        """The calibration alone (its section appears in the report with calibration.enabled)."""
        input:
            f"{CAL_DIR}/summary.csv",

else:
    CALIBRATION_ALL = []
