def report_real_inputs(wildcards):
    """The real-robot inputs of the report: the accuracy scores' errors file, the segment
    comparison always, the full replay only when borealtc_dir is set (rules/real.smk)."""
    segments = config["real_data"]["segments"]
    provenance = segments.replace(".csv", ".provenance.yaml")
    inputs = {
        "accuracy_errors": accuracy_errors(),
        "segments": segments,
        "segments_per_test": f"{REAL}/metrics/segments_per_test.csv",
        "segments_summary": f"{REAL}/metrics/segments_summary.csv",
        "segments_pairwise": f"{REAL}/metrics/segments_pairwise.csv",
        "segments_imu_errors": f"{REAL}/metrics/segments_imu_errors.csv",
    }
    if config.get("borealtc_dir") or os.path.exists(provenance):
        inputs["segments_provenance"] = provenance
    if config.get("borealtc_dir"):
        inputs.update(
            {
                f"replay_{name}": f"{REAL}/metrics/replay_{name}.csv"
                for name in ("per_window", "per_test", "summary", "pairwise", "imu_errors")
            }
        )
        inputs["real_logs"] = [f"{REAL}/logs/{c.upper()}/{run}.parquet" for c, run in RUNS]
        inputs["replay_traces"] = [
            f"{REAL}/replay/{engine}/{c}/{run}.parquet" for engine in ENGINES for c, run in RUNS
        ]
    return inputs


rule report:
    input:
        unpack(report_real_inputs),
        weighted="results/scores/weighted.csv",
        trace_stats="results/metrics/trace_stats.csv",
        reference_stats="results/metrics/reference_stats.csv",
        imu_errors="results/metrics/imu_errors.csv",
        per_test_errors="results/metrics/per_test_errors.csv",
        runs="results/metrics/runs.csv",
        rtf="results/metrics/rtf.csv",
        cpu=expand("results/cpu/{engine}.json", engine=ENGINES),
        qualitative=config["qualitative"],
        table11="results/published/table11.csv",
        table11_comparison="results/published/table11_comparison.csv",
        worked_example="results/published/worked_example.json",
        traces=all_traces(),
    output:
        html="results/report/report.html",
        pdf="results/report/report.pdf",
    params:
        weights=canonical(config["weights"]),
        config=canonical(config),
        accuracy=canonical(
            {
                "reference": config["accuracy"]["reference"],
                "errors_file": accuracy_errors(),
                "dataset": config["real_data"]["dataset"],
                "replay": bool(config.get("borealtc_dir")),
            }
        ),
        real_data=canonical(
            {
                "dataset": config["real_data"]["dataset"],
                "classes": config["real_data"]["classes"],
                "window": config["real_data"]["window"],
                "segment_rules": config["real_data"]["segment_rules"],
            }
        ),
    log:
        "results/logs/report.log",
    script:
        "../scripts/report.py"
