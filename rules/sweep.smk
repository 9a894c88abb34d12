# Speed-accuracy sweep (config `sweep:`, e.g. --configfile config/sweeps/timestep.yaml): every engine
# over the committed real segments at each timestep, one job per engine x class x timestep, simulated,
# compared and summarised by the segments source's own functions (simpick.studies.sweep).
# Target: `snakemake sweep`. Without a `sweep:` block these rules do not exist.

if PLAN.sweep:

    rule sweep_segments:
        input:
            segments=SETTINGS.real_data.segments,
            urdf=SETTINGS.robot.urdf,
        output:
            f"{PLAN.sweep_dir}/runs/{{engine}}/{{terrain_class}}/{{dt}}.csv",
        log:
            f"{PLAN.sweep_dir}/logs/{{engine}}/{{terrain_class}}/{{dt}}.log",
        benchmark:
            f"results/benchmarks/sweeps/{PLAN.sweep.name}/{{engine}}/{{terrain_class}}/{{dt}}.tsv"
        wildcard_constraints:
            engine="|".join(PLAN.engines),
            terrain_class="|".join(PLAN.segments),
            dt="|".join(re.escape(label) for label in PLAN.sweep_labels),
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=400,
            # the 0.5 ms step doubles the segments' cost at 1 ms (DART's class job: about 1 min); a
            # hung case is stopped at health.timeout (300 s in config.yaml) and the cases after it are not run
            runtime=30,
        params:
            case=lambda wc: PLAN.sweep_params(wc.engine, wc.terrain_class, wc.dt),
            settings=PLAN.compare_settings("segments"),
            code=lambda wc: PLAN.sweep_code(wc.engine),
        script:
            "../scripts/sweep_segments.py"

    rule sweep_summary:
        input:
            PLAN.sweep_runs(),
        output:
            f"{PLAN.sweep_dir}/summary.csv",
        log:
            f"{PLAN.sweep_dir}/logs/summary.log",
        conda:
            "../envs/simpick.yaml"
        params:
            statistics=PLAN.statistics_params(),
            code=PLAN.script_code("sweep_summary"),
        script:
            "../scripts/sweep_summary.py"

    rule sweep:
        """The sweep alone (its section appears in the report when the study runs with it)."""
        input:
            f"{PLAN.sweep_dir}/summary.csv",
