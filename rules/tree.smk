# The decision tree after the paper's Figure 9 (simpick.score.tree), from the study's own tables:
# the sourced qualitative facts, the analytic mechanics checks, the real-data verdict's outcomes and
# mechanics gate (where the study has real data), the lab's real-time factor and the CPU load. The weights only
# order the engines within a leaf, which the report does from weighted.csv (the table under the printed tree),
# so a weight edit reruns neither decision_tree nor figure_tree.


rule decision_tree:
    input:
        # the real-data evidence, as the answer reads it (PLAN.answer_tables): the verdict's outcomes and
        # mechanics gate where the study has one, else the DRIVE comparison's (its steps replayed against
        # the real robot) when drive_dir is set
        **{k: v for k, v in PLAN.answer_tables().items() if k in ("outcomes", "mechanics")},
        qualitative=SETTINGS.qualitative,
        validation="results/validation/summary.csv",
        rtf=PLAN.metrics_file("lab", "rtf"),
        cpu=expand("results/cpu/{engine}.json", engine=PLAN.engines),
    output:
        tree=report("results/verdict/tree.json", caption="captions/tree.rst", category="Verdict"),
    log:
        "results/logs/decision_tree.log",
    conda:
        "../envs/simpick.yaml"
    params:
        engines=sorted(PLAN.engines),  # a reordered engines: block is not an edit
        code=PLAN.script_code("decision_tree"),
    script:
        "../scripts/decision_tree.py"


rule figure_tree:
    """The decision tree for the PDF: each leaf a letter and its engines in the tree's order. It reads no
    weight, so a weight edit does not redraw it (Matplotlib off the weight path); the report's table under
    the figure orders each leaf by the weighted total."""
    input:
        tree="results/verdict/tree.json",
    output:
        png=report(
            f"{PLAN.figures}/tree.png", caption="captions/tree_figure.rst", category="Figures", subcategory="Verdict"
        ),
    log:
        "results/logs/figures/tree.log",
    benchmark:
        "results/benchmarks/figure_tree.tsv"
    conda:
        "../envs/simpick.yaml"
    threads: 1
    resources:
        mem_mb=300,
        runtime=5,
    params:
        code=PLAN.script_code("tree_figure"),
    script:
        "../scripts/tree_figure.py"
