from simpick.joblog import logged
from simpick.studies.turnmap import engine_job

with logged(snakemake.log[0]):
    engine_job(snakemake.input.grid, snakemake.input.urdf, snakemake.params.case, snakemake.output[0])
