from simpick.joblog import logged
from simpick.report.robots import robots_job

with logged(snakemake.log[0]):
    robots_job(dict(snakemake.input.items()), snakemake.params.settings, dict(snakemake.output.items()))
