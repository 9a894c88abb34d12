"""The real-data sets the report describes: per set the dataset it comes from and its sample rates
(measured, declared, simulated), read from the segment table's provenance and the replay's
per-test table; a reader needs these to judge what the comparison rests on."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from simpick.report.load import ReportData
from simpick.report.real.common import (
    SET_TITLES,
    _isnan,
)

if TYPE_CHECKING:
    from simpick.real.settings import DeclaredRates
    from simpick.report.params import ShownDatasets


def _hz_range(values: Sequence[float]) -> str | None:
    """ "100 Hz" or "49.9–50.1 Hz" (4 significant digits), None when there are none."""
    vals = sorted(float(v) for v in values if v is not None and not _isnan(v))
    if not vals:
        return None
    lo, hi = (f"{v:.4g}" for v in (vals[0], vals[-1]))
    return f"{lo} Hz" if lo == hi else f"{lo}–{hi} Hz"


def _declared_text(declared: DeclaredRates) -> str | None:
    parts = [
        f"{what} {rate:g} Hz" for rate, what in ((declared.imu_hz, "IMU"), (declared.commands_hz, "wheels")) if rate
    ]
    return ", ".join(parts) or None


def datasets(data: ReportData, declared: ShownDatasets) -> list[dict[str, Any]]:
    """Per real-data set: the dataset it comes from and its sample rates (measured, declared, and
    the simulated IMU's, which the comparison uses). Measured rates of the full replay come from
    its canonical logs' meta; those of the committed segments from the table's provenance. ``declared``:
    each set's dataset as the plan states it."""
    from simpick.report.params import ShownDataset

    rows = []
    if data.segments is not None:
        d = declared.segments or ShownDataset()
        prov = data.segments_provenance or {}
        rates = prov.get("rates_hz") or {}
        label = d.label or (
            str(data.segments["dataset"].iloc[0]) if "dataset" in data.segments.columns and len(data.segments) else None
        )
        rows.append(
            {
                "set": "segments",
                "title": SET_TITLES["segments"],
                "label": label or "(not named)",
                "where": "the committed segment table",
                "n": f"{len(data.segments)} segments",
                "imu": _hz_range(rates.get("imu") or []),
                "commands": _hz_range(rates.get("commands") or []),
                "declared": _declared_text(d.declared),
                "simulated": _hz_range([d.simulated_imu_hz] if d.simulated_imu_hz else []),
            }
        )
    replay = (data.real.get("replay") or {}).get("per_test")
    if replay is not None and "real_imu_hz" in replay:
        # the replay's per-test table carries each run's measured rates and each trace's IMU rate
        # (simpick.compare.real.replay_compare): the report reads no log or trace itself
        d = declared.replay or ShownDataset()
        per_run = replay.drop_duplicates(["terrain_class", "run"])
        rows.append(
            {
                "set": "replay",
                "title": SET_TITLES["replay"],
                "label": d.label or d.name or "(not named)",
                "where": d.folder or "",
                "n": f"{len(per_run)} runs",
                "imu": _hz_range(per_run.real_imu_hz.dropna().tolist()),
                "commands": _hz_range(per_run.real_commands_hz.dropna().tolist()),
                "declared": _declared_text(d.declared),
                "simulated": _hz_range(replay.sim_imu_hz.dropna().tolist()),
            }
        )
    for row in rows:
        shown = getattr(declared, row["set"])  # the set's dataset: segments or replay, fields of ShownDatasets
        stated = shown.declared.commands_hz if shown else None
        row["wheel_rate"] = row["commands"] or (f"{float(stated):g} Hz (declared)" if stated else None)
    return rows
