"""The speed-accuracy sweep (config ``sweep:``, rules/sweep.smk): the committed segments' jobs again at
each of the sweep's timesteps, labelled as wildcards ("0.5ms").

It stands apart as the one family that varies a setting the study otherwise fixes: its jobs reuse a
source's parameters and code with the timestep replaced.
"""

from __future__ import annotations

from simpick.config import timestep_label


class SweepPlanning:
    """The sweep's points and jobs (a mixin of :class:`simpick.plan.Plan`)."""

    def __init__(self):
        # Speed-accuracy sweep (the typed section, None without one): timesteps as wildcard labels ("0.5ms")
        self.sweep = self.settings.sweep
        self.sweep_dir = f"results/sweeps/{self.sweep.name}" if self.sweep else None
        self.sweep_labels = [timestep_label(t) for t in self.sweep.timesteps] if self.sweep else []

    def sweep_params(self, engine, terrain_class, label):
        """The segments source's job of a class on ``engine`` (case_params) at the sweep point's timestep."""
        from simpick.plan.jobs import job_params
        from simpick.studies.sweep import SweepPointParams

        unit = self.case_params("segments", engine, terrain_class, self.segments[terrain_class])
        dt = dict(zip(self.sweep_labels, self.sweep.timesteps))[label]
        physics = self.settings.physics.model_dump(mode="json") | {"timestep": float(dt)}
        return job_params("sweep_segments", SweepPointParams, unit | {"physics": physics})

    def sweep_code(self, engine):
        """A sweep point's code: its job (which runs the compare stage's code), the model's adapter,
        and how the segments source's cases are driven (no other source's)."""
        return self.script_code(
            "sweep_segments",
            *self.engine_modules(engine),
            self.prepare_module("segments"),
        )

    def sweep_runs(self):
        return [
            f"{self.sweep_dir}/runs/{engine}/{cls}/{label}.csv"
            for engine in self.engines
            for cls in self.segments
            for label in self.sweep_labels
        ]
