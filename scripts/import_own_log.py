from simpick.realdata import import_own_job
from simpick.workflow import logged

with logged(snakemake.log[0]):
    import_own_job(snakemake.params.entry, snakemake.output[0], snakemake.params.track)
