from simpick.joblog import logged
from simpick.score.simulator_settings import settings_files_job

# the params less the rule's code version (a rerun trigger, not read by the job): the job's model
with logged(snakemake.log[0]):
    settings_files_job(
        dict(snakemake.input.items()), {k: v for k, v in snakemake.params.items() if k != "code"}, snakemake.output[0]
    )
