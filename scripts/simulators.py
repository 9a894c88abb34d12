from simpick.joblog import logged
from simpick.score.simulators import simulators_job

with logged(snakemake.log[0]):
    simulators_job(dict(snakemake.input.items()), dict(snakemake.params.items()), dict(snakemake.output.items()))
