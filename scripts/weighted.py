from simpick.joblog import logged
from simpick.score.jobs import weighted_job

with logged(snakemake.log[0]):
    weighted_job(snakemake.input.scores, snakemake.params.weights, dict(snakemake.output.items()))
