from simpick.compare.jobs import compare_job
from simpick.joblog import logged

with logged(snakemake.log[0]):
    compare_job(
        snakemake.params.kind,
        list(snakemake.input.traces),
        dict(snakemake.input.items()),
        snakemake.params.settings,
        dict(snakemake.output.items()),
    )
