"""The study config, validated before any job runs.

Typed models give every error the key, the bad value and what is allowed; the Snakefile
calls :func:`validate_or_exit`, so a bad config stops the run with those lines and no
traceback.

The models are split by the config's sections, one idea a module: ``base`` (the strict model and
number types), ``robot`` (physics, robot, IMU, health), ``lab`` (terrains, motions, CPU load,
reference), ``real`` (real data, DRIVE, own logs), ``studies`` (validation, sweep, calibration),
``verdict`` (accuracy, simulators, statistics, the verdict), ``study`` (the Study model and its
checks across sections) and ``load`` (problems, duplicate keys, :func:`plain`,
:func:`validate_or_exit`, :func:`read_study`). What the Snakefile, the plan and the schema use is importable from
here, as before the split.
"""

from simpick.config.load import duplicate_keys, merged, plain, problems, read_study, validate_or_exit
from simpick.config.studies import timestep_label
from simpick.config.study import Study
from simpick.config.verdict import Statistics

__all__ = [
    "Statistics",
    "Study",
    "duplicate_keys",
    "merged",
    "plain",
    "problems",
    "read_study",
    "timestep_label",
    "validate_or_exit",
]
