# The scores, which read no weight, and results/scores/provenance.yaml: which errors file, tests and
# exclusions they rest on (the report reads that file rather than working it out from the config
# again). The weights reach the weighted table only, which the report job weighs, so that a weight edit
# reruns neither the scores nor what reads them alone (the report's evidence and appendices, rule
# report_evidence).
rule scores:
    input:
        imu_errors=PLAN.accuracy_errors(),
        accuracy_tests=PLAN.accuracy_source()["per_test"],
        runs=PLAN.metrics_file("lab", "runs"),
        rtf=PLAN.metrics_file("lab", "rtf"),
        cpu=expand("results/cpu/{engine}.json", engine=PLAN.engines),
        qualitative=SETTINGS.qualitative,
    output:
        scores=report("results/scores/scores.csv", caption="captions/scores.rst", category="Scores"),
        provenance=report("results/scores/provenance.yaml", caption="captions/scores_provenance.rst", category="Scores"),
    log:
        "results/logs/scores.log",
    benchmark:
        "results/benchmarks/scores.tsv"
    conda:
        "../envs/simpick.yaml"
    threads: 1
    resources:
        mem_mb=300,
        runtime=5,
    params:
        engines=sorted(PLAN.engines),  # a reordered engines: block is not an edit
        accuracy=canonical({k: PLAN.accuracy_source()[k] for k in ("reference", "set", "dataset")}),
        cpu_test=f"{SETTINGS.cpu_load.terrain}/{SETTINGS.cpu_load.motion}",
        code=PLAN.script_code("scores"),
    script:
        "../scripts/scores.py"


# The weighted table (the scores times the config's weights, the totals, the ranking, each weight x score
# and what puts the leader ahead of each engine) and the answer are not jobs of their own: the report job
# weighs the scores before it writes the page (simpick.report.weighing, rules/report.smk), so that a weight
# edit reruns one job.


# simpick's verdict beside the paper's method (simpick.score.verdict): per real run the yaw-rate gain
# error, the heading error and (where a log measures it) the speed error, with intervals; every engine
# against the best (outcomes.csv: worse, equivalent within the config's margin, or undetermined;
# simpick.score.equivalence) behind the mechanics gate of the validation (mechanics.csv); what the
# paper's accuracy scores separate. It reads no weight: a weight edit does not rerun these tests, a
# margin edit reruns them and the answer, not the scores.
if PLAN.verdict:

    rule verdict:
        input:
            per_test=PLAN.metrics_file(PLAN.verdict_source(), "per_test"),
            accuracy_tests=PLAN.accuracy_source()["per_test"],
            accuracy_errors=PLAN.accuracy_errors(),
            validation="results/validation/summary.csv",
        output:
            metrics=report("results/verdict/metrics.csv", caption="captions/verdict_metrics.rst", category="Verdict"),
            table=report("results/verdict/table.csv", caption="captions/verdict_table.rst", category="Verdict"),
            outcomes=report("results/verdict/outcomes.csv", caption="captions/verdict_outcomes.rst", category="Verdict"),
            mechanics=report(
                "results/verdict/mechanics.csv", caption="captions/verdict_mechanics.rst", category="Verdict"
            ),
            discrimination=report(
                "results/verdict/discrimination.csv", caption="captions/verdict_discrimination.rst", category="Verdict"
            ),
            headings=report("results/verdict/headings.csv", caption="captions/verdict_headings.rst", category="Verdict"),
        log:
            "results/logs/verdict.log",
        benchmark:
            "results/benchmarks/verdict.tsv"
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=500,
            runtime=10,
        params:
            settings=PLAN.verdict_settings(),
            code=PLAN.script_code("verdict"),
        script:
            "../scripts/verdict.py"


# The answer (simpick.score.answer: one row per engine and a sentence per need, the paper's weighted total
# with its interval over real runs, the separation table and the report's first paragraph) is written by
# the report job, beside the weighted table (rules/report.smk), from the real data the study has of its
# robot (PLAN.answer_tables): the verdict's runs above, else the DRIVE comparison's steps (rules/drive.smk,
# which writes the same tables beside its outcomes).
