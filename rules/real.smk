# Real robot data in: the replay sources' canonical logs (a dataset folder, --config borealtc_dir=PATH,
# in results/real/<dataset>/; the user's own logs, config own_logs, in results/real/own/), a dataset
# folder's own segment table, and the maintainers' copy of it over the committed one (read, never
# written by a run). Each kind of source has its import rule; from the canonical log (or the committed
# table) on, every case goes through the one simulate, compare and summarise family (simulate.smk,
# metrics.smk). Helpers (the case tables SOURCES, REPLAY_CASES) in common.smk.


if REPLAY_SET:

    rule dataset_manifest:
        """Which folder results/real/<dataset>/ holds the results of (a second folder of the same
        name is then refused before any job: simpick.datasets.open_dataset)."""
        output:
            f"{REPLAY}/dataset.yaml",
        log:
            f"results/logs/real/{REPLAY_SET.name}/dataset_manifest.log",
        priority: 50
        conda:
            "../envs/simpick.yaml"
        params:
            dataset=canonical(replay_dataset()),
        script:
            "../scripts/dataset_manifest.py"

    rule import_real:
        input:
            imu=lambda wc: str(REPLAY_SET.run(wc.terrain_class, wc.run).imu),
            pro=lambda wc: str(REPLAY_SET.run(wc.terrain_class, wc.run).pro),
        output:
            f"{REPLAY}/logs/{{terrain_class}}/{{run}}.parquet",
        log:
            f"results/logs/real/{REPLAY_SET.name}/import/{{terrain_class}}/{{run}}.log",
        wildcard_constraints:
            terrain_class="|".join(REPLAY_SET.classes),
            run="|".join(sorted({re.escape(run) for _, run in RUNS})),
        conda:
            "../envs/simpick.yaml"
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
            code=script_code("import_real"),
        script:
            "../scripts/import_real.py"

    # The folder's own constant-command segments: a result, beside its replay, and a source of cases
    # ("<dataset>-segments", rules/common.smk) known only once it is written: a checkpoint.
    checkpoint real_segments:
        input:
            logs=real_logs(REPLAY_SET.name),
        output:
            csv=f"{REPLAY}/segments.csv",
            provenance=f"{REPLAY}/segments.provenance.yaml",
        log:
            f"results/logs/real/{REPLAY_SET.name}/real_segments.log",
        conda:
            "../envs/simpick.yaml"
        params:
            rules=canonical(
                {
                    "segment_rules": config["real_data"]["segment_rules"],
                    "track": config["robot"]["track"],
                    "source": replay_dataset()["source"],
                }
            ),
            code=script_code("real_segments"),
        script:
            "../scripts/real_segments.py"

    # How the real robot turns (issue 20, point 0): its yaw-rate gain in steady-command windows
    # against speed, turn radius and wheel-speed difference, beside the rigid-Coulomb prediction.
    rule real_turning:
        input:
            logs=real_logs(REPLAY_SET.name),
            urdf=config["robot"]["urdf"],
        output:
            windows=f"{REPLAY}/turning/windows.csv",
            summary=f"{REPLAY}/turning/summary.csv",
        log:
            f"results/logs/real/{REPLAY_SET.name}/real_turning.log",
        conda:
            "../envs/simpick.yaml"
        params:
            settings=canonical(
                {
                    "track": config["robot"]["track"],
                    "window": 1.0,  # s: short enough for many windows a run, long for a mean of 100 samples
                    "settle": 0.5,  # s of held command before a window (wheel speeds settle in ~0.3 s)
                    "tolerance": config["real_data"]["segment_rules"]["tolerance"],
                    "min_turn": config["real_data"]["segment_rules"]["min_turn"],
                }
            ),
            code=script_code("real_turning"),
        script:
            "../scripts/real_turning.py"


# Maintainers only, on purpose (README "Real data"): the BorealTC folder's derived table over the
# committed one. The committed files are never a rule's output, so no failed job can delete them;
# the job replaces them atomically, and its receipt (what changed) is the output.
rule maintain_segments:
    input:
        unpack(maintained_table),
    output:
        f"{REAL}/maintain_segments.yaml",
    log:
        "results/logs/real/maintain_segments.log",
    conda:
        "../envs/simpick.yaml"
    params:
        committed=canonical(
            {
                "csv": config["real_data"]["segments"],
                "provenance": config["real_data"]["segments"].replace(".csv", ".provenance.yaml"),
            }
        ),
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
        log:
            "results/logs/real/own/import/{terrain_class}/{run}.log",
        wildcard_constraints:
            terrain_class="|".join(sorted({re.escape(c) for c, _ in REPLAY_CASES["own"]})),
            run="|".join(sorted(re.escape(name) for name in OWN_LOGS)),
        conda:
            "../envs/simpick.yaml"
        params:
            entry=lambda wc: canonical(OWN_LOGS[wc.run]),
            track=canonical(config["robot"]["track"]),
            code=script_code("import_own_log"),
        script:
            "../scripts/import_own_log.py"
