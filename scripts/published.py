from pathlib import Path

from simpick.joblog import logged
from simpick.score.jobs import published_job

with logged(snakemake.log[0]):
    published_job(snakemake.input[0], str(Path(snakemake.output.table11).parent))
