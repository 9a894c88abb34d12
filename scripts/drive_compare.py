from simpick.joblog import logged
from simpick.score.steps import compare_job

with logged(snakemake.log[0]):
    compare_job(dict(snakemake.input), snakemake.params.settings, dict(snakemake.output))
