# Real robot data: constant-command segments (committed, default) and the full replay
# of a BorealTC-layout folder (--config borealtc_dir=PATH).
import csv
import os

DATASET = config["real_data"]["dataset"]
REAL = f"results/real/{DATASET}"


def read_segments(path):
    """terrain class -> segment ids, from the committed table (plain csv: fast to parse).
    Absent only while it is being derived (the config check demands it otherwise)."""
    by_class = {}
    if not os.path.exists(path):
        return by_class
    with open(path, newline="") as handle:
        for row in csv.DictReader(handle):
            by_class.setdefault(row["terrain_class"], []).append(row["segment"])
    unknown = sorted(set(by_class) - set(config["real_data"]["classes"]))
    if unknown:
        raise WorkflowError(
            f"{path}: terrain classes {unknown} have no entry under real_data.classes in the config"
        )
    return by_class


def real_params(engine, terrain_class):
    return engine_params(engine) | canonical(
        {
            "terrain_class": terrain_class,
            "class": config["real_data"]["classes"][terrain_class],
        }
    )


SEGMENTS = read_segments(config["real_data"]["segments"])


def segment_traces():
    return [
        f"{REAL}/segments/{engine}/{cls}/{segment}.parquet"
        for engine in ENGINES
        for cls, ids in SEGMENTS.items()
        for segment in ids
    ]


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
    script:
        "../scripts/segment_metrics.py"


if config.get("borealtc_dir"):
    from simpick.realdata import discover_runs

    RUNS = discover_runs(config["borealtc_dir"])

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
        script:
            "../scripts/replay.py"

    rule replay_metrics:
        input:
            logs=[f"{REAL}/logs/{c.upper()}/{run}.parquet" for c, run in RUNS],
            traces=[
                f"{REAL}/replay/{engine}/{c}/{run}.parquet"
                for engine in ENGINES
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
        script:
            "../scripts/replay_metrics.py"


def accuracy_errors():
    """The Eq. 7 totals the accuracy scores rest on (see accuracy.reference in the config)."""
    if config["accuracy"]["reference"] == "paper":
        return "results/metrics/imu_errors.csv"
    if config.get("borealtc_dir"):
        return f"{REAL}/metrics/replay_imu_errors.csv"
    return f"{REAL}/metrics/segments_imu_errors.csv"


rule fetch_borealtc:
    """For users who are online: the public dataset into data/borealtc (not part of the
    project; git-ignored). Then run with --config borealtc_dir=data/borealtc."""
    output:
        directory("data/borealtc"),
    log:
        "results/logs/real/fetch_borealtc.log",
    script:
        "../scripts/fetch_borealtc.py"
