from simpick.joblog import logged
from simpick.studies.turnmap import grid_job

with logged(snakemake.log[0]):
    grid_job(snakemake.input.steps, snakemake.input.urdf, snakemake.params.case, snakemake.output[0])
