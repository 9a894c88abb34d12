"""Planning: which jobs a study has and what each one depends on, worked out once per run from the
config, before any job (the DAG logic the rules call; ``rules/common.smk`` builds one :class:`Plan`).

- :mod:`simpick.plan.study`: :class:`Plan`, which joins the parts below, and the validation's jobs;
- :mod:`simpick.plan.models`: the engines that can run here, the simulators' profiles, the baselines;
- :mod:`simpick.plan.realdata`: the committed segments, the replay's dataset folder, own logs;
- :mod:`simpick.plan.sources`: the sources of cases (lab, committed segments, a dataset folder, own
  logs, a derived segment table) and the simulate / compare / summarise units over them;
- :mod:`simpick.plan.sweep`: the speed-accuracy sweep's points;
- :mod:`simpick.plan.scheduling`: each job's priority (:mod:`simpick.plan.costs`) and time limit;
- :mod:`simpick.plan.optin`: the engines an opt-in config adds, for the report;
- :mod:`simpick.plan.answer`: what the scores, the verdict and the answer rest on;
- :mod:`simpick.plan.code`: each job's code version;
- :mod:`simpick.plan.report`: the report's inputs, figures and slices of the config;
- :mod:`simpick.plan.calibration`: the calibration's units, settings and outputs.

Nothing here runs in a job: a job's code version (:mod:`simpick.codeversion`) never includes it, so
an edit here reruns a job only where it changes what the job is given.
"""

from simpick.plan.study import Plan, PlanError

__all__ = ["Plan", "PlanError"]
