from simpick.joblog import logged
from simpick.real.jobs import import_job

with logged(snakemake.log[0]):
    import_job(
        snakemake.input.imu,
        snakemake.input.pro,
        snakemake.params.folder_class,
        snakemake.output[0],
        snakemake.params.settings,
    )
