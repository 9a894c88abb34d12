from simpick.realdata import fetch_borealtc
from simpick.workflow import logged

with logged(snakemake.log[0]):
    fetch_borealtc(snakemake.output[0])
