from simpick.joblog import logged
from simpick.simulate.jobs import cpu_job
from simpick.simulate.watchdog import runtime_timeout

with logged(snakemake.log[0]):
    cpu_job(
        snakemake.output[0],
        snakemake.input.terrain,
        snakemake.input.urdf,
        snakemake.params.case,
        runtime_timeout(snakemake.resources.get("runtime")),
    )
