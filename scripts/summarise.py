from simpick.workflow import logged, summarise_job

with logged(snakemake.log[0]):
    summarise_job(snakemake.input.per_test, snakemake.input.runs, snakemake.params.settings,
                  dict(snakemake.output.items()))
