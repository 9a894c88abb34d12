from simpick.sweep import sweep_job
from simpick.watchdog import runtime_timeout
from simpick.workflow import logged

with logged(snakemake.log[0]):
    sweep_job(snakemake.input.segments, snakemake.input.urdf, snakemake.params.case, snakemake.output[0],
              timeout=runtime_timeout(snakemake.resources.get("runtime")))
