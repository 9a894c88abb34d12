rule terrain:
    output:
        "results/terrains/{terrain}.json",
    log:
        "results/logs/terrain/{terrain}.log",
    conda:
        "../envs/simpick.yaml"
    params:
        spec=lambda wc: canonical(PLAN.config["terrains"][wc.terrain]),
        seed=lambda wc: canonical(PLAN.config["seed"]),
        code=PLAN.script_code("terrain"),
    script:
        "../scripts/terrain.py"
