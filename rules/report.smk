rule report:
    input:
        unpack(report_real_inputs),
        weighted="results/scores/weighted.csv",
        scores_provenance="results/scores/provenance.yaml",
        validation="results/validation/summary.csv",
        # the lab's per-axis table holds the simulated statistics, the paper's and the errors between
        trace_stats=metrics_file("lab", "detail"),
        reference_stats=metrics_file("lab", "detail"),
        imu_errors=metrics_file("lab", "imu_errors"),
        per_test_errors=metrics_file("lab", "detail"),
        runs=metrics_file("lab", "runs"),
        rtf=metrics_file("lab", "rtf"),
        cpu=expand("results/cpu/{engine}.json", engine=ENGINES),
        qualitative=config["qualitative"],
        table11="results/published/table11.csv",
        table11_comparison="results/published/table11_comparison.csv",
        worked_example="results/published/worked_example.json",
        traces=all_traces(),
    output:
        # report(): `snakemake --report` carries the study report (its figures are embedded in it)
        html=report("results/report/report.html", category="Study report"),
    params:
        weights=canonical(config["weights"]),
        # only the keys the report reads (strip geometry, commanded paths, test order): an edit
        # elsewhere reaches it through its inputs or not at all
        config=canonical(report_config()),
        statistics=statistics_params(),
        code=code_version("report", "realdata.py", "realmetrics.py", "scoring.py", "metrics.py", "traces.py"),
        real_data=canonical(
            {
                "dataset": DATASET,
                "datasets": report_datasets(),
                "classes": config["real_data"]["classes"],
                "window": config["real_data"]["window"],
                "segment_rules": config["real_data"]["segment_rules"],
            }
        ),
    log:
        "results/logs/report.log",
    benchmark:
        "results/benchmarks/report.tsv"
    conda:
        "../envs/simpick.yaml"
    script:
        "../scripts/report.py"


rule report_pdf:
    """The PDF in a job of its own: after a weight edit the HTML is there ~3 s sooner."""
    input:
        "results/report/report.html",
    output:
        report("results/report/report.pdf", category="Study report"),
    params:
        code=code_version("report"),
    log:
        "results/logs/report_pdf.log",
    benchmark:
        "results/benchmarks/report_pdf.tsv"
    conda:
        "../envs/simpick.yaml"
    script:
        "../scripts/report_pdf.py"
