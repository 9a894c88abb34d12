"""The report's part of the plan: its inputs, the figures it embeds, and the slices of the config it
shows (rules/report.smk). A mixin of :class:`simpick.plan.Plan`."""

from __future__ import annotations

import os

from simpick.plan.jobs import fields_of, job_params

FIGURES = "results/report/figures"
# simpick's verdict tables (rule verdict), each an input of the report
VERDICT_TABLES = ("metrics", "table", "separation", "ranking", "discrimination", "headings", "outcomes", "answer")
# of those, the answer's, which the report job writes itself (simpick.report.weighing; the rest are the
# real-data comparison's: Plan.answer_tables)
ANSWER_TABLES = ("separation", "ranking", "answer")
# what the report job's weighing writes (simpick.report.weighing): output name -> (path, caption, category of
# `snakemake --report`); the answer's where the study has one, the simulators' where it runs any
WEIGHED = {
    "weighted": ("results/scores/weighted.csv", "captions/weighted.rst", "Scores"),
    "contributions": ("results/scores/contributions.csv", "captions/scores_contributions.rst", "Scores"),
    "drivers": ("results/scores/drivers.csv", "captions/scores_contributions.rst", "Scores"),
}
ANSWERED = {
    "ranking": ("results/verdict/ranking.csv", "captions/verdict_ranking.rst", "Verdict"),
    "separation": ("results/verdict/separation.csv", "captions/verdict_separation.rst", "Verdict"),
    "answer": ("results/verdict/answer.csv", "captions/verdict_answer.rst", "Verdict"),
    "answer_yaml": ("results/verdict/answer.yaml", "captions/verdict_answer.rst", "Verdict"),
    "headline": ("results/verdict/headline.yaml", "captions/verdict_headline.rst", "Verdict"),
}
SIMULATORS_WEIGHED = {
    "simulators_scores": ("results/simulators/scores.csv", "captions/simulators.rst", "Simulators"),
    "simulators_weighted": ("results/simulators/weighted.csv", "captions/simulators.rst", "Simulators"),
}


class ReportPlanning:
    def __init__(self):
        self.figures = FIGURES
        # engine -> colour follows this list (simpick.report.draw.colors): sorted, so reordering the
        # config's engines neither recolours nor redraws a figure
        self.figure_engines = sorted(self.engines) + sorted(self.baselines)
        self.lab_figure_tests = self._lab_figure_tests()

    def _lab_figure_tests(self):
        """The lab tests with an IMU-statistics figure: every simulated test, and every test the
        paper gives a real reference for (drawn with the reference alone when no engine ran it)."""
        from simpick.inputs.published import load_published
        from simpick.inputs.reference import lab_reference

        tests = [(t, m) for t in self.terrains for m in self.motions]
        published = lab_reference(load_published(self.settings.reference.published))
        return tests + [tm for tm in published if tm not in tests]

    def report_config(self):
        """The slice of the config the report shows and reads (:class:`simpick.report.params.ReportConfig`):
        terrains (strip geometry), motions (commanded paths, test order) and the robot."""
        study = self.settings
        return {
            "terrains": {name: terrain.model_dump(mode="json") for name, terrain in study.terrains.items()},
            "motions": {name: motion.model_dump(mode="json") for name, motion in study.motions.items()},
            "robot": {
                "track": study.robot.track,
                "name": self.robot.name,
                "label": study.robot.label or self.robot.name,
                "real_data_robot": study.real_data.robot if not self.real_data_robot else None,
            },
        }

    def report_real_data(self):
        """The real data's settings the report shows (:class:`simpick.report.params.ReportRealData`)."""
        real_data = self.settings.real_data
        return {
            "dataset": self.dataset,
            "datasets": self.report_datasets(),
            "classes": {name: c.model_dump(mode="json") for name, c in real_data.classes.items()},
            "window": real_data.window,
            "segment_rules": real_data.segment_rules.model_dump(mode="json"),
        }

    def figure_params(self, rule):
        """Figure rule ``rule``'s params (simpick.report.draw.RULES gives its model): the engines, whose
        order gives their colours, and what the figure reads beside them; no weight."""
        from simpick.report.draw import RULES

        data = {"engines": self.figure_engines}
        if rule == "figure_paths":
            data["config"] = self.report_config()
        elif rule == "figure_real_gain":
            data["statistics"] = self.settings.statistics.model_dump(mode="json")
            data["real_data"] = {"classes": self.report_real_data()["classes"]}
        elif rule == "figure_replay":
            data["track"] = self.settings.robot.track
        elif rule == "figure_real_turning":
            data = {}  # the real robot's turning windows alone: no engine
        return job_params(rule, RULES[rule][3], data)

    def evidence_params(self):
        """Rule report_evidence's params (:class:`simpick.report.params.EvidenceParams`): no weight, so that a
        weight edit does not lay the evidence out again."""
        from simpick.report.params import EvidenceParams

        data = {
            "config": self.report_config(),
            "statistics": self.settings.statistics.model_dump(mode="json"),
            "engines": self.figure_engines,  # the evidence's engine order (no ranking) and colours
            "real_data": self.report_real_data(),
        }
        return job_params("report_evidence", EvidenceParams, data)

    def report_params(self):
        """Rule report's params (:class:`simpick.report.params.ReportParams`) less what the rule takes from its
        inputs (the DRIVE tables' and the simulators' folders): the evidence's, the weights, and the
        configured engines this machine cannot run and the opt-in ones, named as not run."""
        from simpick.report.params import ReportParams

        data = {
            "config": self.report_config(),
            "statistics": self.settings.statistics.model_dump(mode="json"),
            "engines": self.figure_engines,
            "real_data": self.report_real_data(),
            "weights": dict(self.settings.weights),
            "unavailable": self.unavailable,
            "opt_in": self.opt_in,
        }
        params = job_params("report", ReportParams, data)
        # the rule gives these from its inputs (Snakemake resolves them when the job runs)
        return {k: v for k, v in params.items() if k not in ("drive", "drive_calibration", "simulators")}

    def report_real_inputs(self, wildcards=None):
        """The real-robot inputs of the report: the accuracy scores' errors file, the committed
        segments' comparison always, the full replay of the dataset folder when one is given."""
        segments = self.settings.real_data.segments
        provenance = segments.replace(".csv", ".provenance.yaml")
        inputs = {"accuracy_errors": self.accuracy_errors()}
        if self.real_data_robot:  # the committed segments are real_data.robot's
            inputs["segments"] = segments
            inputs.update(
                {
                    f"segments_{table}": self.metrics_file("segments", table)
                    for table in ("per_test", "summary", "pairwise", "imu_errors")
                }
            )
        if self.accuracy_source()["set"] != "lab":  # its per-test table: how much of each error a rigid model leaves
            inputs["accuracy_per_test"] = self.accuracy_source()["per_test"]
        if os.path.exists(provenance) and self.real_data_robot:
            inputs["segments_provenance"] = provenance
        if self.replay_set:
            name = self.replay_set.name
            inputs.update(
                {
                    f"replay_{table}": self.metrics_file(name, table)
                    for table in ("per_test", "summary", "pairwise", "imu_errors")
                }
            )
            inputs["replay_per_window"] = self.metrics_file(name, "detail")
            inputs["real_turning"] = f"{self.replay}/turning/summary.csv"
        if self.answer_source:
            # the comparison's tables the answer rests on: the verdict's, or the DRIVE comparison's (the answer's
            # own tables the report job writes itself: weighing_outputs)
            inputs.update({f"verdict_{t}": p for t, p in self.answer_tables().items() if t in VERDICT_TABLES})
            if self.answer_source == "verdict":
                inputs["verdict_headings"] = "results/verdict/headings.csv"
        if self.sweep:
            inputs["sweep"] = f"{self.sweep_dir}/summary.csv"
        if self.settings.calibration and self.settings.calibration.enabled:  # rules/calibration.smk
            inputs["calibration"] = f"{self.cal_dir}/summary.csv"
            inputs["calibration_turning"] = f"{self.cal_dir}/turning.csv"
            inputs["calibration_target"] = f"{self.cal_dir}/target.csv"
        return inputs

    def evidence_real_inputs(self, wildcards=None):
        """The real-robot inputs of the evidence's sections 2-5 and the appendices (rule report_evidence):
        the report's, less the answer's tables (they read the weights; the evidence shows none) and of the
        verdict's only what the accuracy scores can tell apart (section 3), which no weight reaches."""
        return {
            k: v
            for k, v in self.report_real_inputs().items()
            if not k.startswith("verdict_") or k == "verdict_discrimination"
        }

    def body_figures(self):
        """The figures the body embeds (rule report): the first page's, the answer's and the printed
        tree (which reads no weight; the body orders its leaves by the weighted total in a table). The
        others are the evidence's."""
        fig = self.figures
        return [f for f in self.report_figures() if f in (f"{fig}/answer.png", f"{fig}/tree.png")]

    def evidence_figures(self):
        """The figures the evidence's sections 2-5 and the appendices embed: the report's, less the body's."""
        return [f for f in self.report_figures() if f not in self.body_figures()]

    def report_datasets(self):
        """Which dataset each real-data set comes from, and its declared rates (the report states them)."""
        from simpick.real.settings import DeclaredRates

        # real_data.datasets: keyed by the dataset's name (data, not fields)
        committed = self.settings.real_data.datasets.get(self.dataset)
        return {
            "segments": {
                "name": self.dataset,
                "label": (committed.label if committed else None) or self.dataset,
                "source": (committed.source if committed else None) or "",
                "declared": fields_of(committed, DeclaredRates) if committed else {},
                "simulated_imu_hz": self.settings.imu.rate_hz,
            },
            "replay": self.replay_dataset() if self.replay_set else None,
        }

    def report_figures(self):
        """Every figure file the report embeds (and the notes beside the replay figures)."""
        fig = self.figures
        out = [f"{fig}/paths.png", f"{fig}/validation_gain.png", f"{fig}/real_gain.png"]
        if self.answer_source:
            out.append(f"{fig}/answer.png")
        out.append(f"{fig}/tree.png")  # rules/tree.smk: the decision tree for print
        out += [f"{fig}/imu_stats/{t}/{m}.png" for t, m in self.lab_figure_tests]
        out += [f"{fig}/traces/{t}/{m}.png" for t in self.terrains for m in self.motions]
        if self.sweep:
            out.append(f"{fig}/sweep.png")
        if self.replay_set:
            out += [f"{fig}/replay/{c}.{ext}" for c in self.replay_set.classes for ext in ("png", "json")]
            out.append(f"{fig}/real_turning.png")
        return out

    def lab_test_traces(self, wildcards):
        return [
            f"results/traces/lab/{engine}/{wildcards.terrain}/{wildcards.motion}.parquet" for engine in self.engines
        ]

    def real_gain_inputs(self, wildcards=None):
        """The real-data tables whose yaw-rate gains the figure shows: the committed segments', and
        the full replay's when a dataset folder is given."""
        names = ("per_test", "summary", "pairwise")
        inputs = {f"segments_{n}": self.metrics_file("segments", n) for n in names} if self.real_data_robot else {}
        if self.replay_set:
            inputs.update({f"replay_{n}": self.metrics_file(self.replay_set.name, n) for n in names})
        return inputs

    def replay_class_inputs(self, wildcards):
        """One terrain class of the full replay: its canonical logs, every model's replay of them,
        and the per-test table that picks the run drawn."""
        cls = wildcards.terrain_class
        runs = [run for c, run in self.runs if c == cls]
        return {
            "real_logs": [log for log in self.real_logs(self.replay_set.name) if f"/logs/{cls}/" in log],
            "replay_traces": [
                f"results/traces/{self.replay_set.name}/{e}/{cls}/{run}.parquet"
                for e in self.real_models
                for run in runs
            ],
            "replay_per_test": self.metrics_file(self.replay_set.name, "per_test"),
        }

    # --- the weighing, the report job's first step (simpick.report.weighing) ---

    def weighing_inputs(self, wildcards=None):
        """What the weighing reads, each named with simpick.report.weighing.PREFIX: the scores, and where the
        study has an answer what rule answer read before (the comparison's tables, the scores' record, the
        lab's real-time factor, the CPU runs); the simulators' subjects where it runs any."""
        from simpick.report.weighing import PREFIX

        inputs = {"scores": "results/scores/scores.csv"}
        if self.answer_source:
            inputs |= self.answer_inputs() | {
                "accuracy_tests": self.accuracy_source()["per_test"],
                "provenance": "results/scores/provenance.yaml",
                "rtf": self.metrics_file("lab", "rtf"),
                "cpu": [f"results/cpu/{engine}.json" for engine in self.engines],
            }
        if self.simulators:
            inputs["simulator_subjects"] = "results/simulators/subjects"
        return {PREFIX + k: v for k, v in inputs.items()}

    def weighing_outputs(self):
        """The tables the weighing writes: output name -> (path, caption, category)."""
        return WEIGHED | (ANSWERED if self.answer_source else {}) | (SIMULATORS_WEIGHED if self.simulators else {})

    def weighing_params(self):
        """The weighing's params (simpick.report.weighing.WeighingParams): the answer's, which hold the weights,
        or the weights alone; the simulators' scoring."""
        from simpick.report.weighing import WeighingParams

        data = {
            "answer": self.answer_settings() if self.answer_source else None,
            "weights": dict(self.settings.weights),
            "simulators": self.simulator_scores_params() if self.simulators else None,
        }
        return job_params("report", WeighingParams, data)
