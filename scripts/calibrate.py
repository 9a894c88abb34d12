from simpick.joblog import logged
from simpick.simulate.watchdog import runtime_timeout
from simpick.studies.calibration.search import calibrate_job

with logged(snakemake.log[0]):
    # the job's code version names its Optuna study: trials of older code are not resumed
    calibrate_job(
        {k: (list(v) if k == "logs" else v) for k, v in snakemake.input.items()},
        snakemake.params.case,
        snakemake.params.settings | {"code": snakemake.params.code},
        dict(snakemake.output),
        timeout=runtime_timeout(snakemake.resources.get("runtime")),
    )
