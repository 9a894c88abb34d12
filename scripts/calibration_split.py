from simpick.joblog import logged
from simpick.studies.calibration.split import split_job

with logged(snakemake.log[0]):
    split_job(
        snakemake.params.units,
        snakemake.params.test_fraction,
        snakemake.params.seed,
        snakemake.output[0],
        list(snakemake.input.get("logs", [])),
        snakemake.params.strata,
    )
