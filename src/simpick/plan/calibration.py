"""The calibration's part of the plan (config ``calibration:``, rules/calibration.smk): its units,
the settings its jobs depend on, and its outputs. A mixin of :class:`simpick.plan.Plan`."""

from __future__ import annotations

import csv

from simpick.engines import get_engine
from simpick.sources import base as source_base
from simpick.sources.base import canonical


class CalibrationPlanning:
    def __init__(self):
        # the section as plain data (None without one): simpick.plan.answer and simpick.plan.report read it so
        # (``.get("enabled")``); this module reads the typed one, ``self.settings.calibration``
        self.calibration = self.config.get("calibration")
        self.calibration_all = []
        cal = self.settings.calibration
        if cal is None:
            return

        replay = self.replay_set
        self.cal_source = "replay" if replay else "segments"
        self.cal_dir = (
            f"results/calibration/replay-{replay.name}" if replay else f"results/calibration/segments-{self.dataset}"
        )
        self.cal_models = [
            m
            # a simulator's profile is tuned only within what the simulator exposes (the catalog), never over
            # its adapter's whole space: not calibrated here
            for m in (cal.models or [m for m in self.real_models if m not in self.profiles])
            if m not in self.unavailable and get_engine(m).calibratable
        ]
        self.cal_classes = sorted({c for c, _ in self.runs}) if replay else sorted(self.segments)
        if cal.enabled:
            self.calibration_all = [f"{self.cal_dir}/summary.csv"]

    def calibration_units(self):
        """(terrain class, run, unit) of every real unit the split divides; a segment's with whether it
        turns (the split stratifies by it; a replayed run's is read from its log by the split job)."""
        if self.replay_set:
            return [[c, run, run] for c, run in self.runs]
        with open(self.settings.real_data.segments, newline="") as handle:
            return [
                [r["terrain_class"], r["run"], r["segment"], r["kind"] == "turning"] for r in csv.DictReader(handle)
            ]

    def calibration_split_inputs(self, wildcards=None):
        """The table the units come from; for a replay its logs too (which runs turn)."""
        if self.replay_set:
            return {
                "dataset": f"{self.replay}/dataset.yaml",
                "logs": [source_base.log_path(self.replay_set.name, c, run) for c, run in self.runs],
            }
        return {"segments": self.settings.real_data.segments}

    def calibration_strata(self):
        """How the split job tells a replayed run that turns: the calibration's steady windows within
        its compared seconds (None for segments: their kind says it)."""
        if not self.replay_set:
            return None
        from simpick.plan.jobs import job_params
        from simpick.studies.calibration.settings import EvaluateSettings
        from simpick.studies.calibration.split import SplitStrata

        settings = EvaluateSettings.model_validate(self.calibration_settings(None, search=False))
        data = {
            "track": self.settings.robot.track,
            "steady": settings.steady.model_dump(mode="json"),
            "duration": settings.replay_seconds,
        }
        return job_params("calibration_split", SplitStrata, data)

    def calibration_data(self, wildcards):
        """The real data a class's jobs read: the committed table, or the class's canonical logs."""
        if self.replay_set:
            return {
                "logs": [
                    source_base.log_path(self.replay_set.name, c, run)
                    for c, run in self.runs
                    if c == wildcards.terrain_class
                ]
            }
        return {"segments": self.settings.real_data.segments}

    def calibration_settings(self, engine, search=True):
        """What a class's errors depend on; with ``search`` also the optimiser's budget, seed and
        this model's bounds (so an evaluation does not rerun on a budget edit unless the best
        parameters change). Validated against the calibrate or evaluate job's model (simpick.plan.jobs)."""
        from simpick.plan.jobs import job_params
        from simpick.studies.calibration.settings import EvaluateSettings, SearchSettings

        cal = self.settings.calibration
        rules = self.settings.real_data.segment_rules
        data = {
            "source": self.cal_source,
            "scales": cal.scales.model_dump(mode="json"),
            # the units' first seconds: the committed segments', or a replayed run's with the steady-command
            # turning windows of the real turning analysis (rule real_turning; window and settle:
            # simpick.real.turning.turning_windows' own)
            **(
                {
                    "replay_seconds": cal.replay_seconds,
                    "steady": {"tolerance": rules.tolerance, "min_turn": rules.min_turn},
                }
                if self.replay_set
                else {"segment_seconds": cal.segment_seconds}
            ),
        }
        if not search:
            return job_params("calibration_evaluate", EvaluateSettings, data)
        data |= {
            "n_trials": cal.n_trials,
            "startup_trials": cal.startup_trials,
            "seed": cal.seed,
            "bounds": {engine: cal.bounds.get(engine) or {}},
        }
        return job_params("calibrate", SearchSettings, data)

    def calibration_outputs(self):
        return [f"{self.cal_dir}/{e}/{c}/evaluation.csv" for e in self.cal_models for c in self.cal_classes]

    def calibration_bests(self):
        return [f"{self.cal_dir}/{e}/{c}/best.yaml" for e in self.cal_models for c in self.cal_classes]

    def calibration_turning(self):
        """What the summary's turning and target tables depend on."""
        return canonical(
            {
                "track": self.settings.robot.track,
                "engines": self.engines,
                "target": self.settings.calibration.target.model_dump(),
            }
        )
