from simpick.realdata import simulate_segments_job
from simpick.workflow import logged

with logged(snakemake.log[0]):
    simulate_segments_job(snakemake.input.segments, snakemake.input.urdf, list(snakemake.output), snakemake.params.case)
