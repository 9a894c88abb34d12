# Calibration (issue 11, config `calibration:`): every real-data model calibrated per terrain class on
# training runs, judged on held-out test runs as configured and as calibrated. Units are the committed
# segments, or the full replay's runs when borealtc_dir is set. Target: `snakemake calibration`; with
# calibration.enabled the default target and the report include it. Library: simpick.calibration; helpers in common.smk.

if CALIBRATION:

    rule calibration_split:
        input:
            unpack(calibration_split_inputs),
        output:
            f"{CAL_DIR}/split.csv",
        log:
            f"{CAL_DIR}/logs/split.log",
        conda:
            "../envs/simpick.yaml"
        params:
            units=calibration_units(),
            strata=calibration_strata(),
            test_fraction=canonical(CALIBRATION["test_fraction"]),
            seed=int(CALIBRATION["seed"]),
            code=script_code("calibration_split"),
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
        log:
            f"{CAL_DIR}/logs/{{engine}}/{{terrain_class}}/calibrate.log",
        benchmark:
            f"{CAL_DIR}/benchmarks/{{engine}}/{{terrain_class}}/calibrate.tsv"
        wildcard_constraints:
            engine="|".join(CAL_MODELS),
            terrain_class="|".join(CAL_CLASSES),
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=600,
            # DART, 12 trials over 2 segments of 5 s: about 2 min; a replayed class: up to an hour
            runtime=120,
        params:
            case=lambda wc: real_params(wc.engine, wc.terrain_class),
            settings=lambda wc: calibration_settings(wc.engine),
            code=lambda wc: script_code("calibrate", engine_module(wc.engine)),
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
        log:
            f"{CAL_DIR}/logs/{{engine}}/{{terrain_class}}/evaluate.log",
        benchmark:
            f"{CAL_DIR}/benchmarks/{{engine}}/{{terrain_class}}/evaluate.tsv"
        wildcard_constraints:
            engine="|".join(CAL_MODELS),
            terrain_class="|".join(CAL_CLASSES),
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=600,
            runtime=60,
        params:
            case=lambda wc: real_params(wc.engine, wc.terrain_class),
            settings=lambda wc: calibration_settings(wc.engine, search=False),
            code=lambda wc: script_code("calibration_evaluate", engine_module(wc.engine)),
        script:
            "../scripts/calibration_evaluate.py"

    rule calibration_summary:
        input:
            evals=calibration_outputs(),
            bests=[f"{CAL_DIR}/{e}/{c}/best.yaml" for e in CAL_MODELS for c in CAL_CLASSES],
            split=f"{CAL_DIR}/split.csv",
            urdf=config["robot"]["urdf"],
        output:
            summary=f"{CAL_DIR}/summary.csv",
            units=f"{CAL_DIR}/units.csv",
            parameters=f"{CAL_DIR}/parameters.csv",
            turning=f"{CAL_DIR}/turning.csv",
            target=f"{CAL_DIR}/target.csv",
        log:
            f"{CAL_DIR}/logs/summary.log",
        conda:
            "../envs/simpick.yaml"
        params:
            statistics=statistics_params(),
            turning=canonical(
                {
                    "track": config["robot"]["track"],
                    "engines": ENGINES,
                    "target": SETTINGS.calibration.target.model_dump(),
                }
            ),
            code=script_code("calibration_summary"),
        script:
            "../scripts/calibration_summary.py"

    rule calibration:
        """The calibration alone (its section appears in the report with calibration.enabled)."""
        input:
            f"{CAL_DIR}/summary.csv",
