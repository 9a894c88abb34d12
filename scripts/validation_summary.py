from simpick.validation import summarise_job
from simpick.workflow import logged

with logged(snakemake.log[0]):
    summarise_job(list(snakemake.input), dict(snakemake.output.items()), snakemake.params.tolerances)
