from simpick.joblog import logged
from simpick.score.simulators import settings_files_job

with logged(snakemake.log[0]):
    settings_files_job(dict(snakemake.input.items()), dict(snakemake.params.items()), snakemake.output[0])
