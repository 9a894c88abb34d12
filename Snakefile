# simpick: the Farley, Wang & Marshall (2022) simulator study as a workflow.
# Data flow: validate (engines against analytic mechanics) -> summary; terrain -> simulate -> traces -> metrics (+ cpu load) -> scores -> report;
# the paper's own Table 11 is recomputed beside it; with a `sweep:` config, real-data error against speed per timestep;
# `snakemake calibration` (or calibration.enabled) calibrates every model on training runs and judges it on test runs.
from snakemake.utils import min_version

min_version("9.0")


configfile: "config.yaml"


include: "rules/common.smk"
include: "rules/terrain.smk"
include: "rules/validate.smk"
include: "rules/simulate.smk"
include: "rules/metrics.smk"
include: "rules/real.smk"
include: "rules/sweep.smk"
include: "rules/calibration.smk"
include: "rules/scores.smk"
include: "rules/published.smk"
include: "rules/report.smk"


rule all:
    input:
        "results/validation/summary.csv",
        all_traces(),
        segment_traces(),
        f"{REAL}/metrics/segments_summary.csv",
        [f"results/real/{source}/metrics/replay_summary.csv" for source in REPLAY_CASES],
        [f"{REPLAY}/segments.csv", f"{REPLAY}/dataset.yaml"] if REPLAY_SET else [],
        f"{SWEEP_DIR}/summary.csv" if SWEEP else [],
        CALIBRATION_ALL,
        "results/scores/weighted.csv",
        "results/published/table11.csv",
        "results/report/report.html",
        "results/report/report.pdf",
    default_target: True
