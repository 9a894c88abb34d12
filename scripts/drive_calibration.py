from simpick.joblog import logged
from simpick.studies.calibration.steps import summary_job

with logged(snakemake.log[0]):
    summary_job(dict(snakemake.input), snakemake.params.settings, dict(snakemake.output))
