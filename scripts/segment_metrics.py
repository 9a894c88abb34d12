from simpick.realdata import segment_metrics_job
from simpick.workflow import logged

with logged(snakemake.log[0]):
    segment_metrics_job(snakemake.input.segments, list(snakemake.input.traces), snakemake.params.track,
                        dict(snakemake.output.items()), snakemake.params.statistics)
