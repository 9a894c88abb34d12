from simpick.validation import validate_job
from simpick.watchdog import runtime_timeout
from simpick.workflow import logged

with logged(snakemake.log[0]):
    validate_job(list(snakemake.output), snakemake.input.urdf, snakemake.params.case,
                 timeout=runtime_timeout(snakemake.resources.get("runtime")))
