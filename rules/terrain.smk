rule terrain:
    output:
        "results/terrains/{terrain}.json",
    params:
        spec=lambda wc: canonical(config["terrains"][wc.terrain]),
        seed=lambda wc: canonical(config["seed"]),
        code=script_code("terrain"),
    log:
        "results/logs/terrain/{terrain}.log",
    conda:
        "../envs/simpick.yaml"
    script:
        "../scripts/terrain.py"
