"""The DRIVE dataset (Norlab; Baril et al., "DRIVE: Data-driven Robot Input Vector Exploration",
arXiv:2309.10718): a robot given random constant wheel-speed commands, each held one step
(6 s on the Warthog), with measured wheel speeds, an IMU and a lidar-ICP pose.

SAFETY. DRIVE stores each session as a pandas pickle
(``<session>/model_training_datasets/slip_dataset_all.pkl``), and unpickling runs whatever
code the file holds. This reader therefore has no default location: it reads only the
folder its caller names (the user's ``calib_data/`` folder or one session folder), checks
that each file starts like a pickle before unpickling it, and unpickles each file once,
from the bytes it hashed. Give it only files from a source you trust (the DRIVE repository,
or a copy whose ``git hash-object`` matches the repository's blob; ``meta["source"]["git_blob_sha1"]``
is that hash).

Layout read (one row per 2 s window; a column ``name_i`` is sample i of the window at 20 Hz):
a step is one transient window (``transitory_state_mask`` 1) followed by its steady windows
(``steady_state_mask`` 1): 0-2 s transient, 2-6 s steady on the Warthog. Step k is counted
from the rows (DRIVE's own ``calib_step`` lags at some boundaries). Per session the reader
returns a :class:`DriveSession`: ``samples`` (one row per 20 Hz sample), ``steps`` (one row
per step: the command, the start state and the steady means) and ``meta`` (provenance).

Quirks of DRIVE's files and what the reader does with each (all recorded in ``meta``):

* the gyro's sign (``imu_yaw_i``) differs between files: it is fixed per file against the
  ICP yaw rate (the sign of the correlation of the steps' steady means; refused when the
  data cannot tell, unless the config declares the sign) and the fix is recorded;
* ``icp_vel_yaw_i`` is a copy of the gyro, not an ICP yaw rate: never read as one (the ICP yaw
  rate comes from the ICP poses ``icp_yaw_i``);
* ICP poses are relative to each window's start, held between lidar updates (4-9 Hz) and not
  unwrapped: the reader unwraps them, composes a step's windows into the step's start frame,
  and measures the steady speed and yaw rate between the first and the last pose update of
  each window (both about equally stale), not from DRIVE's smoothed derivative ``icp_vel_x_i``
  (kept as ``vx_icp_drive``; it reads 6-10 % lower on asphalt and gravel, its spline starting
  from the held origin); a step's ICP heading change over its steady part is that yaw rate times
  the steady time (``heading_icp``; ``heading_gyro`` integrates the gyro). The composed poses
  (``x_icp, y_icp, yaw_icp``) lose the motion between a window's last held pose and the next
  window's origin (up to 10 % of a turn's heading): a trajectory to look at, not a target;
* in a few steady windows the ICP's motion runs against the wheels' (both faster than
  :data:`REVERSED_SPEED`, opposite signs; on the shared sessions 17 windows of 345 steps, none on grass:
  ICP 0.3-3.2 m/s against wheels 0.4-3.5 m/s, often the wheels' speed with its sign turned, 1.46 m/s
  forwards for wheels driving 1.46 m/s backwards), while the ICP's yaw changes still agree with the gyro:
  as if that window's registration had started half a turn from the truth. DRIVE's smoothed ``icp_vel_x``
  reverses too in 14 of those 17 (its window mean over 0.3 m/s against the wheels). No ground moves a
  robot against its driven wheels at such speeds, so such a window's ICP body velocity is not used (the
  step's steady speed comes from its other steady window) and the count is reported per step
  (``icp_reversed``) and in the quirks;
* identical sessions under several folders: detected by a hash of the arrays
  (:func:`read_drive` keeps one, preferring the run that recorded the data over an
  execute-only run that carries a copy);
* the terrain comes from ``metadata.yaml``, overridable per session by the caller; a folder
  name that names another terrain is reported, not trusted;
* the next command can arrive a few samples before a step's end (counted per step).

:func:`read_session` runs the reader's steps in order, each a named function of a module of its own:
DRIVE's files on disk (:mod:`simpick.real.logs.drive_files`), the arrays' layout and checks
(:mod:`simpick.real.logs.drive_layout`), the ICP's rates per window (:mod:`simpick.real.logs.drive_icp`),
the sample and step tables (:mod:`simpick.real.logs.drive_tables`), the terrain and the quirks in words
(:mod:`simpick.real.logs.drive_quirks`); the arrays turned into measurements are
:mod:`simpick.real.logs.drive_signals`. The names of the reader's output are importable from here.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.errors import InputError
from simpick.real.logs.drive_files import METADATA, PICKLE, find_sessions, load_pickle, read_geometry, read_metadata
from simpick.real.logs.drive_icp import icp_rates
from simpick.real.logs.drive_layout import ACCEL_OK, MASKS, SERIES, check_gravity, read_arrays, step_layout
from simpick.real.logs.drive_quirks import GYRO_COPY, folder_terrain_agrees, gyro_copy, session_quirks, session_terrain
from simpick.real.logs.drive_signals import RATE_HZ, REVERSED_SPEED, content_sha256, fix_gyro_sign
from simpick.real.logs.drive_tables import SAMPLE_COLUMNS, START_SECONDS, STEP_COLUMNS, sample_table, step_table

__all__ = [  # the reader's names, and the module's former ones that now live beside it
    "ACCEL_OK",
    "DATASET",
    "GYRO_COPY",
    "MASKS",
    "PICKLE",
    "REVERSED_SPEED",
    "SAMPLE_COLUMNS",
    "SERIES",
    "START_SECONDS",
    "STEP_COLUMNS",
    "DriveDataset",
    "DriveSession",
    "folder_terrain_agrees",
    "read_drive",
    "read_session",
]

DATASET = "DRIVE"


@dataclass
class DriveSession:
    """One DRIVE session. Units: s, rad/s (wheel speeds are wheel angular speeds, not rim
    speeds; multiply by ``meta["geometry"]["wheel_radius"]``), m/s, m/s^2, rad; body frame x
    forward, y left, z up. ``wz`` is the gyro yaw rate with its sign fixed; ``x_icp, y_icp,
    yaw_icp`` the ICP pose in the step's start frame.

    ``steps``, one row per step: ``t_start`` (s, session clock), ``steady_start``, ``t_end`` (s from the
    step's start); ``cmd_left/right`` the command held over the steady part and ``cmd_early_samples`` how
    many steady samples already hold the next one; steady means of the measured wheel speeds
    (``wheel_left/right``), the gyro (``wz_gyro``), the ICP yaw rate and body velocity (``wz_icp``,
    ``vx_icp``, ``vy_icp``; DRIVE's smoothed ``vx_icp_drive``) and the heading change over the steady part
    (``heading_icp``, ``heading_gyro``), and ``icp_reversed``, the steady windows whose ICP motion ran
    against the wheels and were left out of ``vx_icp``/``vy_icp`` (the module's quirks); the state at the
    step's start (``start_*``): the previous step's ICP body velocity over its last window and its gyro and
    wheel speeds over its last :data:`START_SECONDS`, all measured while that step's command had been held
    for seconds (step 0: its own first window and samples)."""

    name: str
    folder: Path
    samples: pd.DataFrame
    steps: pd.DataFrame
    meta: dict = field(default_factory=dict)

    @property
    def terrain_class(self) -> str:
        return self.meta["terrain_class"]

    @property
    def content_hash(self) -> str:
        return self.meta["source"]["content_sha256"]

    def wheel_commands(self, step: int) -> pd.DataFrame:
        """The step's measured wheel speeds as canonical side speeds (time from the step's start, v_left,
        v_right in m/s): what an engine replays."""
        r = self.meta["geometry"]["wheel_radius"]
        s = self.samples[self.samples.step == step]
        if s.empty:
            raise InputError(f"{self.folder}", f"has no step {step}", f"choose a step in 0..{len(self.steps) - 1}")
        return pd.DataFrame(
            {
                "time": s.t_step.to_numpy(),
                "v_left": r * s.wheel_left.to_numpy(),
                "v_right": r * s.wheel_right.to_numpy(),
            }
        )


@dataclass
class DriveDataset:
    folder: Path
    sessions: tuple[DriveSession, ...]
    duplicates: tuple[dict, ...] = ()  # {session, same_as, content_sha256, labels_agree}


# --- one session, in named steps ------------------------------------------------------------------


def _session_pickle(folder: Path) -> Path:
    """The session's dataset pickle, once both it and metadata.yaml are there."""
    if not (folder / METADATA).is_file():
        raise InputError(
            str(folder / METADATA),
            "missing: the session's terrain and robot are unknown",
            f"restore {METADATA} from the DRIVE repository, or remove the folder",
        )
    path = folder / PICKLE
    if not path.is_file():
        raise InputError(str(path), "missing: the session holds no data", "restore it from the DRIVE repository")
    return path


def read_session(
    folder: str | Path,
    *,
    terrain_class: str | None = None,
    gyro_sign: int | None = None,
    wheel_radius: float | None = None,
    wheel_baseline: float | None = None,
    declared_by: str = "the caller",
) -> DriveSession:
    """One DRIVE session folder (metadata.yaml, config_file_used/, the dataset pickle) read and checked.

    ``terrain_class`` replaces metadata.yaml's terrain; ``gyro_sign`` (+1 or -1) declares the sign of
    ``imu_yaw`` where the data cannot fix it (a declared sign the data contradict is refused);
    ``declared_by`` names where these come from in messages (e.g. the config key).
    """
    folder = Path(folder)
    path = _session_pickle(folder)
    metadata = read_metadata(folder)
    geometry = read_geometry(folder, wheel_radius, wheel_baseline)
    frame, source = load_pickle(path)

    # shape: windows of n samples, steps of one transient window and its steady windows
    raw, masks, n = read_arrays(frame, path)
    rows = len(frame)
    layout = step_layout(masks, rows, n, geometry, path)
    check_gravity(raw, path)
    content = content_sha256({**raw, **masks})

    # ICP rates per window, the gyro's sign from the steps' steady means
    icp = icp_rates(raw, masks["steady_state_mask"], geometry, layout)
    gyro_raw = layout.by_step(raw["imu_yaw"])
    wz_icp = np.nanmean(layout.windows(icp.wz)[:, 1:], axis=1)
    gyro = fix_gyro_sign(gyro_raw[:, layout.steady].mean(axis=1), wz_icp, gyro_sign, path, declared_by)
    copy = gyro_copy(frame, raw, n)

    samples = sample_table(raw, icp, gyro["sign"] * gyro_raw, layout)
    steps = step_table(raw, icp, gyro["sign"] * gyro_raw, wz_icp, layout)

    md = metadata["metadata"]
    terrain = session_terrain(folder, md, terrain_class, declared_by)
    early = steps["cmd_early_samples"].to_numpy()
    quirks = session_quirks(folder, gyro, copy, terrain, terrain_class, declared_by, icp, early, layout)
    per_step, window_s = layout.per_step, layout.window_s
    meta = {
        "dataset": DATASET,
        "session": folder.name,
        "reader": "simpick.real.logs.drive",
        "robot": md.get("robot"),
        "traction": md.get("traction"),
        "terrain_class": terrain[0],
        "terrain_source": f"declared by {declared_by}" if terrain_class is not None else f"{folder / METADATA}",
        "metadata_terrain": terrain[1],
        "folder_names_terrain": terrain[2],
        "only_execute_trajectories": bool(metadata.get("only_execute_trajectories", False)),
        "weather": md.get("weather"),
        "source": {**source, "content_sha256": content, "rows": rows, "samples_per_window": n},
        "geometry": geometry,
        "rate_hz": RATE_HZ,
        "windows_per_step": per_step,
        "window_s": window_s,
        "steady": f"{window_s:g}-{per_step * window_s:g} s of each step (rows flagged steady_state_mask)",
        "steps": layout.n_steps,
        "gyro": gyro,
        "gyro_copy_column": {"column": GYRO_COPY, "equals_imu_yaw": copy, "used": False},
        "quirks": quirks,
    }
    return DriveSession(folder.name, folder.resolve(), samples, steps, meta)


# --- a folder of sessions ---------------------------------------------------------------------------


def read_drive(
    folder: str | Path, *, sessions: Mapping[str, Mapping] | None = None, declared_by: str = "the caller", **geometry
) -> DriveDataset:
    """Every session under ``folder`` (see :func:`find_sessions`), one per content: a session whose
    arrays equal an earlier one's is listed in ``duplicates`` and not returned. Of equal sessions the
    one that recorded the data is kept (``only_execute_trajectories`` false), then the first by name.
    ``sessions`` maps a session folder name to its overrides (terrain_class, gyro_sign); an override
    naming no session found is refused."""
    sessions = dict(sessions or {})
    paths = find_sessions(folder)
    unknown = sorted(set(sessions) - {p.name for p in paths})
    if unknown:
        raise InputError(
            f"sessions {unknown} ({declared_by})",
            f"no such session folder in {folder}",
            f"name folders among {[p.name for p in paths]}",
        )
    read = [
        read_session(
            p,
            declared_by=f"{declared_by}, session {p.name}",
            **geometry,
            **{k: v for k, v in (sessions.get(p.name) or {}).items() if v is not None},
        )
        for p in paths
    ]
    order = sorted(read, key=lambda s: (s.meta["only_execute_trajectories"], s.name))
    kept: dict[str, DriveSession] = {}
    duplicates = []
    for s in order:
        first = kept.get(s.content_hash)
        if first is None:
            kept[s.content_hash] = s
            continue
        duplicates.append(
            {
                "session": s.name,
                "same_as": first.name,
                "content_sha256": s.content_hash,
                "labels_agree": s.terrain_class == first.terrain_class,
                "terrain": s.terrain_class,
                "kept_terrain": first.terrain_class,
            }
        )
    return DriveDataset(Path(folder).resolve(), tuple(sorted(kept.values(), key=lambda s: s.name)), tuple(duplicates))
