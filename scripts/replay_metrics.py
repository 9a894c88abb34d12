from simpick.realdata import replay_metrics_job
from simpick.workflow import logged

with logged(snakemake.log[0]):
    replay_metrics_job(list(snakemake.input.logs), list(snakemake.input.traces), snakemake.params.settings,
                       dict(snakemake.output.items()))
