# Real robot data: constant-command segments (committed, default) and the full replay
# of a BorealTC-layout folder (--config borealtc_dir=PATH). Helpers in common.smk.


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
    log:
        "results/logs/real/segment_metrics.log",
    conda:
        "../envs/simpick.yaml"
    script:
        "../scripts/segment_metrics.py"


if config.get("borealtc_dir"):

    rule real_segments:
        input:
            [
                f"{config['borealtc_dir']}/{c.upper()}/{kind}_{run}.csv"
                for c, run in RUNS
                for kind in ("imu", "pro")
            ],
        output:
            csv=config["real_data"]["segments"],
            provenance=config["real_data"]["segments"].replace(".csv", ".provenance.yaml"),
        params:
            folder=config["borealtc_dir"],
            rules=canonical(
                {
                    "segment_rules": config["real_data"]["segment_rules"],
                    "track": config["robot"]["track"],
                }
            ),
        log:
            "results/logs/real/real_segments.log",
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/real_segments.py"

    rule import_real:
        input:
            imu=f"{config['borealtc_dir']}/{{upper}}/imu_{{run}}.csv",
            pro=f"{config['borealtc_dir']}/{{upper}}/pro_{{run}}.csv",
        output:
            f"{REAL}/logs/{{upper}}/{{run}}.parquet",
        params:
            folder=config["borealtc_dir"],
            track=canonical(config["robot"]["track"]),
        log:
            "results/logs/real/import/{upper}/{run}.log",
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/import_real.py"

    rule replay:
        input:
            log=lambda wc: f"{REAL}/logs/{wc.terrain_class.upper()}/{wc.run}.parquet",
            urdf=config["robot"]["urdf"],
        output:
            f"{REAL}/replay/{{engine}}/{{terrain_class}}/{{run}}.parquet",
        params:
            case=lambda wc: real_params(wc.engine, wc.terrain_class),
        log:
            "results/logs/real/replay/{engine}/{terrain_class}/{run}.log",
        benchmark:
            "results/benchmarks/replay/{engine}/{terrain_class}/{run}.tsv"
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
            logs=[f"{REAL}/logs/{c.upper()}/{run}.parquet" for c, run in RUNS],
            traces=[
                f"{REAL}/replay/{engine}/{c}/{run}.parquet"
                for engine in REAL_MODELS
                for c, run in RUNS
            ],
        output:
            per_window=f"{REAL}/metrics/replay_per_window.csv",
            per_test=f"{REAL}/metrics/replay_per_test.csv",
            summary=f"{REAL}/metrics/replay_summary.csv",
            pairwise=f"{REAL}/metrics/replay_pairwise.csv",
            imu_errors=f"{REAL}/metrics/replay_imu_errors.csv",
        params:
            settings=canonical(
                {"track": config["robot"]["track"], "window": config["real_data"]["window"]}
            ),
        log:
            "results/logs/real/replay_metrics.log",
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/replay_metrics.py"


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
        output:
            f"{OWN}/logs/{{name}}.parquet",
        params:
            entry=lambda wc: canonical(OWN_LOGS[wc.name]),
            track=canonical(config["robot"]["track"]),
        log:
            "results/logs/real/own/import/{name}.log",
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/import_own_log.py"

    rule replay_own:
        input:
            log=f"{OWN}/logs/{{name}}.parquet",
            urdf=config["robot"]["urdf"],
        output:
            f"{OWN}/replay/{{engine}}/{{name}}.parquet",
        params:
            case=lambda wc: real_params(wc.engine, OWN_LOGS[wc.name]["terrain_class"]),
        log:
            "results/logs/real/own/replay/{engine}/{name}.log",
        threads: 1
        resources:
            mem_mb=800,
            runtime=30,
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/replay.py"

    rule replay_own_metrics:
        input:
            logs=expand(f"{OWN}/logs/{{name}}.parquet", name=OWN_LOGS),
            traces=expand(f"{OWN}/replay/{{engine}}/{{name}}.parquet", engine=REAL_MODELS, name=OWN_LOGS),
        output:
            per_window=f"{OWN}/metrics/replay_per_window.csv",
            per_test=f"{OWN}/metrics/replay_per_test.csv",
            summary=f"{OWN}/metrics/replay_summary.csv",
            pairwise=f"{OWN}/metrics/replay_pairwise.csv",
            imu_errors=f"{OWN}/metrics/replay_imu_errors.csv",
        params:
            settings=canonical(
                {"track": config["robot"]["track"], "window": config["real_data"]["window"]}
            ),
        log:
            "results/logs/real/own/replay_metrics.log",
        conda:
            "../envs/simpick.yaml"
        script:
            "../scripts/replay_metrics.py"
