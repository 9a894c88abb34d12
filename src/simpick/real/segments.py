"""Constant-command segments of real runs: the real-data cases that need no download.

A segment is a stretch of a real run where both wheel-speed commands stay within a
tolerance of constant for at least ``min_duration`` seconds. After ``settle`` seconds
(the robot reaching the new speed) the real IMU over the rest of the stretch gives the
figures a simulation of the same constant command is compared with: per-axis mean and
1 %-trimmed range (paper Eq. 5-6) and the yaw-rate gain. The table is small enough to
commit, so the default study has real-data accuracy on a machine with no network.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.errors import InputError
from simpick.imustats import AXES, trace_stats, yaw_rate_gain
from simpick.real.logs import RealLog, borealtc

COLUMNS = [
    "segment",
    "dataset",
    "terrain_class",
    "run",
    "kind",
    "t_start",
    "t_end",
    "settle",
    "duration",
    "v_left",
    "v_right",
    "v",
    "w",
    "yaw_rate_gain",
] + [f"{q}_{a}_{s}" for q in ("angular", "linear") for a in AXES for s in ("mean", "range")]


def find_segments(
    log: RealLog,
    *,
    tolerance: float,
    min_duration: float,
    max_duration: float,
    settle: float,
    min_turn: float,
    track: float,
) -> list[dict]:
    """Constant-command stretches of one run, as rows of :data:`COLUMNS`.

    The compared window starts ``settle`` s into a stretch and lasts at most ``max_duration``
    s, which bounds what the default study has to simulate.
    """
    cmd = log.wheel_commands(track)
    t, left, right = cmd["time"].to_numpy(), cmd["v_left"].to_numpy(), cmd["v_right"].to_numpy()
    rows, start = [], 0
    for end in range(1, len(t) + 1):
        window_l, window_r = left[start:end], right[start:end]
        constant = (np.ptp(window_l) <= tolerance) and (np.ptp(window_r) <= tolerance)
        if constant and end < len(t):
            continue
        stop = end - 1 if not constant else end  # the last index that kept it constant, exclusive
        t0, t1 = t[start], t[min(stop, len(t) - 1)]
        if t1 - t0 >= min_duration + settle:
            rows.append(
                _segment(
                    log,
                    t0 + settle,
                    min(t1, t0 + settle + max_duration),
                    left[start:stop].mean(),
                    right[start:stop].mean(),
                    settle,
                    min_turn,
                    track,
                )
            )
        start = max(stop, start + 1)
    return [r for r in rows if r is not None]


def _segment(
    log: RealLog, t0: float, t1: float, v_left: float, v_right: float, settle: float, min_turn: float, track: float
) -> dict | None:
    imu = log.imu[(log.imu["time"] >= t0) & (log.imu["time"] < t1)]
    covered = float(imu["time"].iloc[-1] - imu["time"].iloc[0]) if len(imu) > 1 else 0.0
    if covered < 0.99 or max(abs(v_left), abs(v_right)) < 0.02:  # under a second of IMU, or standing still
        return None
    v, w = (v_left + v_right) / 2, (v_right - v_left) / track
    kind = "turning" if abs(w) >= min_turn else "straight"
    stats = trace_stats(imu)
    gain = (
        yaw_rate_gain(
            imu["wz"].to_numpy(), np.full(len(imu), v_left), np.full(len(imu), v_right), track, min_kinematic=min_turn
        )
        if kind == "turning"
        else float("nan")
    )
    row = {
        "dataset": log.meta.get("dataset", "borealtc"),
        "terrain_class": log.meta["terrain_class"].lower(),
        "run": str(log.meta["run_id"]),
        "kind": kind,
        "t_start": round(t0, 3),
        "t_end": round(t1, 3),
        "settle": settle,
        "duration": round(t1 - t0, 3),
        "v_left": v_left,
        "v_right": v_right,
        "v": v,
        "w": w,
        "yaw_rate_gain": gain,
    }
    for q, axes in stats.items():
        for a, s in axes.items():
            row[f"{q}_{a}_mean"], row[f"{q}_{a}_range"] = s["mean"], s["range"]
    return row


def select(rows: list[dict], per_kind: int | Mapping[str, int]) -> pd.DataFrame:
    """The ``per_kind`` longest straight and turning segments of each terrain class: one count for both kinds, or
    a count per kind (``{"straight": N, "turning": M}``)."""
    frame = pd.DataFrame(rows)
    if frame.empty:
        return pd.DataFrame(columns=COLUMNS)
    counts = per_kind if isinstance(per_kind, Mapping) else {"straight": per_kind, "turning": per_kind}
    frame = frame.sort_values(
        ["terrain_class", "kind", "duration", "run", "t_start"], ascending=[True, True, False, True, True]
    )
    rank = frame.groupby(["terrain_class", "kind"], sort=True).cumcount()
    frame = (
        frame[rank < frame.kind.map(counts).fillna(0)]
        .sort_values(["terrain_class", "kind", "run", "t_start"])
        .reset_index(drop=True)
    )
    frame["segment"] = [
        f"{c}-{k}-{r}-{t:07.2f}s".replace(".", "p")
        for c, k, r, t in zip(frame.terrain_class, frame.kind, frame.run, frame.t_start)
    ]
    return frame[COLUMNS]


BOREALTC_SOURCE = "BorealTC (LaRocque et al., IROS 2024), CC0 1.0; github.com/norlab-ulaval/BorealTC data/borealtc"


def derive(
    folder: str | Path,
    *,
    tolerance: float,
    min_duration: float,
    max_duration: float,
    settle: float,
    min_turn: float,
    per_kind: int | Mapping[str, int],
    track: float,
    source: str = BOREALTC_SOURCE,
    **read_options,
) -> tuple[pd.DataFrame, dict]:
    """Segments table and its provenance from a dataset folder (BorealTC layout)."""
    logs = (
        borealtc.read_run(imu, pro, cls, track=track, **read_options) for cls, _, imu, pro in borealtc.discover(folder)
    )
    return derive_from_logs(
        logs,
        tolerance=tolerance,
        min_duration=min_duration,
        max_duration=max_duration,
        settle=settle,
        min_turn=min_turn,
        per_kind=per_kind,
        track=track,
        source=source,
    )


def derive_from_logs(
    logs,
    *,
    tolerance: float,
    min_duration: float,
    max_duration: float,
    settle: float,
    min_turn: float,
    per_kind: int | Mapping[str, int],
    track: float,
    source: str,
) -> tuple[pd.DataFrame, dict]:
    """Segments table and its provenance from a dataset's runs (canonical logs, in the folder's
    class and run order); ``source`` says where the data come from."""
    rows, sources, rates = [], [], {"imu": [], "commands": []}
    for log in logs:
        rows += find_segments(
            log,
            tolerance=tolerance,
            min_duration=min_duration,
            max_duration=max_duration,
            settle=settle,
            min_turn=min_turn,
            track=track,
        )
        for stream in ("imu", "commands"):
            info = log.meta["source_files"][stream]
            path = Path(info["path"])
            sources.append({"file": f"{path.parent.name}/{path.name}", "sha256": info["sha256"]})
            rates[stream].append(float(log.meta["rates"][stream]["median_hz"]))
    table = select(rows, per_kind)
    provenance = {
        "dataset": source,
        "derived_by": "simpick.real.segments.derive (rule real_segments)",
        "parameters": {
            "tolerance_m_s": tolerance,
            "min_duration_s": min_duration,
            "max_duration_s": max_duration,
            "settle_s": settle,
            "min_turn_rad_s": min_turn,
            "per_kind": dict(per_kind) if isinstance(per_kind, Mapping) else per_kind,
            "track_m": track,
        },
        "segments_found": len(rows),
        "segments_kept": len(table),
        "source_files": sources,
        "rates_hz": {s: [round(min(r), 4), round(max(r), 4)] if r else None for s, r in rates.items()},
    }
    return table, provenance


def load_segments(path: str | Path) -> pd.DataFrame:
    """A segment table (the committed one, or a dataset folder's), its columns checked."""
    try:
        frame = pd.read_csv(path, dtype={"run": str})
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise InputError(str(path), f"cannot read the segments table: {exc}") from None
    missing = [c for c in COLUMNS if c not in frame.columns]
    if missing:
        raise InputError(
            str(path),
            f"columns {missing} are missing",
            "restore it (git checkout -- PATH) or regenerate it: "
            "snakemake --cores 2 maintain_segments --config borealtc_dir=PATH",
        )
    return frame
