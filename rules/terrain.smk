rule terrain:
    output:
        "results/terrains/{terrain}.json",
    log:
        "results/logs/terrain/{terrain}.log",
    conda:
        "../envs/simpick.yaml"
    params:
        spec=lambda wc: canonical(SETTINGS.terrains[wc.terrain].model_dump(mode="json")),
        seed=lambda wc: canonical(SETTINGS.seed),
        code=PLAN.script_code("terrain"),
    script:
        "../scripts/terrain.py"
