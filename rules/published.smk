rule published_table11:
    input:
        "resources/published/farley2022.yaml",
    output:
        table11="results/published/table11.csv",
        comparison="results/published/table11_comparison.csv",
        worked_example="results/published/worked_example.json",
    log:
        "results/logs/published.log",
    script:
        "../scripts/published.py"
