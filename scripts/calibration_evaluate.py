from simpick.joblog import logged
from simpick.simulate.watchdog import runtime_timeout
from simpick.studies.calibration.search import evaluate_job

with logged(snakemake.log[0]):
    evaluate_job(
        {k: (list(v) if k == "logs" else v) for k, v in snakemake.input.items()},
        snakemake.params.case,
        snakemake.params.settings,
        snakemake.output[0],
        timeout=runtime_timeout(snakemake.resources.get("runtime")),
    )
