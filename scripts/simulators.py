from simpick.joblog import logged
from simpick.score.simulators import simulators_job

# the params less the rule's code version (a rerun trigger, not read by the job): the job's model
with logged(snakemake.log[0]):
    simulators_job(
        dict(snakemake.input.items()),
        {k: v for k, v in snakemake.params.items() if k != "code"},
        dict(snakemake.output.items()),
    )
