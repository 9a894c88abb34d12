# How the real robot turns across DRIVE's command space (--config drive_dir=PATH), beside the quasi-static
# Coulomb reference and each engine (simpick.studies.turnmap): the real gain binned per terrain against
# the commanded speed, turn radius and wheel-speed difference; each bin's median step driven on flat ground
# with the terrain's friction in every engine, as the validation's yaw_gain case. Needs rules/drive.smk's
# steps table, so it is included after it.
TURNMAP_TARGETS = []

if SETTINGS.drive_dir:
    TURNMAP = f"{DRIVE}/turnmap"
    TURNMAP_TARGETS = [f"{DRIVE}/turnmap.csv", f"{DRIVE}/turnmap.png"]

    rule turnmap_grid:
        input:
            steps=f"{DRIVE}/steps.csv",
            urdf=PLAN.config["robot"]["urdf"],
        output:
            f"{TURNMAP}/grid.csv",
        log:
            f"results/logs/drive/{SETTINGS.drive_dataset}/turnmap_grid.log",
        conda:
            "../envs/simpick.yaml"
        params:
            case=PLAN.turnmap_params(),
            code=PLAN.script_code("turnmap_grid"),
        script:
            "../scripts/turnmap_grid.py"

    rule turnmap_engine:
        input:
            grid=f"{TURNMAP}/grid.csv",
            urdf=PLAN.config["robot"]["urdf"],
        output:
            f"{TURNMAP}/{{engine}}.csv",
        log:
            f"results/logs/drive/{SETTINGS.drive_dataset}/turnmap_{{engine}}.log",
        benchmark:
            f"results/benchmarks/drive/{SETTINGS.drive_dataset}/turnmap_{{engine}}.tsv"
        conda:
            "../envs/simpick.yaml"
        threads: 1
        params:
            case=lambda wc: PLAN.turnmap_params(wc.engine),
            code=lambda wc: PLAN.script_code("turnmap_engine", *PLAN.engine_modules(wc.engine)),
        script:
            "../scripts/turnmap_engine.py"

    rule turnmap_table:
        input:
            grid=f"{TURNMAP}/grid.csv",
            engines=[f"{TURNMAP}/{e}.csv" for e in PLAN.engines],
        output:
            table=f"{DRIVE}/turnmap.csv",
            wall=f"{TURNMAP}/wall_time.csv",
        log:
            f"results/logs/drive/{SETTINGS.drive_dataset}/turnmap_table.log",
        conda:
            "../envs/simpick.yaml"
        params:
            code=PLAN.script_code("turnmap_table"),
        script:
            "../scripts/turnmap_table.py"

    rule turnmap_figure:
        input:
            f"{DRIVE}/turnmap.csv",
        output:
            f"{DRIVE}/turnmap.png",
        log:
            f"results/logs/drive/{SETTINGS.drive_dataset}/turnmap_figure.log",
        conda:
            "../envs/simpick.yaml"
        params:
            code=PLAN.script_code("turnmap_figure"),
        script:
            "../scripts/turnmap_figure.py"
