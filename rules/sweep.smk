# Speed-accuracy sweep (config `sweep:`, e.g. --configfile config/sweeps/timestep.yaml): every engine
# over the committed real segments at each timestep, one job per engine x class x timestep, simulated,
# compared and summarised by the segments source's own functions (simpick.sweep).
# Target: `snakemake sweep`. Without a `sweep:` block these rules do not exist.

if SWEEP:

    rule sweep_segments:
        input:
            segments=config["real_data"]["segments"],
            urdf=config["robot"]["urdf"],
        output:
            f"{SWEEP_DIR}/runs/{{engine}}/{{terrain_class}}/{{dt}}.csv",
        log:
            f"{SWEEP_DIR}/logs/{{engine}}/{{terrain_class}}/{{dt}}.log",
        benchmark:
            f"results/benchmarks/sweeps/{SWEEP['name']}/{{engine}}/{{terrain_class}}/{{dt}}.tsv"
        wildcard_constraints:
            engine="|".join(ENGINES),
            terrain_class="|".join(SEGMENTS),
            dt="|".join(re.escape(label) for label in SWEEP_LABELS),
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=400,
            # the 0.5 ms step doubles the segments' cost at 1 ms (DART's class job: about 1 min); a
            # hung case is stopped at health.timeout (300 s in config.yaml) and the cases after it are not run
            runtime=30,
        params:
            case=lambda wc: sweep_params(wc.engine, wc.terrain_class, wc.dt),
            settings=compare_settings("segments"),
            code=lambda wc: script_code(
                "sweep_segments",
                engine_module(wc.engine),
                source_entry("segments", "prepare_case"),
                source_entry("segments", "compare"),
            ),
        script:
            "../scripts/sweep_segments.py"

    rule sweep_summary:
        input:
            sweep_runs(),
        output:
            f"{SWEEP_DIR}/summary.csv",
        log:
            f"{SWEEP_DIR}/logs/summary.log",
        conda:
            "../envs/simpick.yaml"
        params:
            statistics=statistics_params(),
            code=script_code("sweep_summary"),
        script:
            "../scripts/sweep_summary.py"

    rule sweep:
        """The sweep alone (its section appears in the report when the study runs with it)."""
        input:
            f"{SWEEP_DIR}/summary.csv",
