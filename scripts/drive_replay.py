from simpick.joblog import logged
from simpick.simulate.steps import replay_job
from simpick.simulate.watchdog import runtime_timeout

with logged(snakemake.log[0]):
    replay_job(
        dict(snakemake.input),
        snakemake.params.case,
        dict(snakemake.output),
        runtime_timeout(snakemake.resources.runtime),
    )
