# The scores, and results/scores/provenance.yaml: which errors file, tests and exclusions they
# rest on (the report reads that file rather than working it out from the config again).
rule scores:
    input:
        imu_errors=PLAN.accuracy_errors(),
        accuracy_tests=PLAN.accuracy_source()["per_test"],
        runs=PLAN.metrics_file("lab", "runs"),
        rtf=PLAN.metrics_file("lab", "rtf"),
        cpu=expand("results/cpu/{engine}.json", engine=PLAN.engines),
        qualitative=PLAN.config["qualitative"],
    output:
        scores=report("results/scores/scores.csv", caption="captions/scores.rst", category="Scores"),
        weighted=report("results/scores/weighted.csv", caption="captions/weighted.rst", category="Scores"),
        provenance=report("results/scores/provenance.yaml", caption="captions/scores_provenance.rst", category="Scores"),
    log:
        "results/logs/scores.log",
    benchmark:
        "results/benchmarks/scores.tsv"
    conda:
        "../envs/simpick.yaml"
    params:
        engines=sorted(PLAN.engines),  # a reordered engines: block is not an edit
        weights=canonical(PLAN.config["weights"]),
        accuracy=canonical({k: PLAN.accuracy_source()[k] for k in ("reference", "set", "dataset")}),
        cpu_test=f"{PLAN.config['cpu_load']['terrain']}/{PLAN.config['cpu_load']['motion']}",
        code=PLAN.script_code("scores"),
    script:
        "../scripts/scores.py"


# simpick's verdict beside the paper's method (simpick.score.verdict): per real run the yaw-rate gain
# error, the heading error and (where a log measures it) the speed error, with intervals and paired
# verdicts over runs; what the paper's accuracy scores separate; the weighted total with an interval
# over real runs; the report's first paragraph. The report reads these tables and computes none.
if PLAN.verdict:

    rule verdict:
        input:
            per_test=PLAN.metrics_file(PLAN.verdict_source(), "per_test"),
            accuracy_tests=PLAN.accuracy_source()["per_test"],
            weighted="results/scores/weighted.csv",
            provenance="results/scores/provenance.yaml",
        output:
            metrics=report("results/verdict/metrics.csv", caption="captions/verdict_metrics.rst", category="Verdict"),
            table=report("results/verdict/table.csv", caption="captions/verdict_table.rst", category="Verdict"),
            separation=report(
                "results/verdict/separation.csv", caption="captions/verdict_separation.rst", category="Verdict"
            ),
            ranking=report("results/verdict/ranking.csv", caption="captions/verdict_ranking.rst", category="Verdict"),
            discrimination=report(
                "results/verdict/discrimination.csv", caption="captions/verdict_discrimination.rst", category="Verdict"
            ),
            headings=report("results/verdict/headings.csv", caption="captions/verdict_headings.rst", category="Verdict"),
            headline=report(
                "results/verdict/headline.yaml", caption="captions/verdict_headline.rst", category="Verdict"
            ),
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
