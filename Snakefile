# simpick: the Farley, Wang & Marshall (2022) simulator study as a workflow.
# Data flow (the plan of jobs and the case tables: simpick.plan, built in rules/common.smk as PLAN):
# - one path per case: each source yields a case table (engine-independent rows) and every case goes
#   through the same three families, over a {source} wildcard:
#     simulate (a job per case x model, under the watchdog) -> results/traces/<source>/<model>/<group>/<case>.parquet
#     compare (a job per source: per-test error rows)  -> results/metrics/<source>/{per_test,detail,runs}.csv
#     summarise (a job per source)                     -> results/metrics/<source>/{imu_errors,rtf,summary,pairwise}.csv
#   Sources: lab (terrain -> terrain x motion on every engine, against the paper's reference statistics);
#   segments (the committed resources/real/*_segments.csv, read, never written: every model drives each
#   segment's command, against its real window statistics); a dataset folder (--config borealtc_dir=PATH:
#   dataset_manifest, import_real per run -> results/real/<dataset>/logs/; checkpoint real_segments: its own
#   segment table, a result and the case table of source <dataset>-segments) and own logs (own_logs: import_own_log -> results/real/own/logs/), each replayed run
#   against its real log window by window. Only the maintainers' maintain_segments target copies
#   BorealTC's derived table over the committed one.
# - lab extras: cpu_load per engine; validate (engines against analytic mechanics) -> validation_summary;
#   published: the paper's Table 11 recomputed.
# - scores rest on one source's Eq. 7 totals (accuracy.reference: the segments, the dataset replay, own
#   logs or the paper's lab reference) and record it in results/scores/provenance.yaml, which the report reads.
# - calibration (`snakemake calibration` or calibration.enabled): every model per class on training units
#   (segments, or the replay's runs), judged on test units; sweep (a `sweep:` config): segment error and speed
#   per timestep. Both simulate in-process and feed the report when run.
from snakemake.utils import min_version

from simpick.plan.scheduling import release_scheduler_timers

min_version("9.0")


configfile: "config.yaml"


include: "rules/common.smk"
include: "rules/terrain.smk"
include: "rules/validate.smk"
include: "rules/simulate.smk"
include: "rules/metrics.smk"
include: "rules/real.smk"
include: "rules/drive.smk"
include: "rules/turnmap.smk"
include: "rules/sweep.smk"
include: "rules/calibration.smk"
include: "rules/scores.smk"
include: "rules/tree.smk"
include: "rules/simulators.smk"
include: "rules/published.smk"
include: "rules/report.smk"


# Snakemake's process would wait up to a second for its scheduler's last timer before it exits
# (simpick.plan.scheduling.release_scheduler_timers)
onsuccess:
    release_scheduler_timers()


onerror:
    release_scheduler_timers()


rule all:
    default_target: True
    input:
        PLAN.all_targets(),
        DRIVE_TARGETS,
        TURNMAP_TARGETS,
