from simpick.joblog import logged
from simpick.studies.sweep import sweep_job

with logged(snakemake.log[0]):
    sweep_job(dict(snakemake.input.items()), snakemake.params.case, snakemake.params.settings, snakemake.output[0])
