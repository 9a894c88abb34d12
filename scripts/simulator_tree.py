from simpick.joblog import logged
from simpick.score.simulators import simulator_tree_job

with logged(snakemake.log[0]):
    simulator_tree_job(snakemake.input.tree_dir, dict(snakemake.params.items()), snakemake.output.tree)
