from simpick.workflow import logged, terrain_job

with logged(snakemake.log[0]):
    terrain_job(snakemake.output[0], snakemake.wildcards.terrain, int(snakemake.params.seed), snakemake.params.spec)
