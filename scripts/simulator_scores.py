from simpick.joblog import logged
from simpick.score.simulators import simulator_scores_job

with logged(snakemake.log[0]):
    simulator_scores_job(snakemake.input.tree_dir, dict(snakemake.params.items()), dict(snakemake.output.items()))
