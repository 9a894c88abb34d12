from simpick.joblog import logged
from simpick.real.jobs import maintain_segments_job

with logged(snakemake.log[0]):
    maintain_segments_job(
        snakemake.input.csv, snakemake.input.provenance, snakemake.params.committed, snakemake.output[0]
    )
