from simpick.joblog import logged
from simpick.score.jobs import scores_job

with logged(snakemake.log[0]):
    scores_job(
        snakemake.params.engines,
        snakemake.input.imu_errors,
        snakemake.input.rtf,
        list(snakemake.input.cpu),
        snakemake.input.qualitative,
        snakemake.params.weights,
        dict(snakemake.output.items()),
    )
