# The DRIVE source (--config drive_dir=PATH; simpick.sources.drive): its import step reads the session
# folders into the step units' tables (simpick.real.drive, simpick.real.steps: the case, step and wheels
# tables, and how the real robot turns); then every chosen step replayed in every model (a job per model x
# session, the steps kind: simpick.simulate.steps) and compared with the real robot (simpick.compare.steps,
# simpick.score.steps). DRIVE's files are pickles, which can run code when read: they are read only from
# the folder the user names, by the import step; planning lists the folder and reads no pickle. The
# sessions replayed are those the import step kept (one per content: a folder holding a copy of another's
# pickle is not replayed twice): a checkpoint.
DRIVE_TARGETS = []

if SETTINGS.drive_dir:
    from simpick.errors import InputError
    from simpick.sources import module as source_module

    # the DRIVE source (simpick.sources.drive): which folders are sessions, which this study can replay,
    # which models replay them, and each job's inputs and parameters
    DRIVE_SOURCE = source_module("drive")
    DRIVE = DRIVE_SOURCE.root(SETTINGS)
    DRIVE_SESSIONS = DRIVE_SOURCE.folders(SETTINGS.drive_dir)
    DRIVE_FOLDERS = {p.name: p for p in DRIVE_SESSIONS}
    DRIVE_SPEC = {"folders": DRIVE_FOLDERS}
    # what the jobs read of the declaration (its robot is the plan's alone: checked below)
    DRIVE_DECLARED = DRIVE_SOURCE.declared(SETTINGS)
    # each session's metadata.yaml (YAML, no pickle): another robot's session, a tracked one, or one whose
    # terrain has no ground model is refused now, one line each, before any job
    _problems = DRIVE_SOURCE.problems(
        DRIVE_SESSIONS,
        SETTINGS.real_data.datasets[SETTINGS.drive_dataset],  # keyed by dataset name (data)
        SETTINGS.real_data.classes,
        PLAN.robot.name,
        SETTINGS.drive_dataset,
    )
    for _problem in _problems:
        print(f"simpick: {_problem}", file=sys.stderr)
    if _problems:
        sys.exit(1)
    try:
        # simulator profiles replay DRIVE only with simulators.drive: each adds its engine's replay time (a
        # calibrated profile's fit is then made on DRIVE's training steps, its replay merges it)
        DRIVE_MODELS = DRIVE_SOURCE.models(
            SETTINGS.drive_replay.models,
            [m for m in PLAN.real_models if SETTINGS.simulators.drive or m not in PLAN.profiles],
            PLAN.unavailable,
        )
    except InputError as _exc:
        print(f"simpick: {_exc}", file=sys.stderr)
        sys.exit(1)
    DRIVE_TARGETS = [f"{DRIVE}/{table}.csv" for table in DRIVE_SOURCE.TABLES]
    DRIVE_TARGETS += [f"{DRIVE}/{table}.csv" for table in ("errors", "summary", "outcomes")]

    checkpoint drive_tables:
        input:
            [f for p in DRIVE_SESSIONS for f in DRIVE_SOURCE.session_files(p)],
        output:
            sessions=f"{DRIVE}/sessions.csv",
            steps=f"{DRIVE}/steps.csv",
            turning=f"{DRIVE}/turning.csv",
            bins=f"{DRIVE}/bins.csv",
            cases=f"{DRIVE}/cases.csv",
            wheels=f"{DRIVE}/{DRIVE_SOURCE.WHEELS}",
        log:
            f"results/logs/drive/{SETTINGS.drive_dataset}/drive_tables.log",
        conda:
            "../envs/simpick.yaml"
        params:
            folder=str(SETTINGS.drive_dir),
            name=SETTINGS.drive_dataset,
            declared=DRIVE_DECLARED,
            code=PLAN.script_code("drive_tables"),
        script:
            "../scripts/drive_tables.py"

    rule drive_replay:
        """One model x one DRIVE session: its chosen steps (drive_replay.every, max_steps_per_session),
        each from its warm-up, under the watchdog, driven by the wheels table (simpick.simulate.steps)."""
        input:
            # a calibrated profile's fit (its settings merged at run time)
            unpack(lambda wc: PLAN.calibrated_input(wc.model)),
            **DRIVE_SOURCE.case_inputs(SETTINGS, "drive", DRIVE_SPEC, "", []),
        output:
            trace=f"{DRIVE}/replay/{{model}}/{{session}}.parquet",
            steps=f"{DRIVE}/replay/{{model}}/{{session}}.csv",
        log:
            f"results/logs/drive/{SETTINGS.drive_dataset}/replay/{{model}}/{{session}}.log",
        benchmark:
            f"results/benchmarks/drive/{SETTINGS.drive_dataset}/replay/{{model}}/{{session}}.tsv"
        wildcard_constraints:
            model="|".join(DRIVE_MODELS),
            session="|".join(re.escape(s) for s in DRIVE_FOLDERS),
        # the model's measured seconds per replay job (simpick.plan.costs): DART's and Drake's start first
        priority: lambda wc: PLAN.job_priority("drive_replay", wc.model)
        conda:
            "../envs/simpick.yaml"
        resources:
            runtime=120,
        params:
            case=lambda wc: PLAN.drive_replay_params(wc.model, wc.session),
            code=lambda wc: PLAN.script_code("drive_replay", *PLAN.engine_modules(wc.model)),
        script:
            "../scripts/drive_replay.py"

    rule drive_compare:
        """Every replayed step against the real robot: errors per step, pooled per session and terrain,
        and the verdict (every engine against the best, with equivalence)."""
        input:
            cases=f"{DRIVE}/cases.csv",
            steps=f"{DRIVE}/steps.csv",
            replayed=drive_replayed,
            validation="results/validation/summary.csv",
        output:
            errors=f"{DRIVE}/errors.csv",
            summary=f"{DRIVE}/summary.csv",
            outcomes=f"{DRIVE}/outcomes.csv",
            # the tables rule answer reads beside the outcomes where the study's first page rests on DRIVE,
            # in the verdict's form (results/verdict/): over every terrain, one test per step
            per_test=f"{DRIVE}/per_test.csv",
            metrics=f"{DRIVE}/metrics.csv",
            table=f"{DRIVE}/table.csv",
            mechanics=f"{DRIVE}/mechanics.csv",
        log:
            f"results/logs/drive/{SETTINGS.drive_dataset}/drive_compare.log",
        conda:
            "../envs/simpick.yaml"
        params:
            settings=PLAN.drive_compare_params([m for m in DRIVE_MODELS if m in PLAN.engines]),
            code=PLAN.script_code("drive_compare"),
        script:
            "../scripts/drive_compare.py"

    # Calibration on DRIVE steps (simpick.studies.calibration.steps): every model that declares calibratable
    # parameters, per terrain class, trained on some chosen steps and judged on the others. In `snakemake`
    # (all) when calibration.enabled; `snakemake drive_calibration` runs it either way.
    DRIVE_CAL = f"{DRIVE}/calibration"
    # the plan's calibrated models (calibration.models, those that declare parameters), among the replay's
    DRIVE_CAL_MODELS = [m for m in DRIVE_MODELS if m in PLAN.cal_models]

    rule drive_calibrate:
        """One model x one terrain class: the seeded split of its chosen steps, the search on the training
        steps, both variants evaluated on every step."""
        input:
            cases=f"{DRIVE}/cases.csv",
            steps=f"{DRIVE}/steps.csv",
            wheels=f"{DRIVE}/{DRIVE_SOURCE.WHEELS}",
            urdf=SETTINGS.robot.urdf,
        output:
            best=f"{DRIVE_CAL}/{{model}}/{{terrain}}/best.yaml",
            trials=f"{DRIVE_CAL}/{{model}}/{{terrain}}/trials.csv",
            evals=f"{DRIVE_CAL}/{{model}}/{{terrain}}/evals.csv",
            split=f"{DRIVE_CAL}/{{model}}/{{terrain}}/split.csv",
        log:
            f"results/logs/drive/{SETTINGS.drive_dataset}/calibrate/{{model}}/{{terrain}}.log",
        wildcard_constraints:
            model="|".join(DRIVE_CAL_MODELS) or "no-model",
            terrain="|".join(re.escape(c) for c in SETTINGS.real_data.classes),
        conda:
            "../envs/simpick.yaml"
        resources:
            runtime=240,
        params:
            settings=lambda wc: PLAN.drive_calibrate_params(wc.model, wc.terrain),
            code=lambda wc: PLAN.script_code("drive_calibrate", *PLAN.engine_modules(wc.model)),
        script:
            "../scripts/drive_calibrate.py"

    rule drive_calibration:
        """The project's calibration summary over every model x class, and the held-out gains with the
        equivalent wheel_separation_multiplier."""
        input:
            evals=drive_cal_files,
            bests=lambda wc: drive_cal_files(wc, "best.yaml"),
            cases=f"{DRIVE}/cases.csv",
            steps=f"{DRIVE}/steps.csv",
            sessions=f"{DRIVE}/sessions.csv",
            urdf=SETTINGS.robot.urdf,
        output:
            summary=f"{DRIVE_CAL}/summary.csv",
            turning=f"{DRIVE_CAL}/turning.csv",
        log:
            f"results/logs/drive/{SETTINGS.drive_dataset}/drive_calibration.log",
        conda:
            "../envs/simpick.yaml"
        params:
            settings=PLAN.drive_calibration_params(),
            code=PLAN.script_code("drive_calibration"),
        script:
            "../scripts/drive_calibration.py"

    if SETTINGS.calibration and SETTINGS.calibration.enabled:
        DRIVE_TARGETS += [f"{DRIVE_CAL}/summary.csv", f"{DRIVE_CAL}/turning.csv"]
