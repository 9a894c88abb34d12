from simpick.joblog import logged
from simpick.report import LIST_INPUTS, report_job

with logged(snakemake.log[0]):
    report_job(
        dict(snakemake.input.items()),
        snakemake.params.weighing,
        # the plan's params (simpick.report.params.ReportParams) and the folders the rule takes from its inputs
        dict(snakemake.params.settings)
        | {key: getattr(snakemake.params, key) for key in ("drive", "drive_calibration", "simulators")},
        dict(snakemake.output.items()),
        lists=LIST_INPUTS,
    )
