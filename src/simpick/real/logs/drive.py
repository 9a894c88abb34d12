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

The reader's steps are named functions below (:func:`read_session` runs them in order); DRIVE's files
on disk are :mod:`simpick.real.logs.drive_files`, the arrays turned into measurements
:mod:`simpick.real.logs.drive_signals`.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from simpick.errors import InputError
from simpick.real.logs.drive_files import METADATA, PICKLE, find_sessions, load_pickle, read_geometry, read_metadata
from simpick.real.logs.drive_signals import (
    DT,
    RATE_HZ,
    REVERSED_SPEED,
    column_of,
    compose_windows,
    content_sha256,
    fix_gyro_sign,
    held_longest,
    reversed_windows,
    series_of,
    update_rates,
)

DATASET = "DRIVE"
SERIES = {  # per-sample columns read (DRIVE name -> name here); rad/s, m/s^2, m, rad
    "cmd_left": "cmd_left",
    "cmd_right": "cmd_right",
    "left_wheel_vel": "wheel_left",
    "right_wheel_vel": "wheel_right",
    "imu_acceleration_x": "ax",
    "imu_acceleration_y": "ay",
    "imu_acceleration_z": "az",
    "imu_yaw": "wz",
    "icp_x": "icp_x",
    "icp_y": "icp_y",
    "icp_yaw": "icp_yaw",
    "icp_vel_x": "vx_icp_drive",
    "icp_vel_y": "vy_icp_drive",
}
MASKS = ("transitory_state_mask", "steady_state_mask")
GYRO_COPY = "icp_vel_yaw"  # a copy of imu_yaw in DRIVE's files: checked, never used
ACCEL_OK = (7.0, 13.0)  # m/s^2: the norm of the mean specific force (gravity; simpick.real.logs.validate's limits)
START_SECONDS = 0.5  # s at the end of the previous step averaged for a step's start state
SAMPLE_COLUMNS = [
    "step",
    "window",
    "sample",
    "time",
    "t_step",
    "steady",
    "cmd_left",
    "cmd_right",
    "wheel_left",
    "wheel_right",
    "ax",
    "ay",
    "az",
    "wz",
    "x_icp",
    "y_icp",
    "yaw_icp",
    "vx_icp_drive",
    "vy_icp_drive",
]
STEP_COLUMNS = [
    "step",
    "t_start",
    "steady_start",
    "t_end",
    "cmd_left",
    "cmd_right",
    "cmd_early_samples",
    "wheel_left",
    "wheel_right",
    "wz_gyro",
    "wz_icp",
    "vx_icp",
    "vy_icp",
    "icp_reversed",
    "vx_icp_drive",
    "heading_icp",
    "heading_gyro",
    "start_from",
    "start_vx",
    "start_vy",
    "start_wz",
    "start_wheel_left",
    "start_wheel_right",
]


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


@dataclass(frozen=True)
class _Layout:
    """A session's shape: windows of ``n`` samples, steps of ``per_step`` windows (one transient window,
    then steady ones), ``n_steps`` steps."""

    n: int
    per_step: int
    n_steps: int

    @property
    def window_s(self) -> float:
        return self.n * DT

    @property
    def steady(self) -> slice:
        """A step's steady samples, in a row of :meth:`by_step`."""
        return slice(self.n, self.per_step * self.n)

    def by_step(self, a: np.ndarray) -> np.ndarray:  # (rows, n) -> (steps, per_step * n)
        return a.reshape(self.n_steps, self.per_step * self.n)

    def windows(self, a: np.ndarray) -> np.ndarray:  # (rows,) -> (steps, per_step)
        return a.reshape(self.n_steps, self.per_step)


@dataclass(frozen=True)
class _Icp:
    """Per window, the ICP's body velocity and yaw rate between pose updates (a reversed steady window's
    velocity NaN), which windows were reversed, and the poses composed into each step's start frame."""

    vx: np.ndarray
    vy: np.ndarray
    wz: np.ndarray
    reversed: np.ndarray
    x: np.ndarray
    y: np.ndarray
    yaw: np.ndarray


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


def _read_arrays(frame: pd.DataFrame, path: Path) -> tuple[dict, dict, int]:
    """The per-sample series (DRIVE's names, (rows, n) each), the window flags, and n, the samples of a window."""
    n = sum(1 for c in frame.columns if re.fullmatch(r"cmd_left_\d+", str(c)))
    if n < 2:
        raise InputError(
            f"{path}: column 'cmd_left_0'",
            "missing (no per-sample cmd_left_i columns)",
            "use the pickle DRIVE's parser wrote",
        )
    raw = {base: series_of(frame, base, n, path) for base in SERIES}
    masks = {m: column_of(frame, m, path) for m in MASKS}
    return raw, masks, n


def _layout(masks: dict, rows: int, n: int, geometry: dict, path: Path) -> _Layout:
    """The steps the window flags mark, checked: each one transient window and the same number of steady
    windows, as long as the session's DRIVE configuration says."""
    trans, steady = masks["transitory_state_mask"], masks["steady_state_mask"]
    if (
        rows == 0
        or not np.isin(trans, (0, 1)).all()
        or not np.isin(steady, (0, 1)).all()
        or (trans + steady != 1).any()
    ):
        raise InputError(
            f"{path}: columns {list(MASKS)}",
            "must be 0/1 flags, exactly one set per row",
            "use the pickle DRIVE's parser wrote",
        )
    starts = np.flatnonzero(trans == 1)
    if len(starts) == 0 or starts[0] != 0:
        raise InputError(
            f"{path}: column 'transitory_state_mask'",
            "row 0 does not start a step (flag 1)",
            "use the pickle DRIVE's parser wrote, uncut",
        )
    lengths = np.diff(np.append(starts, rows))
    if len(set(lengths.tolist())) != 1 or lengths[0] < 2:
        bad = int(starts[np.flatnonzero(lengths != np.bincount(lengths).argmax())[0]]) if len(set(lengths)) > 1 else 0
        raise InputError(
            f"{path}: column 'transitory_state_mask'",
            f"steps must all be one transient window and the same number of steady windows; the step "
            f"at row {bad} differs ({rows} rows)",
            "drop incomplete steps (whole steps of rows)",
        )
    layout = _Layout(n=n, per_step=int(lengths[0]), n_steps=rows // int(lengths[0]))
    per_step, window_s = layout.per_step, layout.window_s
    if geometry.get("step_len") is not None and abs(geometry["step_len"] - per_step * window_s) > 1e-6:
        raise InputError(
            f"{path}: column 'transitory_state_mask'",
            f"steps of {per_step} windows of {window_s:g} s, but the session's DRIVE configuration "
            f"({geometry['source']}) says step_len {geometry['step_len']:g} s",
            "use the pickle and the configuration of the same session",
        )
    return layout


def _check_gravity(raw: dict, path: Path) -> None:
    """The mean specific force must be gravity along +z (m/s^2): the accelerometer's units and axes."""
    force = np.array([raw[f"imu_acceleration_{a}"].mean() for a in "xyz"])
    norm = float(np.linalg.norm(force))
    if not ACCEL_OK[0] <= norm <= ACCEL_OK[1] or force[2] < 0.5 * norm:
        raise InputError(
            f"{path}: columns imu_acceleration_*",
            f"mean specific force ({force[0]:.2f}, {force[1]:.2f}, {force[2]:.2f}) m/s^2: not gravity "
            f"along +z (norm {ACCEL_OK[0]:g}-{ACCEL_OK[1]:g} m/s^2 expected, as in DRIVE's own files)",
            "use the pickle DRIVE's parser wrote (m/s^2, z up, gravity included)",
        )


def _icp(raw: dict, steady: np.ndarray, geometry: dict, layout: _Layout) -> _Icp:
    """The ICP poses unwrapped, their update-to-update rates per window (reversed steady windows left
    out) and the poses composed per step."""
    yaw_u = np.unwrap(raw["icp_yaw"], axis=1)
    vx_w, vy_w, wz_w = update_rates(raw["icp_x"], raw["icp_y"], yaw_u)
    reversed_w = (steady == 1) & reversed_windows(
        vx_w, raw["left_wheel_vel"], raw["right_wheel_vel"], geometry["wheel_radius"]
    )  # a transient window may end moving against its wheels' mean: the robot reversing within it
    vx_w, vy_w = np.where(reversed_w, np.nan, vx_w), np.where(reversed_w, np.nan, vy_w)
    X, Y, Yaw = compose_windows(raw["icp_x"], raw["icp_y"], yaw_u, layout.per_step)
    return _Icp(vx=vx_w, vy=vy_w, wz=wz_w, reversed=reversed_w, x=X, y=Y, yaw=Yaw)


def _gyro_copy(frame: pd.DataFrame, raw: dict, n: int) -> bool | None:
    """Whether DRIVE's icp_vel_yaw_i columns equal imu_yaw_i (None: the file has none)."""
    if all(f"{GYRO_COPY}_{i}" in frame.columns for i in range(n)):
        return bool(np.array_equal(frame[[f"{GYRO_COPY}_{i}" for i in range(n)]].to_numpy(float), raw["imu_yaw"]))
    return None


def _sample_table(raw: dict, icp: _Icp, wz: np.ndarray, layout: _Layout) -> pd.DataFrame:
    """One row per 20 Hz sample (:data:`SAMPLE_COLUMNS`); ``wz`` the gyro with its sign fixed, by step."""
    n, per_step, by_step = layout.n, layout.per_step, layout.by_step
    sample = np.tile(np.arange(per_step * n), layout.n_steps)
    step = np.repeat(np.arange(layout.n_steps), per_step * n)
    t_step = sample * DT
    return pd.DataFrame(
        {
            "step": step,
            "window": sample // n,
            "sample": sample,
            "time": step * per_step * layout.window_s + t_step,
            "t_step": t_step,
            "steady": sample >= n,
            **{
                SERIES[b]: by_step(raw[b]).ravel()
                for b in (
                    "cmd_left",
                    "cmd_right",
                    "left_wheel_vel",
                    "right_wheel_vel",
                    "imu_acceleration_x",
                    "imu_acceleration_y",
                    "imu_acceleration_z",
                )
            },
            "wz": wz.ravel(),
            "x_icp": by_step(icp.x).ravel(),
            "y_icp": by_step(icp.y).ravel(),
            "yaw_icp": by_step(icp.yaw).ravel(),
            "vx_icp_drive": by_step(raw["icp_vel_x"]).ravel(),
            "vy_icp_drive": by_step(raw["icp_vel_y"]).ravel(),
        },
        columns=SAMPLE_COLUMNS,
    )


def _step_table(raw: dict, icp: _Icp, wz: np.ndarray, wz_icp: np.ndarray, layout: _Layout) -> pd.DataFrame:
    """One row per step (:data:`STEP_COLUMNS`): the command, the steady means, the start state; ``wz``
    the gyro with its sign fixed, by step, ``wz_icp`` the steps' steady ICP yaw rate."""
    n_steps, per_step, window_s, steady_slice = layout.n_steps, layout.per_step, layout.window_s, layout.steady
    cl, cr = layout.by_step(raw["cmd_left"]), layout.by_step(raw["cmd_right"])
    wl, wr = layout.by_step(raw["left_wheel_vel"]), layout.by_step(raw["right_wheel_vel"])
    cmd_l, cmd_r = held_longest(cl[:, steady_slice]), held_longest(cr[:, steady_slice])
    early = ((cl[:, steady_slice] != cmd_l[:, None]) | (cr[:, steady_slice] != cmd_r[:, None])).sum(axis=1)
    with warnings.catch_warnings():  # a step whose every steady window is unusable has no ICP speed (NaN)
        warnings.simplefilter("ignore", RuntimeWarning)
        vx_s = np.nanmean(layout.windows(icp.vx)[:, 1:], axis=1)
        vy_s = np.nanmean(layout.windows(icp.vy)[:, 1:], axis=1)
    reversed_s = layout.windows(icp.reversed)[:, 1:].sum(axis=1)
    last = max(1, round(START_SECONDS / DT))
    vx_w, vy_w = layout.windows(icp.vx), layout.windows(icp.vy)
    start = {  # the previous step's last START_SECONDS (steady: its command held 4 s), or step 0's own start
        "vx": np.r_[vx_w[0, 0], vx_w[:-1, -1]],
        "vy": np.r_[vy_w[0, 0], vy_w[:-1, -1]],
        "wz": np.r_[wz[0, :last].mean(), wz[:-1, -last:].mean(axis=1)],
        "wl": np.r_[wl[0, :last].mean(), wl[:-1, -last:].mean(axis=1)],
        "wr": np.r_[wr[0, :last].mean(), wr[:-1, -last:].mean(axis=1)],
    }
    return pd.DataFrame(
        {
            "step": np.arange(n_steps),
            "t_start": np.arange(n_steps) * per_step * window_s,
            "steady_start": np.full(n_steps, window_s),
            "t_end": np.full(n_steps, per_step * window_s),
            "cmd_left": cmd_l,
            "cmd_right": cmd_r,
            "cmd_early_samples": early,
            "wheel_left": wl[:, steady_slice].mean(axis=1),
            "wheel_right": wr[:, steady_slice].mean(axis=1),
            "wz_gyro": wz[:, steady_slice].mean(axis=1),
            "wz_icp": wz_icp,
            "vx_icp": vx_s,
            "vy_icp": vy_s,
            "icp_reversed": reversed_s,
            "vx_icp_drive": layout.by_step(raw["icp_vel_x"])[:, steady_slice].mean(axis=1),
            "heading_icp": np.nansum(layout.windows(icp.wz)[:, 1:], axis=1) * window_s,
            "heading_gyro": wz[:, steady_slice].sum(axis=1) * DT,
            "start_from": ["own first window (no previous step)"] + ["previous step's end"] * (n_steps - 1),
            "start_vx": start["vx"],
            "start_vy": start["vy"],
            "start_wz": start["wz"],
            "start_wheel_left": start["wl"],
            "start_wheel_right": start["wr"],
        },
        columns=STEP_COLUMNS,
    )


def folder_terrain_agrees(name: str, terrain: str) -> bool:
    """Whether a session folder's name (DRIVE: <robot>_<traction>_<terrain>_<date>) names ``terrain``."""
    return f"_{terrain.lower()}_" in f"_{name.lower()}_"


def _terrain(folder: Path, md: dict, terrain_class: str | None, declared_by: str) -> tuple[str, object, bool | None]:
    """The session's terrain class (declared, else metadata.yaml's), metadata's own terrain, and whether
    the folder's name names it (None: metadata names none)."""
    meta_terrain = md.get("terrain")
    if terrain_class is None and not isinstance(meta_terrain, str):
        raise InputError(
            f"{folder / METADATA}: field 'metadata.terrain'",
            "missing",
            f"add it, or declare the session's terrain class ({declared_by})",
        )
    terrain = str(terrain_class if terrain_class is not None else meta_terrain).lower()
    agrees = folder_terrain_agrees(folder.name, str(meta_terrain)) if isinstance(meta_terrain, str) else None
    return terrain, meta_terrain, agrees


def _quirks(
    folder: Path,
    gyro: dict,
    copy: bool | None,
    terrain: tuple[str, object, bool | None],
    terrain_class: str | None,
    declared_by: str,
    icp: _Icp,
    early: np.ndarray,
    layout: _Layout,
) -> list[str]:
    """What this session's files needed (the module's quirks), in words for ``meta["quirks"]``."""
    terrain_name, meta_terrain, agrees = terrain
    reversed_w = icp.reversed
    quirks = []
    if gyro["sign"] < 0:
        quirks.append(f"imu_yaw has the opposite sign to the ICP yaw rate here: negated ({gyro['basis']})")
    if copy:
        quirks.append(f"{GYRO_COPY}_i is a copy of imu_yaw_i (not an ICP yaw rate): not used")
    if agrees is False:
        quirks.append(f"the folder name {folder.name!r} does not name the metadata terrain {meta_terrain!r}")
    if terrain_class is not None and isinstance(meta_terrain, str) and terrain_name != meta_terrain.lower():
        quirks.append(f"terrain {terrain_name!r} declared by {declared_by} replaces metadata's {meta_terrain!r}")
    if reversed_w.any():
        quirks.append(
            f"the ICP moves against the wheels (opposite signs, both over {REVERSED_SPEED:g} m/s) in "
            f"{int(reversed_w.sum())} window(s) of {int((layout.windows(reversed_w).any(axis=1)).sum())} "
            "step(s): those windows' ICP speed not used"
        )
    if early.any():
        quirks.append(
            f"the next command arrives up to {int(early.max())} sample(s) before the step's end in "
            f"{int((early > 0).sum())} step(s)"
        )
    return quirks


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
    raw, masks, n = _read_arrays(frame, path)
    rows = len(frame)
    layout = _layout(masks, rows, n, geometry, path)
    _check_gravity(raw, path)
    content = content_sha256({**raw, **masks})

    # ICP rates per window, the gyro's sign from the steps' steady means
    icp = _icp(raw, masks["steady_state_mask"], geometry, layout)
    gyro_raw = layout.by_step(raw["imu_yaw"])
    wz_icp = np.nanmean(layout.windows(icp.wz)[:, 1:], axis=1)
    gyro = fix_gyro_sign(gyro_raw[:, layout.steady].mean(axis=1), wz_icp, gyro_sign, path, declared_by)
    copy = _gyro_copy(frame, raw, n)

    samples = _sample_table(raw, icp, gyro["sign"] * gyro_raw, layout)
    steps = _step_table(raw, icp, gyro["sign"] * gyro_raw, wz_icp, layout)

    md = metadata["metadata"]
    terrain = _terrain(folder, md, terrain_class, declared_by)
    early = steps["cmd_early_samples"].to_numpy()
    quirks = _quirks(folder, gyro, copy, terrain, terrain_class, declared_by, icp, early, layout)
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
