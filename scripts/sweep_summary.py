from simpick.joblog import logged
from simpick.studies.sweep import sweep_summary_job

with logged(snakemake.log[0]):
    sweep_summary_job(list(snakemake.input), snakemake.output[0], snakemake.params.statistics)
