from simpick.joblog import logged
from simpick.studies.simulator_calibration import split_job

with logged(snakemake.log[0]):
    split_job(
        dict(snakemake.input.items()),
        snakemake.params.test_fraction,
        snakemake.params.seed,
        snakemake.output[0],
    )
