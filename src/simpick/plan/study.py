"""The study's plan (:class:`Plan`): everything the rules ask of a study, gathered from its parts.

Each idea of the plan lies in a module of its own, a mixin :class:`Plan` joins; ``Plan.__init__`` sets
them up in the order they rest on one another: the robot, the models (:mod:`simpick.plan.models`),
the real data (:mod:`simpick.plan.realdata`), the sweep (:mod:`simpick.plan.sweep`), the sources of
cases and their units (:mod:`simpick.plan.sources`), priorities and time limits
(:mod:`simpick.plan.scheduling`), the opt-in engines (:mod:`simpick.plan.optin`), what the scores and
the answer rest on (:mod:`simpick.plan.answer`), then the calibration and the report. The code
versions the rules carry come from :mod:`simpick.plan.code`. What stays here is the validation
against analytic mechanics and the default target, which gather no idea of their own.
"""

from __future__ import annotations

from collections.abc import Callable

from simpick.config import Study, plain
from simpick.inputs.robot import load_from_config
from simpick.plan.answer import AnswerPlanning
from simpick.plan.calibration import CalibrationPlanning
from simpick.plan.code import CodePlanning
from simpick.plan.errors import PlanError
from simpick.plan.jobs import JobPlanning
from simpick.plan.models import ModelPlanning
from simpick.plan.optin import OptInPlanning
from simpick.plan.realdata import RealDataPlanning
from simpick.plan.report import ReportPlanning
from simpick.plan.scheduling import CostPlanning
from simpick.plan.sources import SourcePlanning
from simpick.plan.sweep import SweepPlanning

__all__ = ["Plan", "PlanError"]


class Plan(
    ModelPlanning,
    RealDataPlanning,
    SweepPlanning,
    SourcePlanning,
    CostPlanning,
    OptInPlanning,
    AnswerPlanning,
    CodePlanning,
    ReportPlanning,
    CalibrationPlanning,
    JobPlanning,
):
    """Everything the rules ask of a study, from its validated config (:class:`simpick.config.Study`),
    worked out once at planning time. ``config``: the raw dict Snakemake holds (its ``engines`` and
    ``baselines`` order); ``self.config`` is the validated settings as plain data.

    ``basedir`` is the workflow's folder (scripts/ lie there); ``derived_table`` gives the path of
    the dataset folder's derived segment table once its checkpoint has run (Snakemake's
    ``checkpoints.real_segments.get().output.csv``).
    """

    def __init__(self, config: dict, settings: Study, basedir: str, derived_table: Callable[[], str] | None = None):
        # the validated settings as plain data (defaults filled in), not the raw dict: what the
        # rules pass on and the jobs receive
        self.config = config = plain(settings, config)
        self.settings = settings
        self.basedir = basedir
        self._derived_table = derived_table

        # The study's robot, read again here (the config check has read it and stopped on any
        # problem). The committed segments and a dataset folder were recorded on real_data.robot
        # (BorealTC: a Husky A200): they are compared with the study only when its robot is that one
        # (else the config check has refused every part that rests on them).
        # (its plain form: load_from_config reads the robot section as the config gives it, files and all)
        self.robot = load_from_config(settings.robot.model_dump(mode="json"))
        self.real_data_robot = self.robot.name == (settings.real_data.robot or self.robot.name)
        ModelPlanning.__init__(self)
        self.terrains = list(settings.terrains)
        self.motions = list(settings.motions)
        self.validation_cases = list(settings.validation.cases)
        RealDataPlanning.__init__(self)
        SweepPlanning.__init__(self)
        SourcePlanning.__init__(self)
        CostPlanning.__init__(self)
        OptInPlanning.__init__(self)
        AnswerPlanning.__init__(self)
        CalibrationPlanning.__init__(self)
        ReportPlanning.__init__(self)

    # --- validation against analytic mechanics ---

    def validation_results(self, engines=None):
        """Every case's record of ``engines`` (all; ``"{engine}"``: one job's outputs)."""
        engines = [engines] if isinstance(engines, str) else engines or self.validated
        return [f"results/validation/{e}/{c}.json" for e in engines for c in self.validation_cases]

    def validation_runtime(self):
        """Minutes for an engine's validation job: a case's share as a lab case's (1 + health.timeout
        // 60); the watchdog stops a case at 90 % of its share (simpick.studies.validation.validate_job)."""
        return self.simulate_runtime(len(self.validation_cases))

    def all_targets(self):
        """What the default target asks for (rule all)."""
        targets = ["results/validation/summary.csv"]
        targets += [self.metrics_file(s, t) for s in self.sources for t in ("imu_errors", "summary")]
        if self.replay_set:
            targets += [
                f"{self.replay}/segments.csv",
                f"{self.replay}/dataset.yaml",
                f"{self.replay}/turning/summary.csv",
            ]
        if self.sweep:
            targets.append(f"{self.sweep_dir}/summary.csv")
        targets += self.calibration_all
        if self.simulators:
            targets += [
                "results/simulators/table.csv",
                "results/simulators/settings",
                "results/simulators/weighted.csv",
                "results/simulators/tree.json",
            ]
        if self.model_profiles:
            targets.append(self.MODELS_DIR)
        targets += [
            "results/scores/weighted.csv",
            "results/published/table11.csv",
            "results/report/report.html",
            "results/report/report.pdf",
        ]
        return targets
