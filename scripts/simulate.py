from simpick.joblog import logged
from simpick.simulate.jobs import simulate_job

with logged(snakemake.log[0]):
    # with its log: after a hung case, the cases after it go on in a fresh process (simpick.simulate.jobs.resume)
    simulate_job(
        list(snakemake.output),
        snakemake.input.urdf,
        dict(snakemake.input.items()),
        snakemake.params.case,
        log=snakemake.log[0],
    )
