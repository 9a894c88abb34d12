from simpick.compare.jobs import summarise_job
from simpick.joblog import logged

with logged(snakemake.log[0]):
    summarise_job(
        snakemake.input.per_test, snakemake.input.runs, snakemake.params.settings, dict(snakemake.output.items())
    )
