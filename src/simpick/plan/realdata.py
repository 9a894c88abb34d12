"""The real robot data a study can compare with: the committed segment table and its dataset, the
dataset folder of the full replay (checked when the plan is built), and the user's own logs.

These stand apart from the sources they become: a folder is opened and checked, its runs listed and
the committed table read once here, whatever sources, calibration or report then rest on them; and a
rule that rewrites the committed table (maintain_segments) asks only about these.
"""

from __future__ import annotations

import sys

from simpick.plan.errors import PlanError
from simpick.real.datasets import open_dataset_or_exit
from simpick.sources import base as source_base
from simpick.sources import own as own_source
from simpick.sources import replay as replay_source
from simpick.sources import segments as segments_source


class RealDataPlanning:
    """The study's real data (a mixin of :class:`simpick.plan.Plan`)."""

    def __init__(self):
        real_data = self.settings.real_data
        # --- real robot data ---
        self.dataset = real_data.dataset  # the committed segment table's dataset
        self.real = f"results/real/{self.dataset}"
        # terrain class -> segment ids of the committed table (the config check has made sure it
        # exists; no run ever writes it)
        try:
            self.segments = segments_source.by_class(real_data.segments, real_data.classes)
        except ValueError as exc:
            raise PlanError(str(exc)) from None

        # The full replay's dataset folder (--config borealtc_dir=PATH [real_dataset=NAME]), checked
        # now: a folder that is not a dataset, an empty class folder, an unpaired file or a class with
        # no ground model stops the run here with one `simpick:` line each, before any job.
        self.replay_set = None
        if self.settings.borealtc_dir:
            self.replay_set = open_dataset_or_exit(
                self.settings.borealtc_dir, classes=real_data.classes, name=self.settings.real_dataset
            )
        self.replay = f"results/real/{self.replay_set.name}" if self.replay_set else None
        self.runs = replay_source.cases(self.replay_set) if self.replay_set else []

        self.own = "results/real/own"
        # name -> the entry as plain data: rule import_own_log's params (simpick.real.jobs.import_own_job)
        self.own_logs = {entry.name: entry.model_dump(mode="json") for entry in self.settings.own_logs}

        # The replay sources and their case tables: a source is the dataset folder (its name) or the
        # user's own logs ("own"); a case is one (terrain class, run) whose canonical log lies at
        # results/real/<source>/logs/<class>/<run>.parquet. Each kind of source has its import rule
        # (rules/real.smk); from the log on, every source is one entry of ``sources``.
        # No dataset is called "own" (simpick.real.datasets.RESERVED_NAMES).
        self.replay_cases = {self.replay_set.name: self.runs} if self.replay_set else {}
        if self.own_logs:
            self.replay_cases["own"] = own_source.cases(self.settings)

    def own_log_files(self, name: str) -> list[str]:
        """The files of the user's own log ``name`` (its CSVs or its bag): rule import_own_log's inputs, so that a
        log replaced under the same name is imported, replayed and compared again."""
        entry = self.own_logs[name]
        return [entry[k] for k in ("csv", "commands_csv", "rosbag") if entry.get(k)]

    def real_logs(self, source):
        return [source_base.log_path(source, c, run) for c, run in self.replay_cases[source]]

    def replay_dataset(self):
        """The replay dataset as the rules see it: name, label, source and declared rates."""
        declared = self.settings.real_data.datasets.get(self.replay_set.name)  # by dataset name: data
        rates = {"imu_hz": declared.imu_hz, "commands_hz": declared.commands_hz} if declared else {}
        return {
            "name": self.replay_set.name,
            "folder": str(self.replay_set.folder),
            "label": (declared and declared.label) or self.replay_set.name,
            "source": (declared and declared.source) or f"dataset folder {self.replay_set.folder}",
            "declared": {k: v for k, v in rates.items() if v},
        }

    def maintained_table(self, wildcards=None):
        """maintain_segments' inputs: the BorealTC folder's derived table. Asked for on any other
        dataset (or none), it stops the run while the DAG is built, before any job."""
        if self.replay_set is None:
            problem = (
                "maintain_segments derives the committed segment table from the BorealTC folder "
                "(fix: pass --config borealtc_dir=PATH/TO/borealtc)"
            )
        elif self.replay_set.name != self.dataset:
            problem = (
                f"maintain_segments rewrites {self.settings.real_data.segments}, the table of dataset "
                f"{self.dataset!r}, but {self.replay_set.folder} is dataset {self.replay_set.name!r} (fix: pass "
                f"--config real_dataset={self.dataset} if that folder holds {self.dataset}; its own table is "
                f"{self.replay}/segments.csv)"
            )
        else:
            return {"csv": f"{self.replay}/segments.csv", "provenance": f"{self.replay}/segments.provenance.yaml"}
        print(f"simpick: {problem}", file=sys.stderr)
        sys.exit(1)
