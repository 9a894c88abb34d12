# Engines against analytic mechanics (simpick.validation): every engine runs cases with known
# answers on the study's robot and settings; the summary judges them against the config's
# tolerances, so a tolerance edit reruns the summary and the report, not the engines.


rule validate:
    input:
        urdf=PLAN.config["robot"]["urdf"],
    output:
        "results/validation/{engine}/{case}.json",
    log:
        "results/logs/validate/{engine}/{case}.log",
    benchmark:
        "results/benchmarks/validate/{engine}/{case}.tsv"
    conda:
        "../envs/simpick.yaml"
    threads: 1
    resources:
        mem_mb=400,
        runtime=lambda wc: 1 + int(PLAN.config["health"]["timeout"]) // 60,
    params:
        case=lambda wc: validation_params(wc.engine, wc.case),
        code=lambda wc: script_code("validate", engine_module(wc.engine)),
    script:
        "../scripts/validate.py"


rule validation_summary:
    input:
        validation_results(),
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
        code=script_code("validation_summary"),
    script:
        "../scripts/validation_summary.py"
