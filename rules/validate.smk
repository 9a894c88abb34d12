# Engines against analytic mechanics (simpick.studies.validation): every engine runs cases with known
# answers on the study's robot and settings; the summary judges them against the config's
# tolerances, so a tolerance edit reruns the summary and the report, not the engines.
# One job per engine runs all its cases in one process (the robot and the engine's module loaded
# once) and writes a record per case; its params hold every case, so editing a case reruns each
# engine's job.


rule validate:
    input:
        # a calibrated profile's jobs read its fit too, and merge its settings at run time
        unpack(lambda wc: PLAN.validation_inputs(wc.engine)),
    output:
        PLAN.validation_results("{engine}"),
    log:
        "results/logs/validate/{engine}.log",
    benchmark:
        "results/benchmarks/validate/{engine}.tsv"
    priority: lambda wc: PLAN.job_priority("validate", wc.engine)
    conda:
        "../envs/simpick.yaml"
    threads: 1
    resources:
        mem_mb=400,
        # each case's share as a lab case's; the watchdog stops a case at 90 % of it (validate_job)
        runtime=PLAN.validation_runtime(),
    params:
        case=lambda wc: PLAN.validation_params(wc.engine),
        code=lambda wc: PLAN.script_code("validate", *PLAN.engine_modules(wc.engine)),
    script:
        "../scripts/validate.py"


rule validation_summary:
    input:
        PLAN.validation_results(),
    output:
        summary="results/validation/summary.csv",
        # per engine, the yaw-rate gain left / right and its spread over start headings
        gains="results/validation/gains.csv",
    log:
        "results/logs/validate/summary.log",
    conda:
        "../envs/simpick.yaml"
    params:
        tolerances=canonical(PLAN.config["validation"]["tolerances"]),
        code=PLAN.script_code("validation_summary"),
    script:
        "../scripts/validation_summary.py"
