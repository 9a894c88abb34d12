from simpick.joblog import logged
from simpick.report import LIST_INPUTS, build_report

EVIDENCE = ("evidence_html", "evidence_pdf")  # rule report_evidence's files, not report inputs

with logged(snakemake.log[0]):
    inputs = {
        key: (list(value) if key in LIST_INPUTS else value)
        for key, value in snakemake.input.items()
        if key not in EVIDENCE
    }
    # the plan's params (simpick.report.params.ReportParams) and the folders the rule takes from its inputs
    params = dict(snakemake.params.settings) | {
        key: getattr(snakemake.params, key) for key in ("drive", "drive_calibration", "simulators")
    }
    build_report(
        inputs,
        params,
        snakemake.output.html,
        snakemake.output.pdf,
        evidence_html=snakemake.input.evidence_html,
        evidence_pdf=snakemake.input.evidence_pdf,
    )
