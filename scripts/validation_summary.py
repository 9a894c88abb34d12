from simpick.joblog import logged
from simpick.studies.validation.judge import summarise_job

with logged(snakemake.log[0]):
    summarise_job(list(snakemake.input), dict(snakemake.output.items()), snakemake.params.tolerances)
