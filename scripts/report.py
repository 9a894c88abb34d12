from simpick.joblog import logged
from simpick.report import LIST_INPUTS, build_report

APPENDIX = ("appendix_html", "appendix_pdf")  # rule report_appendix's files, not report inputs

with logged(snakemake.log[0]):
    inputs = {
        key: (list(value) if key in LIST_INPUTS else value)
        for key, value in snakemake.input.items()
        if key not in APPENDIX
    }
    build_report(
        inputs,
        dict(snakemake.params.items()),
        snakemake.output.html,
        snakemake.output.pdf,
        appendix_html=snakemake.input.appendix_html,
        appendix_pdf=snakemake.input.appendix_pdf,
    )
