from simpick.inputs.jobs import terrain_job
from simpick.joblog import logged

with logged(snakemake.log[0]):
    terrain_job(snakemake.output[0], snakemake.wildcards.terrain, int(snakemake.params.seed), snakemake.params.spec)
