"""The real-data jobs: a dataset folder's manifest and its runs imported to the canonical form, the
user's own logs imported, a dataset's constant-command segments derived, the maintainers' copy of
BorealTC's table over the committed one, and the BorealTC download.
"""

from __future__ import annotations

import hashlib
import io
import os
import shutil
import sys
import tempfile
import urllib.error
import urllib.request
import zipfile
from pathlib import Path

import yaml
from pydantic import Field

from simpick.errors import InputError
from simpick.params import JobParams, Positive
from simpick.real.logs import borealtc, read_canonical, write_canonical
from simpick.real.logs.csvlog import read_csv_log
from simpick.real.logs.rosbag import read_bag
from simpick.real.segments import derive_from_logs, load_segments
from simpick.real.settings import DeclaredRates, SegmentRules
from simpick.tables import write_csv


class SegmentsParams(JobParams):
    """What rule real_segments' job reads: how segments are cut, the controller's track, the data's source."""

    segment_rules: SegmentRules
    track: Positive = Field(description="m, the controller's track (the config's robot.track)")
    source: str = Field(description="where the data come from, for the table's provenance")


class ImportParams(JobParams):
    """What rule import_real's job reads: the controller's track, the dataset's name, label and declared rates."""

    track: Positive = Field(description="m, the controller's track (the config's robot.track)")
    dataset: str = Field(description="the dataset's name (its entry under real_data.datasets)")
    label: str = Field(description="the dataset's name in the report")
    declared: DeclaredRates = Field(description="the rates the config declares for the folder's files")


def segments_job(logs: list[str], output_csv: str, output_provenance: str, params: dict) -> None:
    """The constant-command segments of a dataset's imported runs (a result, never the committed table)."""
    p = SegmentsParams.model_validate(params)
    rules = p.segment_rules
    table, provenance = derive_from_logs(
        (read_canonical(path) for path in logs),
        tolerance=rules.tolerance,
        min_duration=rules.min_duration,
        max_duration=rules.max_duration,
        settle=rules.settle,
        min_turn=rules.min_turn,
        per_kind=rules.per_kind if isinstance(rules.per_kind, int) else rules.per_kind.model_dump(),
        track=p.track,
        source=p.source,
    )
    write_csv(table, output_csv)
    Path(output_provenance).write_text(yaml.safe_dump(provenance, sort_keys=False))


def maintain_segments_job(derived_csv: str, derived_provenance: str, committed: dict, receipt: str) -> None:
    """The maintainer's deliberate step: the derived table (and provenance) over the committed
    ones. Each file is written beside its target and renamed over it, so a failure leaves the
    committed file as it was; the receipt (a result) says what changed."""

    def digest(path) -> str | None:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest() if Path(path).is_file() else None

    load_segments(derived_csv)  # refuse a table the study could not read
    done = {}
    for key, source in (("csv", derived_csv), ("provenance", derived_provenance)):
        target = Path(committed[key])
        before = digest(target)
        partial = target.with_name(f".{target.name}.partial")
        partial.write_bytes(Path(source).read_bytes())
        os.replace(partial, target)
        done[key] = {
            "file": str(target),
            "from": str(source),
            "sha256_before": before,
            "sha256_after": digest(target),
            "changed": before != digest(target),
        }
    Path(receipt).parent.mkdir(parents=True, exist_ok=True)
    Path(receipt).write_text(yaml.safe_dump(done, sort_keys=False))
    changed = [d["file"] for d in done.values() if d["changed"]]
    print(
        f"simpick: maintain_segments: {', '.join(changed) or 'nothing'} changed; commit it if intended", file=sys.stderr
    )


def dataset_manifest_job(dataset: dict, output: str) -> None:
    """results/real/<dataset>/dataset.yaml: the folder whose results that folder holds."""
    Path(output).parent.mkdir(parents=True, exist_ok=True)
    Path(output).write_text(yaml.safe_dump(dict(dataset), sort_keys=False))


def import_job(imu: str, pro: str, terrain_class: str, output: str, params: dict) -> None:
    """One run of a dataset folder -> canonical log (rates measured, checked against any declared)."""
    p = ImportParams.model_validate(params)
    log = borealtc.read_run(
        imu,
        pro,
        terrain_class,
        track=p.track,
        imu_rate_hz=p.declared.imu_hz,
        command_rate_hz=p.declared.commands_hz,
        declared_by=f"real_data.datasets.{p.dataset} in the config",
        dataset=p.label,
    )
    write_canonical(log, output)


def import_own_job(entry: dict, output: str, track: float) -> None:
    """One of the user's logs (config ``own_logs``: a mapped CSV or a ROS bag) -> canonical form."""
    meta = {"dataset": "own", "run_id": entry["name"], "terrain_class": entry["terrain_class"], "name": entry["name"]}
    if entry.get("csv"):
        mapping = {**entry["mapping"], "meta": {**entry["mapping"].get("meta", {}), **meta}}
        log = read_csv_log(entry["csv"], mapping, commands_path=entry.get("commands_csv"), track=track)
    else:
        bag = entry["rosbag"]
        options = {
            k: v
            for k, v in entry.items()
            if k
            in (
                "command_type",
                "wheel_radius",
                "left_joints",
                "right_joints",
                "frame_z",
                "imu_rate_hz",
                "command_rate_hz",
            )
        }
        log = read_bag(bag, entry["imu_topic"], entry["command_topic"], track=track, meta=meta, **options)
    log.meta.update(meta)
    write_canonical(log, output)


BOREALTC_ARCHIVES = (
    "https://github.com/norlab-ulaval/BorealTC/archive/refs/heads/main.zip",
    "https://github.com/norlab-ulaval/BorealTC/archive/refs/heads/master.zip",
)


def fetch_borealtc(dest: str | Path, timeout: float = 30.0) -> Path:
    """Download the public BorealTC repository and keep its data/borealtc folder at ``dest``.

    Offline (or if the repository moved) this raises an InputError that says how to use a
    local copy instead, rather than a network traceback.
    """
    dest = Path(dest)
    errors = []
    for url in BOREALTC_ARCHIVES:
        try:
            with urllib.request.urlopen(url, timeout=timeout) as response:  # noqa: S310 - fixed https URLs
                payload = response.read()
            break
        except (urllib.error.URLError, OSError, TimeoutError) as exc:
            errors.append(f"{url}: {exc}")
    else:
        raise InputError(
            "borealtc_dir",
            "could not download BorealTC (" + "; ".join(errors) + ")",
            "download the folder data/borealtc of the GitHub repository norlab-ulaval/BorealTC "
            "on a connected machine, copy it here, and run "
            "snakemake --cores 2 --config borealtc_dir=PATH/TO/borealtc",
        )
    with tempfile.TemporaryDirectory() as tmp, zipfile.ZipFile(io.BytesIO(payload)) as archive:
        archive.extractall(tmp)
        found = [p for p in Path(tmp).glob("*/data/borealtc") if p.is_dir()]
        if not found:
            raise InputError(
                "borealtc_dir",
                "the downloaded archive has no data/borealtc folder",
                "download data/borealtc by hand and pass --config borealtc_dir=PATH",
            )
        if dest.exists():
            shutil.rmtree(dest)
        shutil.copytree(found[0], dest)
    return dest
