from simpick.workflow import logged, simulate_job

with logged(snakemake.log[0]):
    simulate_job(snakemake.output[0], snakemake.input.terrain, snakemake.input.urdf, snakemake.params.case)
