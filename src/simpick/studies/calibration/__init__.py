"""Calibrate each engine on some real runs, judge it on the others.

A user tunes an engine's contact parameters to their robot and ground before trusting it. This
package asks: after the best calibration each engine allows, how close does it get on runs it
has not seen, and at what cost (after Acosta, Posa et al. 2022, who did this for cube tosses)?

- **Split** (:func:`~.split.split_runs`): per terrain class the real *runs* (never windows or segments of
  one run) are shuffled with a seeded generator and a fraction goes to the test set; the split
  is a result file (``results/calibration/<source>/split.csv``).
- **Parameters**: each engine adapter (and reference model) declares ``calibratable``, a mapping
  of parameter name to :class:`simpick.engines.base.Calibratable` bounds, each with the reason for
  its bounds. ``friction`` is the terrain class's Coulomb coefficient (``real_data.classes.<c>.
  friction``); any other name is one of the adapter's own settings (``engines.<e>.<name>``).
  :func:`~.parameters.apply_parameters` is the only place that knows this, and it knows no engine by name.
- **Objective** (:func:`~.objective.objective_terms`): on every training unit, the low-passed yaw-rate error
  (rad/s) and the low-passed longitudinal-acceleration error (m/s^2), each divided by its scale
  from the config (``calibration.scales``) and summed; the objective is the mean over the
  training units. A unit is a committed segment (the real table keeps only its window means: a
  constant command's low-passed signal is its mean, so the errors are |mean sim - mean real|) or,
  for the full replay, a run (RMS of the difference of the two signals after the same 2 Hz
  low-pass, :func:`simpick.compare.realmetrics.aligned_rmse`, as the replay metrics). A unit the engine
  fails (health check) counts :data:`~.objective.FAILED_UNIT` instead.
  Constant offsets no engine can model (an accelerometer bias, a slope's g sin(angle))
  are removed from the longitudinal-acceleration term: on a replayed run it is the RMS of the
  low-passed difference less its mean over the run; on a committed segment, whose real table
  keeps only window means under a constant command (where the true acceleration is zero, so the
  mean *is* the offset), nothing is left of it and the segment's objective is its yaw-rate term
  alone. The yaw rate, and so the yaw-rate gain (yaw rate / commanded turn), then carries the
  objective's weight on turning units; ``error_accel_x`` is reported as measured (offset
  included) beside it. A unit that turns under a steady command adds its steady yaw-rate gain error
  over ``scales.yaw_rate_gain`` (:func:`~.objective.objective_terms`).
- **Optimiser**: Optuna's TPE sampler with a journal file as storage
  (``results/calibration/<source>/<engine>/<class>/optuna.journal``): an interrupted job resumes
  the finished trials from the file and runs only the missing ones. The sampler is seeded per
  trial from (seed, number of finished trials), so a resumed calibration proposes exactly what
  an uninterrupted one would have. Trial 0 is always the as-configured engine, so the best
  parameters are never worse on the training units than the configured ones.

Everything here drives the engines as the segments and replay sources' jobs do
(:mod:`simpick.simulate.real`), the same paths as the study's real-data comparison.

The modules, one idea each: ``split`` (the runs split into training and test), ``parameters`` (what may
be tuned and how chosen values apply), ``objective`` (one unit's errors, the objective, the units),
``search`` (the Optuna loop and the calibrate and evaluate jobs), ``summary`` (before against after
on the held-out units, the summary job), ``turning`` (the held-out turning table and the target's
verdict) and ``intervals`` (the statistics the two summaries share).
"""
