from simpick.joblog import logged
from simpick.real.drive import tables_job

with logged(snakemake.log[0]):
    tables_job(snakemake.params.folder, snakemake.params.declared, snakemake.params.name, dict(snakemake.output))
