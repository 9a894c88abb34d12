# Calibration (config `calibration:`): what an engine reaches once tuned to the real robot. Every
# real-data model is calibrated per terrain class on training runs and judged on held-out test runs, as
# configured and as calibrated. Units are the committed segments, or the full replay's runs when
# borealtc_dir is set. Target: `snakemake calibration`; with calibration.enabled the default target and
# the report include it. Library: simpick.studies.calibration; its plan in simpick.plan.calibration.

if SETTINGS.calibration is not None:

    rule calibration_split:
        input:
            unpack(PLAN.calibration_split_inputs),
        output:
            f"{PLAN.cal_dir}/split.csv",
        log:
            f"{PLAN.cal_dir}/logs/split.log",
        conda:
            "../envs/simpick.yaml"
        params:
            units=PLAN.calibration_units(),
            strata=PLAN.calibration_strata(),
            test_fraction=canonical(SETTINGS.calibration.test_fraction),
            seed=int(SETTINGS.calibration.seed),
            code=PLAN.script_code("calibration_split"),
        script:
            "../scripts/calibration_split.py"

    rule calibrate:
        """One model x class: the Optuna study (journal beside best.yaml: a rerun resumes it)."""
        input:
            unpack(PLAN.calibration_data),
            split=f"{PLAN.cal_dir}/split.csv",
            urdf=SETTINGS.robot.urdf,
        output:
            best=f"{PLAN.cal_dir}/{{engine}}/{{terrain_class}}/best.yaml",
            trials=f"{PLAN.cal_dir}/{{engine}}/{{terrain_class}}/trials.csv",
        log:
            f"{PLAN.cal_dir}/logs/{{engine}}/{{terrain_class}}/calibrate.log",
        benchmark:
            f"{PLAN.cal_dir}/benchmarks/{{engine}}/{{terrain_class}}/calibrate.tsv"
        wildcard_constraints:
            engine="|".join(PLAN.cal_models),
            terrain_class="|".join(PLAN.cal_classes),
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=600,
            # DART, 12 trials over 2 segments of 5 s: about 2 min; a replayed class: up to an hour
            runtime=120,
        params:
            case=lambda wc: PLAN.real_params(wc.engine, wc.terrain_class),
            settings=lambda wc: PLAN.calibration_settings(wc.engine),
            code=lambda wc: PLAN.script_code("calibrate", *PLAN.engine_modules(wc.engine)),
        script:
            "../scripts/calibrate.py"

    rule calibration_evaluate:
        """Every unit of the class, as configured and as calibrated (train and test)."""
        input:
            unpack(PLAN.calibration_data),
            split=f"{PLAN.cal_dir}/split.csv",
            best=f"{PLAN.cal_dir}/{{engine}}/{{terrain_class}}/best.yaml",
            urdf=SETTINGS.robot.urdf,
        output:
            f"{PLAN.cal_dir}/{{engine}}/{{terrain_class}}/evaluation.csv",
        log:
            f"{PLAN.cal_dir}/logs/{{engine}}/{{terrain_class}}/evaluate.log",
        benchmark:
            f"{PLAN.cal_dir}/benchmarks/{{engine}}/{{terrain_class}}/evaluate.tsv"
        wildcard_constraints:
            engine="|".join(PLAN.cal_models),
            terrain_class="|".join(PLAN.cal_classes),
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=600,
            runtime=60,
        params:
            case=lambda wc: PLAN.real_params(wc.engine, wc.terrain_class),
            settings=lambda wc: PLAN.calibration_settings(wc.engine, search=False),
            code=lambda wc: PLAN.script_code("calibration_evaluate", *PLAN.engine_modules(wc.engine)),
        script:
            "../scripts/calibration_evaluate.py"

    rule calibration_summary:
        input:
            evals=PLAN.calibration_outputs(),
            bests=PLAN.calibration_bests(),
            split=f"{PLAN.cal_dir}/split.csv",
            urdf=SETTINGS.robot.urdf,
        output:
            summary=f"{PLAN.cal_dir}/summary.csv",
            units=f"{PLAN.cal_dir}/units.csv",
            parameters=f"{PLAN.cal_dir}/parameters.csv",
            turning=f"{PLAN.cal_dir}/turning.csv",
            target=f"{PLAN.cal_dir}/target.csv",
        log:
            f"{PLAN.cal_dir}/logs/summary.log",
        conda:
            "../envs/simpick.yaml"
        params:
            statistics=PLAN.statistics_params(),
            turning=PLAN.calibration_turning(),
            code=PLAN.script_code("calibration_summary"),
        script:
            "../scripts/calibration_summary.py"

    rule calibration:
        """The calibration alone (its section appears in the report with calibration.enabled)."""
        input:
            f"{PLAN.cal_dir}/summary.csv",
