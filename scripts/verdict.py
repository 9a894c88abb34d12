from simpick.joblog import logged
from simpick.score.verdict import verdict_job

with logged(snakemake.log[0]):
    verdict_job(dict(snakemake.input.items()), snakemake.params.settings, dict(snakemake.output.items()))
