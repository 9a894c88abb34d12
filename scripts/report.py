from simpick.joblog import logged
from simpick.report import LIST_INPUTS, build_report

EVIDENCE = ("evidence_html", "evidence_pdf")  # rule report_evidence's files, not report inputs

with logged(snakemake.log[0]):
    inputs = {
        key: (list(value) if key in LIST_INPUTS else value)
        for key, value in snakemake.input.items()
        if key not in EVIDENCE
    }
    build_report(
        inputs,
        dict(snakemake.params.items()),
        snakemake.output.html,
        snakemake.output.pdf,
        evidence_html=snakemake.input.evidence_html,
        evidence_pdf=snakemake.input.evidence_pdf,
    )
