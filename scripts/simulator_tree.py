from pathlib import Path

from simpick.joblog import logged
from simpick.score.tree import decision_tree_job

with logged(snakemake.log[0]):
    subjects = Path(snakemake.input.tree_dir)
    inputs = {
        "qualitative": str(subjects / "qualitative.yaml"),
        "validation": str(subjects / "validation.csv"),
        "rtf": str(subjects / "rtf.csv"),
        "cpu": sorted(str(p) for p in (subjects / "cpu").glob("*.json")),
    }
    if snakemake.params.verdict:
        inputs |= {"outcomes": str(subjects / "outcomes.csv"), "mechanics": str(subjects / "mechanics.csv")}
    decision_tree_job(list(snakemake.params.simulators), inputs, snakemake.output.tree)
