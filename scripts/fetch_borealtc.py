from simpick.real.jobs import fetch_borealtc
from simpick.joblog import logged

with logged(snakemake.log[0]):
    fetch_borealtc(snakemake.output[0])
