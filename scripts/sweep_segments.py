from simpick.sweep import sweep_job
from simpick.workflow import logged

with logged(snakemake.log[0]):
    sweep_job(dict(snakemake.input.items()), snakemake.params.case, snakemake.params.settings, snakemake.output[0])
