from simpick.compare.drive import compare_job
from simpick.joblog import logged

with logged(snakemake.log[0]):
    compare_job(dict(snakemake.input), snakemake.params.settings, dict(snakemake.output))
