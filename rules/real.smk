# Real robot data: constant-command segments (the committed table, read, never written) and
# the full replay of a replay source: a dataset folder (--config borealtc_dir=PATH; results in
# results/real/<dataset>/) or the user's own logs (config own_logs; results/real/own/). Each
# kind of source has its import rule; from the canonical log on, every source goes through the
# same replay and replay_metrics rules. Helpers (the case tables REPLAY_CASES) in common.smk.


# One job per terrain class and engine: its segments are short runs sharing one import.
for _cls, _ids in SEGMENTS.items():

    rule:
        name:
            f"simulate_segments_{_cls}"
        input:
            segments=config["real_data"]["segments"],
            urdf=config["robot"]["urdf"],
        output:
            expand(
                f"{REAL}/segments/{{{{engine}}}}/{_cls}/{{segment}}.parquet",
                segment=_ids,
            ),
        params:
            case=lambda wc, cls=_cls: real_params(wc.engine, cls),
            code=lambda wc: engine_code(wc.engine, "realdata.py"),
        log:
            f"results/logs/real/segments/{{engine}}/{_cls}.log",
        benchmark:
            f"results/benchmarks/segments/{{engine}}/{_cls}.tsv"
        threads: 1
        resources:
            mem_mb=400,
            runtime=15,
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/simulate_segments.py"


rule segment_metrics:
    input:
        segments=config["real_data"]["segments"],
        traces=segment_traces(),
    output:
        per_test=f"{REAL}/metrics/segments_per_test.csv",
        summary=f"{REAL}/metrics/segments_summary.csv",
        pairwise=f"{REAL}/metrics/segments_pairwise.csv",
        imu_errors=f"{REAL}/metrics/segments_imu_errors.csv",
    params:
        track=canonical(config["robot"]["track"]),
        statistics=statistics_params(),
        code=code_version("realdata.py", "realmetrics.py", "metrics.py", "traces.py", "workflow.py"),
    log:
        "results/logs/real/segment_metrics.log",
    conda:
        "../envs/simpick.yaml"
    script:
        "../scripts/segment_metrics.py"


if REPLAY_SET:

    rule dataset_manifest:
        """Which folder results/real/<dataset>/ holds the results of (a second folder of the same
        name is then refused before any job: simpick.datasets.open_dataset)."""
        output:
            f"{REPLAY}/dataset.yaml",
        params:
            dataset=canonical(replay_dataset()),
        priority: 50
        log:
            f"results/logs/real/{REPLAY_SET.name}/dataset_manifest.log",
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/dataset_manifest.py"

    rule import_real:
        input:
            imu=lambda wc: str(REPLAY_SET.run(wc.terrain_class, wc.run).imu),
            pro=lambda wc: str(REPLAY_SET.run(wc.terrain_class, wc.run).pro),
        output:
            f"{REPLAY}/logs/{{terrain_class}}/{{run}}.parquet",
        params:
            folder_class=lambda wc: REPLAY_SET.run(wc.terrain_class, wc.run).folder,
            settings=canonical(
                {
                    "track": config["robot"]["track"],
                    "dataset": REPLAY_SET.name,
                    "label": replay_dataset()["label"],
                    "declared": replay_dataset()["declared"],
                }
            ),
            code=code_version("reallogs", "realdata.py"),
        wildcard_constraints:
            terrain_class="|".join(REPLAY_SET.classes),
            run="|".join(sorted({re.escape(run) for _, run in RUNS})),
        log:
            f"results/logs/real/{REPLAY_SET.name}/import/{{terrain_class}}/{{run}}.log",
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/import_real.py"

    # The folder's own constant-command segments: a result, beside its replay.
    rule real_segments:
        input:
            logs=real_logs(REPLAY_SET.name),
        output:
            csv=f"{REPLAY}/segments.csv",
            provenance=f"{REPLAY}/segments.provenance.yaml",
        params:
            rules=canonical(
                {
                    "segment_rules": config["real_data"]["segment_rules"],
                    "track": config["robot"]["track"],
                    "source": replay_dataset()["source"],
                }
            ),
            code=code_version("realsegments.py", "realdata.py", "reallogs"),
        log:
            f"results/logs/real/{REPLAY_SET.name}/real_segments.log",
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/real_segments.py"


# Maintainers only, on purpose (README "Real data"): the BorealTC folder's derived table over the
# committed one. The committed files are never a rule's output, so no failed job can delete them;
# the job replaces them atomically, and its receipt (what changed) is the output.
rule maintain_segments:
    input:
        unpack(maintained_table),
    output:
        f"{REAL}/maintain_segments.yaml",
    params:
        committed=canonical(
            {
                "csv": config["real_data"]["segments"],
                "provenance": config["real_data"]["segments"].replace(".csv", ".provenance.yaml"),
            }
        ),
    log:
        "results/logs/real/maintain_segments.log",
    conda:
        "../envs/simpick.yaml"
    script:
        "../scripts/maintain_segments.py"


rule fetch_borealtc:
    """For users who are online: the public dataset into data/borealtc (not part of the
    project; git-ignored). Then run with --config borealtc_dir=data/borealtc."""
    output:
        directory("data/borealtc"),
    log:
        "results/logs/real/fetch_borealtc.log",
    conda:
        "../envs/simpick.yaml"
    script:
        "../scripts/fetch_borealtc.py"


if OWN_LOGS:

    rule import_own_log:
        """One of the user's logs (a mapped CSV or a ROS bag) to the canonical form, filed under
        its terrain class like a dataset folder's runs."""
        output:
            f"{OWN}/logs/{{terrain_class}}/{{run}}.parquet",
        params:
            entry=lambda wc: canonical(OWN_LOGS[wc.run]),
            track=canonical(config["robot"]["track"]),
            code=code_version("reallogs", "realdata.py"),
        wildcard_constraints:
            terrain_class="|".join(sorted({re.escape(c) for c, _ in REPLAY_CASES["own"]})),
            run="|".join(sorted(re.escape(name) for name in OWN_LOGS)),
        log:
            "results/logs/real/own/import/{terrain_class}/{run}.log",
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/import_own_log.py"


# One replay family for every source: a case's canonical log driven through one model (under
# the watchdog: simpick.realdata.replay_job), then all of a source's cases compared at once.
if REPLAY_CASES:
    _SOURCES = "|".join(re.escape(source) for source in REPLAY_CASES)

    rule replay:
        input:
            log="results/real/{source}/logs/{terrain_class}/{run}.parquet",
            urdf=config["robot"]["urdf"],
        output:
            "results/real/{source}/replay/{engine}/{terrain_class}/{run}.parquet",
        params:
            case=lambda wc: real_params(wc.engine, wc.terrain_class),
            code=lambda wc: engine_code(wc.engine, "realdata.py", "reallogs"),
        wildcard_constraints:
            source=_SOURCES,
            terrain_class="|".join(sorted({re.escape(c) for cases in REPLAY_CASES.values() for c, _ in cases})),
            run="|".join(sorted({re.escape(run) for cases in REPLAY_CASES.values() for _, run in cases})),
        log:
            "results/logs/real/{source}/replay/{engine}/{terrain_class}/{run}.log",
        benchmark:
            "results/benchmarks/replay/{source}/{engine}/{terrain_class}/{run}.tsv"
        threads: 1
        resources:
            mem_mb=800,
            runtime=30,
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/replay.py"

    rule replay_metrics:
        input:
            logs=lambda wc: real_logs(wc.source),
            traces=lambda wc: replay_traces(wc.source),
        output:
            per_window="results/real/{source}/metrics/replay_per_window.csv",
            per_test="results/real/{source}/metrics/replay_per_test.csv",
            summary="results/real/{source}/metrics/replay_summary.csv",
            pairwise="results/real/{source}/metrics/replay_pairwise.csv",
            imu_errors="results/real/{source}/metrics/replay_imu_errors.csv",
        params:
            settings=canonical(
                {
                    "track": config["robot"]["track"],
                    "window": config["real_data"]["window"],
                    "statistics": statistics_params(),
                }
            ),
            code=code_version(
                "realdata.py", "realmetrics.py", "metrics.py", "traces.py", "workflow.py", "reallogs"
            ),
        wildcard_constraints:
            source=_SOURCES,
        log:
            "results/logs/real/{source}/replay_metrics.log",
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/replay_metrics.py"
