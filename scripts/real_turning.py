from simpick.joblog import logged
from simpick.real.turning import turning_job

with logged(snakemake.log[0]):
    turning_job(
        list(snakemake.input.logs),
        snakemake.input.urdf,
        snakemake.params.settings,
        {"windows": snakemake.output.windows, "summary": snakemake.output.summary},
    )
