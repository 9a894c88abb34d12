# The scores, and results/scores/provenance.yaml: which errors file, tests and exclusions they
# rest on (the report reads that file rather than working it out from the config again).
rule scores:
    input:
        imu_errors=accuracy_errors(),
        accuracy_tests=accuracy_source()["per_test"],
        runs=metrics_file("lab", "runs"),
        rtf=metrics_file("lab", "rtf"),
        cpu=expand("results/cpu/{engine}.json", engine=ENGINES),
        qualitative=config["qualitative"],
    output:
        scores=report("results/scores/scores.csv", caption="captions/scores.rst", category="Scores"),
        weighted=report("results/scores/weighted.csv", caption="captions/weighted.rst", category="Scores"),
        provenance=report("results/scores/provenance.yaml", caption="captions/scores_provenance.rst", category="Scores"),
    params:
        engines=sorted(ENGINES),  # a reordered engines: block is not an edit
        weights=canonical(config["weights"]),
        accuracy=canonical({k: accuracy_source()[k] for k in ("reference", "set", "dataset")}),
        cpu_test=f"{config['cpu_load']['terrain']}/{config['cpu_load']['motion']}",
        code=script_code("scores"),
    log:
        "results/logs/scores.log",
    benchmark:
        "results/benchmarks/scores.tsv"
    conda:
        "../envs/simpick.yaml"
    script:
        "../scripts/scores.py"
