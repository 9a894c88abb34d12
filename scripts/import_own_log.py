from simpick.joblog import logged
from simpick.real.jobs import import_own_job

with logged(snakemake.log[0]):
    import_own_job(snakemake.params.entry, snakemake.output[0], snakemake.params.track)
