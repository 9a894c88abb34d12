from simpick.joblog import logged
from simpick.real.jobs import dataset_manifest_job

with logged(snakemake.log[0]):
    dataset_manifest_job(snakemake.params.dataset, snakemake.output[0])
