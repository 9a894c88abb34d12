from simpick.validation import validate_job
from simpick.workflow import logged

with logged(snakemake.log[0]):
    validate_job(snakemake.output[0], snakemake.input.urdf, snakemake.params.case)
