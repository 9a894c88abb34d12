from simpick.real.jobs import maintain_segments_job
from simpick.joblog import logged

with logged(snakemake.log[0]):
    maintain_segments_job(snakemake.input.csv, snakemake.input.provenance, snakemake.params.committed,
                          snakemake.output[0])
