from simpick.joblog import logged
from simpick.simulate.jobs import simulate_job

with logged(snakemake.log[0]):
    simulate_job(list(snakemake.output), snakemake.input.urdf, dict(snakemake.input.items()), snakemake.params.case)
