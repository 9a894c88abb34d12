rule scores:
    input:
        imu_errors=accuracy_errors(),
        rtf="results/metrics/rtf.csv",
        cpu=expand("results/cpu/{engine}.json", engine=ENGINES),
        qualitative=config["qualitative"],
    output:
        scores="results/scores/scores.csv",
        weighted="results/scores/weighted.csv",
    params:
        engines=sorted(ENGINES),  # a reordered engines: block is not an edit
        weights=canonical(config["weights"]),
        code=code_version("scoring.py", "workflow.py"),
    log:
        "results/logs/scores.log",
    benchmark:
        "results/benchmarks/scores.tsv"
    conda:
        "../envs/simpick.yaml"
    script:
        "../scripts/scores.py"
