"""Planning: which jobs a study has and what each one depends on, worked out once per run from the
config, before any job (the DAG logic the rules call; ``rules/common.smk`` builds one :class:`Plan`).

- :mod:`simpick.plan.study`: the study's models, its sources of cases (lab, committed segments, a
  dataset folder, own logs, a derived segment table), the simulate / compare / summarise units over
  them, the sweep, the accuracy and verdict sources, and each job's parameters and code version;
- :mod:`simpick.plan.report`: the report's inputs, figures and slices of the config;
- :mod:`simpick.plan.calibration`: the calibration's units, settings and outputs.

Nothing here runs in a job: a job's code version (:mod:`simpick.codeversion`) never includes it, so
an edit here reruns a job only where it changes what the job is given.
"""

from simpick.plan.study import Plan, PlanError

__all__ = ["Plan", "PlanError"]
