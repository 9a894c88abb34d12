from simpick.realdata import replay_job
from simpick.workflow import logged

with logged(snakemake.log[0]):
    replay_job(snakemake.input.log, snakemake.input.urdf, snakemake.output[0], snakemake.params.case)
