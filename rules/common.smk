# The study's configuration as the rules see it: the validated settings, the plan built from them
# (simpick.plan: models, sources of cases, each job's inputs, parameters and code version), and the
# wildcards. The DAG logic is library code (src/simpick/plan/), tested like the rest.
import os
import re
import sys

from simpick.codeversion import use_cache
from simpick.config import validate_or_exit
from simpick.plan import Plan, PlanError
from simpick.sources.base import canonical

# Every rule's code version parses the modules its job can reach, most of the planning's time: what
# the parse gives is kept between runs in the working directory's .snakemake/, keyed by the sources'
# contents (simpick.codeversion.use_cache), so a run whose sources are unchanged parses none.
use_cache(os.path.join(".snakemake", "simpick", "code-versions.json"))

# the typed, validated settings (defaults filled in); a bad config stops here, before any job
SETTINGS = validate_or_exit(config, files=workflow.configfiles)

try:
    PLAN = Plan(
        config,
        SETTINGS,
        # the project's folder (scripts/, resources/): the one above this file's rules/, which is also the
        # main Snakefile's folder unless the study runs as a module of another workflow (rules/robots.smk)
        basedir=os.path.dirname(workflow.current_basedir.get_path_or_uri(secret_free=True)),
        # a dataset folder's derived segment table: its cases are known once its checkpoint has run
        derived_table=lambda: checkpoints.real_segments.get().output.csv,
    )
except PlanError as _exc:
    raise WorkflowError(str(_exc))

# Engines this machine cannot run (not installed): the study runs without them, says so here at
# planning time, and its report lists them.
for _engine, _why in PLAN.unavailable.items():
    print(f"simpick: engine {_engine!r} is left out of this study: {_why}", file=sys.stderr)


wildcard_constraints:
    engine="|".join(PLAN.real_models),
    terrain="|".join(PLAN.terrains),
    motion="|".join(PLAN.motions),


# DRIVE's checkpoint inputs (rules/drive.smk, used only when drive_dir is set): the step and calibration
# tables exist once the tables job has kept its sessions.
def drive_replayed(wildcards, suffix="csv"):
    """Every (model, kept session) step table: known once the tables job has kept its sessions."""
    import pandas as pd

    cases = pd.read_csv(checkpoints.drive_tables.get().output.cases)
    return [f"{DRIVE}/replay/{m}/{s}.{suffix}" for m in DRIVE_MODELS for s in sorted(cases.session.unique())]


def drive_cal_files(wildcards, name="evals.csv"):
    import pandas as pd

    cases = pd.read_csv(checkpoints.drive_tables.get().output.cases)
    return [f"{DRIVE_CAL}/{m}/{t}/{name}" for m in DRIVE_CAL_MODELS for t in sorted(cases.terrain_class.unique())]
