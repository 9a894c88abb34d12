from simpick.joblog import logged
from simpick.report.tree_figure import tree_figure_job

with logged(snakemake.log[0]):
    tree_figure_job(snakemake.input.tree, snakemake.output.png)
