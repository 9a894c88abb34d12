# simpick: the Farley, Wang & Marshall (2022) simulator study as a workflow.
# Data flow (helpers and config slices in rules/common.smk):
# - lab study: terrain -> simulate (one engine x terrain x motion) -> metrics (+ cpu_load) -> scores -> report (+ report_pdf);
#   validate (engines against analytic mechanics) -> validation_summary; published: the paper's Table 11 recomputed.
# - real data, committed segments (resources/real/*_segments.csv, read, never written): simulate_segments_<class>
#   -> segment_metrics -> results/real/<dataset>/metrics/segments_*.
# - real data, replay sources (rules/real.smk): a dataset folder (--config borealtc_dir=PATH: dataset_manifest,
#   import_real per run, real_segments: its own segment table) and the user's own logs (own_logs: import_own_log)
#   each give canonical logs in results/real/<source>/logs/; one replay rule (a job per model x case) and one
#   replay_metrics rule (a job per source) serve both. Only the maintainers' maintain_segments target copies
#   BorealTC's derived table over the committed one.
# - scores rest on one set of Eq. 7 errors (accuracy.reference: the segments, the dataset replay, own logs or the
#   paper's lab reference) and record it in results/scores/provenance.yaml, which the report reads.
# - calibration (`snakemake calibration` or calibration.enabled): every model per class on training units
#   (segments, or the replay's runs), judged on test units; sweep (a `sweep:` config): segment error and speed
#   per timestep. Both feed the report when run.
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
