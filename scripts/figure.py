# one script for every figure rule: simpick.report.draw.RULES maps the rule to what it draws
from simpick.joblog import logged
from simpick.report.draw import figure_job

with logged(snakemake.log[0]):
    figure_job(
        snakemake.rule,
        {k: (list(v) if k in ("traces", "real_logs", "replay_traces") else v) for k, v in snakemake.input.items()},
        snakemake.params.settings,  # the rule's model (simpick.report.draw.RULES), built by the plan
        dict(snakemake.wildcards.items()),
        dict(snakemake.output.items()),
    )
