rule simulate:
    input:
        terrain="results/terrains/{terrain}.json",
        urdf=config["robot"]["urdf"],
    output:
        "results/traces/{engine}/{terrain}/{motion}.parquet",
    params:
        case=lambda wc: simulation_params(wc.engine, wc.terrain, wc.motion),
        code=lambda wc: engine_code(wc.engine),
    log:
        "results/logs/simulate/{engine}/{terrain}/{motion}.log",
    benchmark:
        "results/benchmarks/simulate/{engine}/{terrain}/{motion}.tsv"
    threads: 1
    resources:
        mem_mb=400,
        runtime=lambda wc: 1 + int(config["health"]["timeout"]) // 60,
    conda:
        "../envs/simpick.yaml"
    script:
        "../scripts/simulate.py"


rule cpu_load:
    input:
        terrain=f"results/terrains/{config['cpu_load']['terrain']}.json",
        urdf=config["robot"]["urdf"],
    output:
        "results/cpu/{engine}.json",
    params:
        case=lambda wc: simulation_params(
            wc.engine, config["cpu_load"]["terrain"], config["cpu_load"]["motion"]
        )
        | {"cpu_load": canonical(config["cpu_load"])},
        code=lambda wc: engine_code(wc.engine, "cpuload.py"),
    log:
        "results/logs/cpu_load/{engine}.log",
    benchmark:
        "results/benchmarks/cpu_load/{engine}.tsv"
    threads: 1
    resources:
        mem_mb=600,
        runtime=15,
    conda:
        "../envs/simpick.yaml"
    script:
        "../scripts/cpu_load.py"
