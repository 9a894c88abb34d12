from simpick.sweep import sweep_summary_job
from simpick.workflow import logged

with logged(snakemake.log[0]):
    sweep_summary_job(list(snakemake.input), snakemake.output[0], snakemake.params.statistics)
