from simpick.report import html_to_pdf
from simpick.joblog import logged

with logged(snakemake.log[0]):
    html_to_pdf(snakemake.input[0], snakemake.output[0])
