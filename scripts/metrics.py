from simpick.workflow import logged, metrics_job

with logged(snakemake.log[0]):
    metrics_job(list(snakemake.input.traces), snakemake.input.published, dict(snakemake.output.items()))
