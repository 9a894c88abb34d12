from simpick.joblog import logged
from simpick.studies.simulator_calibration import calibrate

with logged(snakemake.log[0]):
    calibrate(dict(snakemake.input.items()), snakemake.params.case, snakemake.output[0])
