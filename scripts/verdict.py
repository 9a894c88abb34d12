from simpick.score.verdict import verdict_job
from simpick.joblog import logged

with logged(snakemake.log[0]):
    verdict_job(snakemake.input.per_test, snakemake.input.weighted, snakemake.input.provenance,
                snakemake.params.settings, dict(snakemake.output.items()), snakemake.input.accuracy_tests)
