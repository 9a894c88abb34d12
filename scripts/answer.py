from simpick.joblog import logged
from simpick.score.answer import answer_job

with logged(snakemake.log[0]):
    answer_job(dict(snakemake.input.items()), snakemake.params.settings, dict(snakemake.output.items()))
