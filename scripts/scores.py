from simpick.joblog import logged
from simpick.score.jobs import scores_job

with logged(snakemake.log[0]):
    scores_job(
        snakemake.params.engines,
        snakemake.input.imu_errors,
        snakemake.input.rtf,
        list(snakemake.input.cpu),
        snakemake.input.qualitative,
        None,
        dict(snakemake.output.items()),
        {
            "accuracy": snakemake.params.accuracy,
            "accuracy_tests": snakemake.input.accuracy_tests,
            "runs": snakemake.input.runs,
            "cpu_test": snakemake.params.cpu_test,
        },
    )
