from simpick.joblog import logged
from simpick.studies.drive_calibration import calibrate_job
from simpick.simulate.watchdog import runtime_timeout

with logged(snakemake.log[0]):
    calibrate_job(
        dict(snakemake.input),
        snakemake.params.settings,
        dict(snakemake.output),
        runtime_timeout(snakemake.resources.runtime),
    )
