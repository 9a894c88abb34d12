from simpick.realdata import import_job
from simpick.workflow import logged

with logged(snakemake.log[0]):
    import_job(snakemake.params.folder, snakemake.wildcards.upper.lower(), snakemake.wildcards.run,
               snakemake.output[0], snakemake.params.track)
