from simpick.realturning import turning_job
from simpick.workflow import logged

with logged(snakemake.log[0]):
    turning_job(list(snakemake.input.logs), snakemake.input.urdf, snakemake.params.settings,
                {"windows": snakemake.output.windows, "summary": snakemake.output.summary})
