from pathlib import Path

from simpick.joblog import logged
from simpick.score.jobs import scores_job

with logged(snakemake.log[0]):
    subjects = Path(snakemake.input.tree_dir)
    scores_job(
        list(snakemake.params.simulators),
        str(subjects / "imu_errors.csv"),
        str(subjects / "rtf.csv"),
        sorted(str(p) for p in (subjects / "cpu").glob("*.json")),
        str(subjects / "qualitative.yaml"),
        dict(snakemake.params.weights),
        dict(snakemake.output.items()),
    )
