# DRIVE sessions (--config drive_dir=PATH): how the real robot turns, per step, and the per-step replay
# cases (simpick.real.drive). DRIVE's files are pickles, which can run code when read: they are read only
# from the folder the user names, by the job; planning lists the folder and reads no pickle.
DRIVE_TARGETS = []

if SETTINGS.drive_dir:
    from simpick.real.drive import sessions_or_exit
    from simpick.real.logs.drive import METADATA, PICKLE

    DRIVE = f"results/drive/{SETTINGS.drive_dataset}"
    DRIVE_SESSIONS = sessions_or_exit(SETTINGS.drive_dir)
    DRIVE_TARGETS = [f"{DRIVE}/{table}.csv" for table in ("sessions", "steps", "turning", "bins", "cases")]

    rule drive_tables:
        input:
            [str(p / METADATA) for p in DRIVE_SESSIONS] + [str(p / PICKLE) for p in DRIVE_SESSIONS],
        output:
            sessions=f"{DRIVE}/sessions.csv",
            steps=f"{DRIVE}/steps.csv",
            turning=f"{DRIVE}/turning.csv",
            bins=f"{DRIVE}/bins.csv",
            cases=f"{DRIVE}/cases.csv",
        log:
            f"results/logs/drive/{SETTINGS.drive_dataset}/drive_tables.log",
        conda:
            "../envs/simpick.yaml"
        params:
            folder=str(SETTINGS.drive_dir),
            name=SETTINGS.drive_dataset,
            declared=canonical(PLAN.config["real_data"]["datasets"][SETTINGS.drive_dataset]),
            code=PLAN.script_code("drive_tables"),
        script:
            "../scripts/drive_tables.py"
