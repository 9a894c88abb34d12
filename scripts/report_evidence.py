from simpick.joblog import logged
from simpick.report import LIST_INPUTS, build_evidence

with logged(snakemake.log[0]):
    inputs = {key: (list(value) if key in LIST_INPUTS else value) for key, value in snakemake.input.items()}
    build_evidence(inputs, snakemake.params.settings, snakemake.output.html, snakemake.output.pdf)
