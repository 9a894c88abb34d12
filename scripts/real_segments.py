from simpick.joblog import logged
from simpick.real.jobs import segments_job

with logged(snakemake.log[0]):
    segments_job(list(snakemake.input.logs), snakemake.output.csv, snakemake.output.provenance, snakemake.params.rules)
