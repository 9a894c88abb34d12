rule metrics:
    input:
        traces=all_traces(),
        published=config["reference"]["published"],
    output:
        trace_stats="results/metrics/trace_stats.csv",
        reference_stats="results/metrics/reference_stats.csv",
        per_test_errors="results/metrics/per_test_errors.csv",
        imu_errors="results/metrics/imu_errors.csv",
        runs="results/metrics/runs.csv",
        rtf="results/metrics/rtf.csv",
    params:
        code=code_version("metrics.py", "workflow.py", "reference.py", "published.py", "traces.py"),
    log:
        "results/logs/metrics.log",
    conda:
        "../envs/simpick.yaml"
    script:
        "../scripts/metrics.py"
