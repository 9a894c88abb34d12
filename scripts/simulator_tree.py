from simpick.joblog import logged
from simpick.score.simulators import simulator_tree_job

# the params less the rule's code version (a rerun trigger, not read by the job): the job's model
with logged(snakemake.log[0]):
    simulator_tree_job(
        snakemake.input.tree_dir,
        {k: v for k, v in snakemake.params.items() if k != "code"},
        snakemake.input.table,
        snakemake.input.settings,
        snakemake.output.tree,
    )
