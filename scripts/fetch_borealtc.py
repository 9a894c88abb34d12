from simpick.joblog import logged
from simpick.real.jobs import fetch_borealtc

with logged(snakemake.log[0]):
    fetch_borealtc(snakemake.output[0])
