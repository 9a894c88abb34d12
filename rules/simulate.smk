# One simulate family for every source's cases (case tables: PLAN.sources, simpick.plan): a job steps
# its cases on one model, each under the watchdog (simpick.simulate.jobs.simulate_job; health.timeout), and
# writes a trace per case. The unit is one case (rule `simulate`, over {source}), except for a batched
# source (simpick.plan.sources.BATCHED), whose cases share one process and its imports: the committed
# segments, every segment on one model in one job (simulate_segments); the lab, a terrain's motions on one
# engine (simulate_lab, over {group}); a replayed dataset folder's or own logs' runs, a terrain class's on one
# model in one job (simulate_<source>_<class>, BATCHED_KINDS). Snakemake gives a rule a fixed number of
# outputs, so a batched source (or class) has a rule of its own. A dataset folder's derived segments are one
# job each: their ids exist only after the checkpoint.
for _rule, _outputs, _stem, _fixed in PLAN.simulate_units():

    rule:
        name:
            _rule
        input:
            unpack(lambda wc, fixed=_fixed: PLAN.unit_inputs(*PLAN.unit(wc, fixed))),
        output:
            _outputs,
        log:
            f"results/logs/simulate/{_stem}.log",
        benchmark:
            f"results/benchmarks/simulate/{_stem}.tsv"
        wildcard_constraints:
            **PLAN.unit_constraints(_fixed),
        # long jobs first (measured cost per case, times the unit's cases: simpick.plan.costs)
        priority: lambda wc, fixed=_fixed: PLAN.simulate_priority(*PLAN.unit(wc, fixed)[:2], len(PLAN.unit(wc, fixed)[3]))
        conda:
            "../envs/simpick.yaml"
        threads: 1
        resources:
            mem_mb=lambda wc, fixed=_fixed: PLAN.source_of(PLAN.unit(wc, fixed)[0]).MEM_MB,
            # each case is stopped by the watchdog at health.timeout (its hard fallback 30 s later)
            runtime=lambda wc, fixed=_fixed: PLAN.simulate_runtime(len(PLAN.unit(wc, fixed)[3])),
        params:
            case=lambda wc, fixed=_fixed: PLAN.simulate_params(*PLAN.unit(wc, fixed)),
            code=lambda wc, fixed=_fixed: PLAN.case_code(PLAN.unit(wc, fixed)[0], wc.engine),
        script:
            "../scripts/simulate.py"


rule cpu_load:
    input:
        terrain=f"results/terrains/{SETTINGS.cpu_load.terrain}.json",
        urdf=PLAN.config["robot"]["urdf"],
    output:
        "results/cpu/{engine}.json",
    log:
        "results/logs/cpu_load/{engine}.log",
    benchmark:
        "results/benchmarks/cpu_load/{engine}.tsv"
    priority: lambda wc: PLAN.job_priority("cpu_load", wc.engine)
    conda:
        "../envs/simpick.yaml"
    threads: 1
    resources:
        mem_mb=600,
        runtime=15,
    params:
        case=lambda wc: PLAN.cpu_load_params(wc.engine),
        code=lambda wc: PLAN.script_code("cpu_load", *PLAN.engine_modules(wc.engine)),
    script:
        "../scripts/cpu_load.py"
