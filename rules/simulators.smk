# The simulators as rows (simpick.engines.simulators): each simulator's profiles run the validation and the real data
# as models of the study (rules/validate.smk, rules/simulate.smk); here their results are put together by
# simulator, without simulating anything. No weight reaches rule simulators; the report job weighs their scores
# (the paper's table per simulator), simulator_tree reads the evidence alone (weights only order a leaf).


rule simulators:
    input:
        **({"per_test": PLAN.metrics_file(PLAN.verdict_source(), "per_test")} if PLAN.verdict else {}),
        **({"imu_errors": PLAN.accuracy_errors()} if PLAN.verdict else {}),
        # without a verdict (a robot with no BorealTC data), DRIVE's steps where the profiles replayed them:
        # judged as rule drive_compare judges the engines, engines and profiles together
        **(
            {"drive_errors": f"{DRIVE}/errors.csv", "drive_steps": f"{DRIVE}/steps.csv"}
            if not PLAN.verdict and SETTINGS.drive_dir and PLAN.config["simulators"]["drive"]
            else {}
        ),
        **({"split": f"{PLAN.CALIBRATION_DIR}/split.csv"} if PLAN.calibration_spaces else {}),
        catalog=PLAN.config["simulators"]["catalog"],
        validation="results/validation/summary.csv",
        gains="results/validation/gains.csv",
        rtf=PLAN.metrics_file("lab", "rtf"),
        cpu=expand("results/cpu/{engine}.json", engine=PLAN.engines),
        # the calibrated profiles' fits and the split whose test runs judge every row held out
        calibrations=PLAN.calibration_files(),
    output:
        table=report("results/simulators/table.csv", caption="captions/simulators.rst", category="Simulators"),
        outcomes="results/simulators/outcomes.csv",
        mechanics="results/simulators/mechanics.csv",
        # the calibrated profiles' per-class fits beside the pooled one
        per_class="results/simulators/per_class.csv",
        tree_dir=directory("results/simulators/subjects"),
    log:
        "results/logs/simulators.log",
    benchmark:
        "results/benchmarks/simulators.tsv"
    conda:
        "../envs/simpick.yaml"
    params:
        **PLAN.simulators_params(),
        code=PLAN.script_code("simulators"),
    script:
        "../scripts/simulators.py"


rule simulator_settings:
    """Each run profile as the file a user pastes into the simulator (simpick.engines.simulator_files)."""
    input:
        catalog=PLAN.config["simulators"]["catalog"],
        table="results/simulators/table.csv",
        calibrations=PLAN.calibration_files(),
    output:
        directory("results/simulators/settings"),
    log:
        "results/logs/simulator_settings.log",
    conda:
        "../envs/simpick.yaml"
    params:
        **PLAN.simulator_settings_params(),
        code=PLAN.script_code("simulator_settings"),
    script:
        "../scripts/simulator_settings.py"


rule simulator_models:
    """Each profile of a simulator whose engine writes one (MuJoCo, Gazebo, Drake) as a model that opens as it is
    (simpick.studies.simulator_models): the robot on flat ground with its actuators, contacts and options, and the
    yaw-rate gains the validation's own cases measure on it. It reads no table: no weight or verdict reaches it."""
    input:
        **PLAN.simulator_models_input(),
    output:
        directory(PLAN.MODELS_DIR),
    log:
        "results/logs/simulator_models.log",
    benchmark:
        "results/benchmarks/simulator_models.tsv"
    conda:
        "../envs/simpick.yaml"
    params:
        **PLAN.simulator_models_params(),
        code=PLAN.script_code("simulator_models", *PLAN.model_code_roots()),
    script:
        "../scripts/simulator_models.py"


# The paper's weighted table with simulators as its rows (simpick.score.simulators.simulator_scores_job):
# weighed by the report job (simpick.report.weighing), which the weights reach.


rule simulator_tree:
    """The decision tree with simulators as its leaves (simpick.score.tree over results/simulators/subjects), each
    leaf naming the profile its answers ask for: the calibrated one where they ask for closeness to the robot."""
    input:
        tree_dir="results/simulators/subjects",
        table="results/simulators/table.csv",
        settings="results/simulators/settings",
    output:
        tree="results/simulators/tree.json",
    log:
        "results/logs/simulator_tree.log",
    conda:
        "../envs/simpick.yaml"
    params:
        **PLAN.simulator_tree_params(),
        code=PLAN.script_code("simulator_tree"),
    script:
        "../scripts/simulator_tree.py"


# The calibrated profiles (simpick.studies.simulator_calibration): the real runs split as the calibration
# splits them (the committed segments' runs; DRIVE's steps where the profiles replay them, each step a unit of
# its own), then per simulator its turning settings fitted on the training runs within what it exposes
# (resources/simulators/calibration.yaml): least squares of the training runs' gain residuals, their turning
# segments replayed as the simulate jobs replay them. Its validate, simulate and replay jobs read the fit and
# merge its settings.
if PLAN.calibration_spaces:

    rule simulator_split:
        input:
            **PLAN.calibration_real_input(),
        output:
            f"{PLAN.CALIBRATION_DIR}/split.csv",
        log:
            "results/logs/simulators/split.log",
        conda:
            "../envs/simpick.yaml"
        params:
            **PLAN.simulator_split_params(),
            code=PLAN.script_code("simulator_split"),
        script:
            "../scripts/simulator_split.py"

    rule simulator_calibrate:
        input:
            **PLAN.calibration_real_input(),
            split=f"{PLAN.CALIBRATION_DIR}/split.csv",
            urdf=PLAN.config["robot"]["urdf"],
        output:
            f"{PLAN.CALIBRATION_DIR}/{{simulator}}.yaml",
        log:
            "results/logs/simulators/calibrate/{simulator}.log",
        benchmark:
            "results/benchmarks/simulators/calibrate/{simulator}.tsv"
        wildcard_constraints:
            simulator="|".join(PLAN.simulators),
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=600,
            runtime=20,
        params:
            case=lambda wc: PLAN.simulator_calibrate_params(wc.simulator),
            code=lambda wc: PLAN.script_code(
                "simulator_calibrate", *PLAN.engine_modules(PLAN.catalog.simulators[wc.simulator].engine)
            ),
        script:
            "../scripts/simulator_calibrate.py"
