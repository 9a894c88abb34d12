from simpick.joblog import logged
from simpick.studies.turnmap import table_job

with logged(snakemake.log[0]):
    table_job(snakemake.input.grid, list(snakemake.input.engines), dict(snakemake.output))
