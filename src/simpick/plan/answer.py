"""What the scores, the verdict and the first page's answer rest on: the accuracy scores' reference set,
the verdict's real data, and the answer's source, tables, basis and settings.

It stands apart because one choice (the verdict's runs where the study has real data of its robot, else
DRIVE's steps, else none) decides the inputs and words of several rules (answer, its figure, the decision
tree, the scores) and must be made in one place, after the sources are known.
"""

from __future__ import annotations

from simpick.plan.jobs import job_params
from simpick.sources import module as source_module


class AnswerPlanning:
    """The scores', verdict's and answer's sources (a mixin of :class:`simpick.plan.Plan`, set up after
    its sources)."""

    def __init__(self):
        # simpick's verdict rests on real runs: none where the study's robot has no real data
        self.verdict = self.verdict_source() in self.sources
        # The real data the first page's answer rests on (rule answer, its figure, the decision tree): the
        # verdict's runs where the study has them, else the DRIVE comparison's steps (--config drive_dir=PATH),
        # which replay the study's own robot; None: no real data of this robot, no answer table.
        self.drive = source_module("drive").root(self.settings) if self.settings.drive_dir else None
        self.answer_source = "verdict" if self.verdict else ("drive" if self.drive else None)

    def accuracy_source(self):
        """What the accuracy scores rest on (accuracy.reference in the config): the set of tests
        (lab, segments, replay or own), its dataset, its Eq. 7 totals and the per-test table beside
        them. Only the rules use this; the scores job records it in results/scores/provenance.yaml,
        which is what the report reads."""
        reference = self.settings.accuracy.reference
        if reference == "paper":
            kind, source, dataset = "lab", "lab", None
        elif reference == "own":
            kind, source, dataset = "own", "own", "own"
        elif self.replay_set:
            kind, source, dataset = "replay", self.replay_set.name, self.replay_set.name
        else:
            kind, source, dataset = "segments", "segments", self.dataset
        return {
            "reference": reference,
            "set": kind,
            "dataset": dataset,
            "source": source,
            "errors": self.metrics_file(source, "imu_errors"),
            "per_test": self.metrics_file(source, "per_test"),
        }

    def accuracy_errors(self):
        """The Eq. 7 totals the accuracy scores rest on."""
        return self.accuracy_source()["errors"]

    def verdict_source(self):
        """The real data simpick's verdict rests on: the accuracy scores' real set, else the committed
        segments."""
        src = self.accuracy_source()
        return src["source"] if src["set"] != "lab" else "segments"

    def verdict_source_title(self):
        """How the report names the verdict's real data."""
        if self.sources[self.verdict_source()]["kind"] == "segments":
            return f"committed constant-command segments of {self._dataset_label(self.dataset)}"
        return f"full replay of {self.verdict_source()}"

    def verdict_settings(self):
        """Rule verdict's params (:class:`simpick.score.verdict.job.VerdictParams`): what its tests depend
        on, no weight (a weight edit reruns the answer, not them)."""
        from simpick.score.verdict.job import VerdictParams

        data = {
            "engines": sorted(self.engines),
            "baselines": sorted(self.baselines),
            "statistics": self.settings.statistics.model_dump(mode="json"),
            "seed": self.settings.seed,
            "accuracy_set": self.accuracy_source()["set"],
            "verdict": self.settings.verdict.model_dump(mode="json"),
        }
        return job_params("verdict", VerdictParams, data)

    def drive_compare_params(self, engines):
        """Rule drive_compare's params (:class:`simpick.score.steps.CompareParams`) for the study's ``engines``
        the DRIVE replay ran: the verdict's margins and mechanics, the statistics, the unit of pairing, the
        similar-command tolerance and the seed (no weight)."""
        from simpick.real.steps import SIMILAR
        from simpick.score.steps import CompareParams

        data = {
            "engines": list(engines),
            "verdict": self.settings.verdict.model_dump(mode="json"),
            "statistics": self.settings.statistics.model_dump(mode="json"),
            "unit": self.settings.drive_replay.unit,
            "tolerance": SIMILAR,
            "seed": self.settings.seed,
        }
        return job_params("drive_compare", CompareParams, data)

    def _dataset_label(self, name):
        """A dataset's label in the report (real_data.datasets is keyed by dataset name: data, not fields)."""
        declared = self.settings.real_data.datasets.get(name)
        return (declared.label if declared else None) or name

    def _robot_label(self):
        return self.settings.robot.label or self.robot.name

    def answer_basis(self):
        """The real data the answer rests on, as its sentence names them: the dataset, its unit (a DRIVE
        step, or the step's session where the verdict pairs by session; a real run) and the study's other
        real data, which the report compares in their own section."""
        robot = self._robot_label()
        if self.answer_source not in (None, "verdict"):  # a source whose own comparison the answer rests on
            name = self.settings.drive_dataset
            return source_module(self.answer_source).answer_basis(self.settings, self._dataset_label(name), robot)
        source = self.verdict_source()
        name = self.dataset if self.sources[source]["kind"] == "segments" else source
        label = "own-log" if source == "own" else self._dataset_label(name)
        return {
            "dataset": label,
            "unit": "run",
            "title": self.verdict_source_title(),
            "others": [self._dataset_label(self.settings.drive_dataset)] if self.drive else [],
        }

    def answer_settings(self):
        """Rule answer's params (:class:`simpick.score.answer.AnswerParams`): what the answer and the paper's
        ranking with its interval depend on, the weights, and the words the sentences use."""
        from simpick.score.answer import AnswerParams

        drive = self.answer_source == "drive"
        basis = self.answer_basis()
        data = {
            "engines": sorted(self.engines),
            "statistics": self.settings.statistics.model_dump(mode="json"),
            "weights": dict(self.settings.weights),
            "seed": self.settings.seed,
            "source": self.settings.drive_dataset if drive else self.verdict_source(),
            "source_title": basis["title"] if drive else self.verdict_source_title(),
            "robot": self._robot_label(),
            "basis": basis,
        }
        return job_params("answer", AnswerParams, data)

    def answer_tables(self):
        """The real-data comparison's tables the answer, its figure and the decision tree read, by name:
        the verdict's (results/verdict/) where the study has one, else the comparison of the source the
        answer rests on (DRIVE's, written in the same form beside its outcomes: its source module's
        answer_tables); {} without real data of this robot.
        ``discrimination`` (what the paper's accuracy scores separate) is the verdict's alone."""
        if self.answer_source == "verdict":
            tables = {t: f"results/verdict/{t}.csv" for t in ("outcomes", "mechanics", "metrics", "table")}
            tables["discrimination"] = "results/verdict/discrimination.csv"
            tables["per_test"] = self.metrics_file(self.verdict_source(), "per_test")
            return tables
        if self.answer_source is not None:
            return source_module(self.answer_source).answer_tables(self.settings)
        return {}

    def answer_inputs(self, wildcards=None):
        """The comparison's tables the answer reads (answer_tables, less the per-run values only its
        figure draws), and the calibration's turning table where the calibration is part of the study and the
        answer rests on its runs (the DRIVE calibration's table has another form: not read here)."""
        inputs = {k: v for k, v in self.answer_tables().items() if k != "metrics"}
        if self.answer_source == "verdict" and self.settings.calibration and self.settings.calibration.enabled:
            inputs["calibration_turning"] = f"{self.cal_dir}/turning.csv"
        return inputs
