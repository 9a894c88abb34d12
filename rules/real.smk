# Real robot data in: the replay sources' canonical logs (a dataset folder, --config borealtc_dir=PATH,
# in results/real/<dataset>/; the user's own logs, config own_logs, in results/real/own/), a dataset
# folder's own segment table, and the maintainers' copy of it over the committed one (read, never
# written by a run). Each kind of source has its import rule; from the canonical log (or the committed
# table) on, every case goes through the one simulate, compare and summarise family (simulate.smk,
# metrics.smk). The case tables (PLAN.sources, PLAN.replay_cases): simpick.plan.


if PLAN.replay_set:

    rule dataset_manifest:
        """Which folder results/real/<dataset>/ holds the results of (a second folder of the same
        name is then refused before any job: simpick.real.datasets.open_dataset)."""
        output:
            f"{PLAN.replay}/dataset.yaml",
        log:
            f"results/logs/real/{PLAN.replay_set.name}/dataset_manifest.log",
        priority: 50
        conda:
            "../envs/simpick.yaml"
        params:
            dataset=canonical(PLAN.replay_dataset()),
        script:
            "../scripts/dataset_manifest.py"

    rule import_real:
        input:
            imu=lambda wc: str(PLAN.replay_set.run(wc.terrain_class, wc.run).imu),
            pro=lambda wc: str(PLAN.replay_set.run(wc.terrain_class, wc.run).pro),
        output:
            f"{PLAN.replay}/logs/{{terrain_class}}/{{run}}.parquet",
        log:
            f"results/logs/real/{PLAN.replay_set.name}/import/{{terrain_class}}/{{run}}.log",
        wildcard_constraints:
            terrain_class="|".join(PLAN.replay_set.classes),
            run="|".join(sorted({re.escape(run) for _, run in PLAN.runs})),
        conda:
            "../envs/simpick.yaml"
        params:
            folder_class=lambda wc: PLAN.replay_set.run(wc.terrain_class, wc.run).folder,
            # the import job's model (simpick.real.jobs.ImportParams), validated at planning time
            settings=PLAN.import_real_params(),
            code=PLAN.script_code("import_real"),
        script:
            "../scripts/import_real.py"

    # The folder's own constant-command segments: a result, beside its replay, and a source of cases
    # ("<dataset>-segments", simpick.plan) known only once it is written: a checkpoint.
    checkpoint real_segments:
        input:
            logs=PLAN.real_logs(PLAN.replay_set.name),
        output:
            csv=f"{PLAN.replay}/segments.csv",
            provenance=f"{PLAN.replay}/segments.provenance.yaml",
        log:
            f"results/logs/real/{PLAN.replay_set.name}/real_segments.log",
        conda:
            "../envs/simpick.yaml"
        params:
            # the segments job's model (simpick.real.jobs.SegmentsParams), validated at planning time
            rules=PLAN.real_segments_params(),
            code=PLAN.script_code("real_segments"),
        script:
            "../scripts/real_segments.py"


if PLAN.replay_cases:

    # How the real robot turns, the target an engine must meet: its yaw-rate gain in steady-command windows
    # against speed, turn radius and wheel-speed difference, beside the rigid-Coulomb prediction. Per replayed
    # source (the dataset folder, the user's own logs): the calibration's runs where it fits on that source.
    rule real_turning:
        input:
            logs=lambda wc: PLAN.real_logs(wc.source),
            urdf=SETTINGS.robot.urdf,
        output:
            windows="results/real/{source}/turning/windows.csv",
            summary="results/real/{source}/turning/summary.csv",
        log:
            "results/logs/real/{source}/real_turning.log",
        wildcard_constraints:
            source="|".join(re.escape(s) for s in PLAN.replay_cases),
        conda:
            "../envs/simpick.yaml"
        params:
            # the turning job's model (simpick.real.turning.TurningParams), validated at planning time
            settings=PLAN.real_turning_params(),
            code=PLAN.script_code("real_turning"),
        script:
            "../scripts/real_turning.py"


# Maintainers only, on purpose (docs/real-data.md): the BorealTC folder's derived table over the
# committed one. The committed files are never a rule's output, so no failed job can delete them;
# the job replaces them atomically, and its receipt (what changed) is the output.
rule maintain_segments:
    input:
        unpack(PLAN.maintained_table),
    output:
        f"{PLAN.real}/maintain_segments.yaml",
    log:
        "results/logs/real/maintain_segments.log",
    conda:
        "../envs/simpick.yaml"
    params:
        committed=canonical(
            {
                "csv": SETTINGS.real_data.segments,
                "provenance": SETTINGS.real_data.segments.replace(".csv", ".provenance.yaml"),
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


if PLAN.own_logs:

    rule import_own_log:
        """One of the user's logs (a mapped CSV or a ROS bag) to the canonical form, filed under
        its terrain class like a dataset folder's runs."""
        input:
            lambda wc: PLAN.own_log_files(wc.run),
        output:
            f"{PLAN.own}/logs/{{terrain_class}}/{{run}}.parquet",
        log:
            "results/logs/real/own/import/{terrain_class}/{run}.log",
        wildcard_constraints:
            terrain_class="|".join(sorted({re.escape(c) for c, _ in PLAN.replay_cases["own"]})),
            run="|".join(sorted(re.escape(name) for name in PLAN.own_logs)),
        conda:
            "../envs/simpick.yaml"
        params:
            entry=lambda wc: canonical(PLAN.own_logs[wc.run]),
            track=canonical(SETTINGS.robot.track),
            code=PLAN.script_code("import_own_log"),
        script:
            "../scripts/import_own_log.py"
