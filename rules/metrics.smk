# One compare and one summarise family over the study's sources (simpick.plan: PLAN.sources): a source's
# traces against what they are compared with (simpick.compare.jobs.compare_job, by the source's module in
# simpick.sources: the paper's reference
# statistics for the lab, each segment's real window statistics, the real log for a replay), then its
# per-test rows summed and summarised (simpick.compare.jobs.summarise_job), all in results/metrics/<source>/.


rule compare:
    input:
        unpack(PLAN.compare_inputs),
    output:
        per_test="results/metrics/{source}/per_test.csv",
        detail="results/metrics/{source}/detail.csv",
        runs="results/metrics/{source}/runs.csv",
    log:
        "results/logs/compare/{source}.log",
    benchmark:
        "results/benchmarks/compare/{source}.tsv"
    wildcard_constraints:
        source="|".join(re.escape(s) for s in PLAN.sources),
    conda:
        "../envs/simpick.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=30,
    params:
        kind=lambda wc: PLAN.source_of(wc.source).DRIVEN,
        settings=lambda wc: PLAN.compare_params(wc.source),
        code=lambda wc: PLAN.compare_code(wc.source),
    script:
        "../scripts/compare.py"


rule summarise:
    input:
        per_test="results/metrics/{source}/per_test.csv",
        runs="results/metrics/{source}/runs.csv",
    output:
        imu_errors="results/metrics/{source}/imu_errors.csv",
        rtf="results/metrics/{source}/rtf.csv",
        summary="results/metrics/{source}/summary.csv",
        pairwise="results/metrics/{source}/pairwise.csv",
    log:
        "results/logs/summarise/{source}.log",
    benchmark:
        "results/benchmarks/summarise/{source}.tsv"
    wildcard_constraints:
        source="|".join(re.escape(s) for s in PLAN.sources),
    conda:
        "../envs/simpick.yaml"
    threads: 1
    resources:
        mem_mb=400,
        runtime=10,
    params:
        settings=lambda wc: PLAN.summarise_params(wc.source),
        code=PLAN.script_code("summarise"),
    script:
        "../scripts/summarise.py"
