from simpick.joblog import logged
from simpick.score.tree import decision_tree_job

with logged(snakemake.log[0]):
    decision_tree_job(snakemake.params.engines, dict(snakemake.input.items()), snakemake.output.tree)
