from simpick.joblog import logged
from simpick.simulate.watchdog import runtime_timeout
from simpick.studies.validation.job import validate_job

with logged(snakemake.log[0]):
    validate_job(
        list(snakemake.output),
        snakemake.input.urdf,
        snakemake.params.case,
        timeout=runtime_timeout(snakemake.resources.get("runtime")),
        calibrated=dict(snakemake.input.items()).get("calibrated"),
    )
