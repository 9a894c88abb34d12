from simpick.watchdog import runtime_timeout
from simpick.workflow import cpu_job, logged

with logged(snakemake.log[0]):
    cpu_job(snakemake.output[0], snakemake.input.terrain, snakemake.input.urdf, snakemake.params.case,
            runtime_timeout(snakemake.resources.get("runtime")))
