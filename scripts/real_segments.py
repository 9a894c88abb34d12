from simpick.realdata import segments_job
from simpick.workflow import logged

with logged(snakemake.log[0]):
    segments_job(list(snakemake.input.logs), snakemake.output.csv, snakemake.output.provenance,
                 snakemake.params.rules)
