from simpick.joblog import logged
from simpick.report.turnmap import figure_job

with logged(snakemake.log[0]):
    figure_job(snakemake.input[0], snakemake.output[0])
