from simpick.joblog import logged
from simpick.simulate.watchdog import runtime_timeout
from simpick.studies.calibration.steps import calibrate_job

with logged(snakemake.log[0]):
    calibrate_job(
        dict(snakemake.input),
        snakemake.params.settings,
        dict(snakemake.output),
        runtime_timeout(snakemake.resources.runtime),
    )
