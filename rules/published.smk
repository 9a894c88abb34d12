rule published_table11:
    input:
        SETTINGS.reference.published,
    output:
        table11="results/published/table11.csv",
        comparison="results/published/table11_comparison.csv",
        worked_example="results/published/worked_example.json",
    log:
        "results/logs/published.log",
    conda:
        "../envs/simpick.yaml"
    params:
        code=PLAN.script_code("published"),
    script:
        "../scripts/published.py"
