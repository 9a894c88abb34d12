from simpick.joblog import logged
from simpick.studies.calibration.summary import summary_job

with logged(snakemake.log[0]):
    summary_job(
        list(snakemake.input.evals),
        list(snakemake.input.bests),
        snakemake.input.split,
        dict(snakemake.output),
        snakemake.params.statistics,
        snakemake.params.turning,
        snakemake.input.urdf,
    )
