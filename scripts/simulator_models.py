from simpick.joblog import logged
from simpick.studies.simulator_models import simulator_models_job

# the params less the rule's code version (a rerun trigger, not read by the job): the job's model
with logged(snakemake.log[0]):
    simulator_models_job(
        dict(snakemake.input.items()), {k: v for k, v in snakemake.params.items() if k != "code"}, snakemake.output[0]
    )
