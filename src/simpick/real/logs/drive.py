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
"""

from __future__ import annotations

import hashlib
import io
import pickle
import re
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from simpick.errors import InputError
from simpick.real.datasets import DatasetProblems

DATASET = "DRIVE"
PICKLE = Path("model_training_datasets") / "slip_dataset_all.pkl"
METADATA = "metadata.yaml"
RATE_HZ = 20.0  # DRIVE's logger writes one sample per 0.05 s (sample-and-hold of each topic)
DT = 1.0 / RATE_HZ
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
MIN_SIGN_STEPS = 3  # steps turning faster than SIGN_TURN (ICP) needed to fix the gyro's sign
SIGN_TURN = 0.2  # rad/s
ACCEL_OK = (7.0, 13.0)  # m/s^2: the norm of the mean specific force (gravity; simpick.real.logs.validate's limits)
MIN_SIGN_CORRELATION = 0.9
START_SECONDS = 0.5  # s at the end of the previous step averaged for a step's start state
REVERSED_SPEED = 0.3  # m/s: an ICP window moving against its wheels faster than this, both ways, is not used
# (ten times the ICP's spread against the wheels on grass, where no window reverses: median |ICP - wheels| per
# step 0.01-0.04 m/s; the reversed windows of the shared sessions run at 0.3-3.2 m/s against their wheels)
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


# --- finding sessions ---------------------------------------------------------------------------


def find_sessions(folder: str | Path) -> list[Path]:
    """The session folders under ``folder``: one session folder itself (it holds metadata.yaml), a
    ``calib_data/`` folder, or a DRIVE checkout holding ``calib_data/``. A sub-folder is a session
    when it holds metadata.yaml or the dataset pickle; one with only one of the two is refused."""
    folder = Path(folder)
    if not folder.is_dir():
        raise InputError(
            str(folder),
            "DRIVE folder not found" if not folder.exists() else "is a file, not a folder",
            "pass DRIVE's calib_data folder (or one session folder in it)",
        )
    if (folder / METADATA).is_file() or (folder / PICKLE).is_file():
        candidates = [folder]
    else:
        if (folder / "calib_data").is_dir():
            folder = folder / "calib_data"
        candidates = sorted(p for p in folder.iterdir() if p.is_dir() and not p.name.startswith((".", "_")))
        candidates = [p for p in candidates if (p / METADATA).exists() or (p / PICKLE).exists()]
        if not candidates:
            raise InputError(
                str(folder),
                f"holds no DRIVE session (a folder with {METADATA} and {PICKLE})",
                "pass DRIVE's calib_data folder (or one session folder in it)",
            )
    problems = []
    for p in candidates:
        if not (p / METADATA).is_file():
            problems.append(
                InputError(
                    str(p / METADATA),
                    "missing: the session's terrain and robot are unknown",
                    f"restore {METADATA} from the DRIVE repository, or remove the folder",
                )
            )
        elif not (p / PICKLE).is_file():
            problems.append(
                InputError(
                    str(p / PICKLE),
                    "missing: the session holds no data",
                    "restore the file from the DRIVE repository, or remove the folder",
                )
            )
    if problems:
        raise DatasetProblems(problems)
    return candidates


# --- one session ----------------------------------------------------------------------------------


def git_blob_sha1(data: bytes) -> str:
    """What ``git hash-object FILE`` prints: how DRIVE's own files are identified."""
    return hashlib.sha1(b"blob %d\x00" % len(data) + data).hexdigest()


def load_pickle(path: Path) -> tuple[pd.DataFrame, dict]:
    """The pickled DataFrame and the file's identity. Unpickles only after the bytes look like a pickle."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(str(path), f"cannot be read: {exc.strerror or exc}") from None
    if len(data) < 2 or data[0] != 0x80 or not 2 <= data[1] <= pickle.HIGHEST_PROTOCOL:
        raise InputError(
            str(path),
            "is not a pickle file (it does not start with a pickle protocol header)",
            "put DRIVE's slip_dataset_all.pkl there, as written by DRIVE's parser",
        )
    try:
        with warnings.catch_warnings():  # pickles of an older numpy name numpy.core, which still loads
            warnings.simplefilter("ignore", DeprecationWarning)
            frame = pd.read_pickle(io.BytesIO(data))
    except (
        pickle.UnpicklingError,
        EOFError,
        AttributeError,
        ImportError,
        IndexError,
        KeyError,
        TypeError,
        ValueError,
        OSError,
    ) as exc:  # what a truncated, foreign or damaged pickle raises
        raise InputError(
            str(path),
            f"cannot be unpickled ({type(exc).__name__}: {exc})",
            "download the file again from the DRIVE repository",
        ) from None
    if not isinstance(frame, pd.DataFrame):
        raise InputError(
            str(path),
            f"holds a {type(frame).__name__}, not a pandas DataFrame",
            "put DRIVE's slip_dataset_all.pkl there",
        )
    return frame, {"path": str(path.resolve()), "bytes": len(data), "git_blob_sha1": git_blob_sha1(data)}


def read_metadata(folder: Path) -> dict:
    path = folder / METADATA
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError, UnicodeDecodeError) as exc:
        raise InputError(str(path), f"cannot be read as YAML: {exc}", "restore it from the DRIVE repository") from None
    if not isinstance(data, dict) or not isinstance(data.get("metadata"), dict):
        raise InputError(
            f"{path}: field 'metadata'", "missing or not a mapping", "restore the file from the DRIVE repository"
        )
    return data


def read_geometry(folder: Path, wheel_radius: float | None, wheel_baseline: float | None) -> dict:
    """Wheel radius and baseline from the session's own DRIVE configuration (the figures DRIVE used to
    turn body commands into wheel commands), unless the caller gives them."""
    found = {}
    for path in sorted((folder / "config_file_used").glob("*.yaml")):
        try:
            data = yaml.safe_load(path.read_text())
        except (OSError, yaml.YAMLError, UnicodeDecodeError):
            continue
        for node in (data or {}).values() if isinstance(data, dict) else ():
            params = node.get("ros__parameters") if isinstance(node, dict) else None
            if isinstance(params, dict) and "wheel_radius" in params and "wheel_baseline" in params:
                found = {
                    "wheel_radius": float(params["wheel_radius"]),
                    "wheel_baseline": float(params["wheel_baseline"]),
                    "step_len": float(params["step_len"]) if "step_len" in params else None,
                    "source": str(path),
                }
    given = {k: v for k, v in (("wheel_radius", wheel_radius), ("wheel_baseline", wheel_baseline)) if v is not None}
    if given:
        found = {
            **found,
            **given,
            "source": "given by the caller" + (f" (session config: {found['source']})" if found else ""),
        }
    if "wheel_radius" not in found or "wheel_baseline" not in found:
        raise InputError(
            str(folder / "config_file_used"),
            "no DRIVE configuration with wheel_radius and wheel_baseline",
            "restore config_file_used/ from the DRIVE repository, or give the robot's wheel radius and baseline",
        )
    for key in ("wheel_radius", "wheel_baseline"):
        if not found[key] > 0:
            raise InputError(f"{found['source']}: {key}", f"{found[key]} must be positive")
    return found


def _series(frame: pd.DataFrame, base: str, n: int, path: Path) -> np.ndarray:
    names = [f"{base}_{i}" for i in range(n)]
    missing = [c for c in names if c not in frame.columns]
    if missing:
        raise InputError(
            f"{path}: column {missing[0]!r}",
            f"missing ({len(missing)} of {base}_0..{base}_{n - 1})",
            "the file is not a complete DRIVE slip dataset; use the pickle DRIVE's parser wrote",
        )
    values = frame[names].to_numpy()
    if values.dtype.kind not in "fiu":
        raise InputError(
            f"{path}: columns {base}_*", f"not numeric (dtype {values.dtype})", "use the pickle DRIVE's parser wrote"
        )
    bad = np.argwhere(~np.isfinite(values.astype(float)))
    if len(bad):
        row, col = bad[0]
        raise InputError(
            f"{path}: column {names[col]!r}",
            f"not finite at row {row}",
            "repair or drop that step (its three rows) from the file",
        )
    return values.astype(float)


def _column(frame: pd.DataFrame, name: str, path: Path) -> np.ndarray:
    if name not in frame.columns:
        raise InputError(f"{path}: column {name!r}", "missing", "use the pickle DRIVE's parser wrote")
    return _series(frame.rename(columns={name: f"{name}_0"}), name, 1, path)[:, 0]


def content_sha256(arrays: Mapping[str, np.ndarray]) -> str:
    """A hash of the arrays read (names, shapes and float64 bytes): equal for the same data whatever
    the file's pickle protocol, folder or name."""
    h = hashlib.sha256()
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name], dtype="<f8")
        h.update(name.encode() + repr(a.shape).encode() + a.tobytes())
    return h.hexdigest()


def _update_rates(x: np.ndarray, y: np.ndarray, yaw: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per window, the mean body speed (vx, vy) and yaw rate between the first and the last ICP pose
    update (the ticks where the held pose changes): both poses are fresh to within one tick, so the
    interval is known, where the window's first sample is a held origin of unknown age."""
    n_rows = len(x)
    vx, vy, wz = (np.full(n_rows, np.nan) for _ in range(3))
    changed = (np.diff(x, axis=1) != 0) | (np.diff(y, axis=1) != 0) | (np.diff(yaw, axis=1) != 0)
    for k in range(n_rows):
        ticks = np.flatnonzero(changed[k]) + 1
        if len(ticks) < 2:
            continue
        a, b = ticks[0], ticks[-1]
        dt = DT * (b - a)
        dpsi = yaw[k, b] - yaw[k, a]
        mid = 0.5 * (yaw[k, a] + yaw[k, b])
        dx, dy = x[k, b] - x[k, a], y[k, b] - y[k, a]
        # chord in the mid-heading frame, lengthened to the arc of a constant-curvature path
        arc = 1.0 if abs(dpsi) < 1e-9 else (dpsi / 2) / np.sin(dpsi / 2)
        vx[k] = (dx * np.cos(mid) + dy * np.sin(mid)) * arc / dt
        vy[k] = (-dx * np.sin(mid) + dy * np.cos(mid)) * arc / dt
        wz[k] = dpsi / dt
    return vx, vy, wz


def reversed_windows(vx: np.ndarray, wheel_left: np.ndarray, wheel_right: np.ndarray, radius: float) -> np.ndarray:
    """Per window, whether its ICP forward speed ``vx`` (m/s) and its wheels' kinematic forward speed (the
    mean of the measured wheel speeds, rad/s, times ``radius``) both exceed :data:`REVERSED_SPEED` with
    opposite signs: motion no ground gives driven wheels (the module's quirks)."""
    v_kin = radius * (wheel_left.mean(axis=1) + wheel_right.mean(axis=1)) / 2
    with np.errstate(invalid="ignore"):
        return (np.abs(v_kin) > REVERSED_SPEED) & (np.abs(vx) > REVERSED_SPEED) & (np.sign(vx) != np.sign(v_kin))


def _compose(x: np.ndarray, y: np.ndarray, yaw: np.ndarray, per_step: int) -> tuple[np.ndarray, ...]:
    """Each step's windows (poses relative to each window's start) in the step's start frame: window
    j+1 starts where window j's last sample ends (0.05 s of motion between them is not logged)."""
    X, Y, Yaw = x.copy(), y.copy(), yaw.copy()
    for first in range(0, len(x), per_step):
        ox = oy = oyaw = 0.0
        for k in range(first, first + per_step):
            c, s = np.cos(oyaw), np.sin(oyaw)
            X[k] = ox + c * x[k] - s * y[k]
            Y[k] = oy + s * x[k] + c * y[k]
            Yaw[k] = oyaw + yaw[k]
            ox, oy, oyaw = X[k, -1], Y[k, -1], Yaw[k, -1]
    return X, Y, Yaw


def folder_terrain_agrees(name: str, terrain: str) -> bool:
    """Whether a session folder's name (DRIVE: <robot>_<traction>_<terrain>_<date>) names ``terrain``."""
    return f"_{terrain.lower()}_" in f"_{name.lower()}_"


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
    if not (folder / METADATA).is_file():
        raise InputError(
            str(folder / METADATA),
            "missing: the session's terrain and robot are unknown",
            f"restore {METADATA} from the DRIVE repository, or remove the folder",
        )
    path = folder / PICKLE
    if not path.is_file():
        raise InputError(str(path), "missing: the session holds no data", "restore it from the DRIVE repository")
    metadata = read_metadata(folder)
    geometry = read_geometry(folder, wheel_radius, wheel_baseline)
    frame, source = load_pickle(path)

    # --- shape: windows of n samples, steps of one transient window and its steady windows
    n = sum(1 for c in frame.columns if re.fullmatch(r"cmd_left_\d+", str(c)))
    if n < 2:
        raise InputError(
            f"{path}: column 'cmd_left_0'",
            "missing (no per-sample cmd_left_i columns)",
            "use the pickle DRIVE's parser wrote",
        )
    raw = {base: _series(frame, base, n, path) for base in SERIES}
    masks = {m: _column(frame, m, path) for m in MASKS}
    rows = len(frame)
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
    per_step = int(lengths[0])
    n_steps = rows // per_step
    window_s = n * DT
    if geometry.get("step_len") is not None and abs(geometry["step_len"] - per_step * window_s) > 1e-6:
        raise InputError(
            f"{path}: column 'transitory_state_mask'",
            f"steps of {per_step} windows of {window_s:g} s, but the session's DRIVE configuration "
            f"({geometry['source']}) says step_len {geometry['step_len']:g} s",
            "use the pickle and the configuration of the same session",
        )
    force = np.array([raw[f"imu_acceleration_{a}"].mean() for a in "xyz"])
    norm = float(np.linalg.norm(force))
    if not ACCEL_OK[0] <= norm <= ACCEL_OK[1] or force[2] < 0.5 * norm:
        raise InputError(
            f"{path}: columns imu_acceleration_*",
            f"mean specific force ({force[0]:.2f}, {force[1]:.2f}, {force[2]:.2f}) m/s^2: not gravity "
            f"along +z (norm {ACCEL_OK[0]:g}-{ACCEL_OK[1]:g} m/s^2 expected, as in DRIVE's own files)",
            "use the pickle DRIVE's parser wrote (m/s^2, z up, gravity included)",
        )
    arrays = {**raw, **masks}
    content = content_sha256(arrays)

    # --- ICP: unwrap, update-to-update rates per window, the steady part per step
    yaw_u = np.unwrap(raw["icp_yaw"], axis=1)
    vx_w, vy_w, wz_w = _update_rates(raw["icp_x"], raw["icp_y"], yaw_u)
    reversed_w = (steady == 1) & reversed_windows(
        vx_w, raw["left_wheel_vel"], raw["right_wheel_vel"], geometry["wheel_radius"]
    )  # a transient window may end moving against its wheels' mean: the robot reversing within it
    vx_w, vy_w = np.where(reversed_w, np.nan, vx_w), np.where(reversed_w, np.nan, vy_w)
    X, Y, Yaw = _compose(raw["icp_x"], raw["icp_y"], yaw_u, per_step)

    def by_step(a: np.ndarray) -> np.ndarray:  # (rows, n) -> (steps, per_step * n)
        return a.reshape(n_steps, per_step * n)

    steady_slice = slice(n, per_step * n)
    gyro_raw = by_step(raw["imu_yaw"])
    gyro_steady = gyro_raw[:, steady_slice].mean(axis=1)
    wz_icp = np.nanmean(wz_w.reshape(n_steps, per_step)[:, 1:], axis=1)
    gyro = _gyro_sign(gyro_steady, wz_icp, gyro_sign, path, declared_by)

    copy = None
    if all(f"{GYRO_COPY}_{i}" in frame.columns for i in range(n)):
        copy = bool(np.array_equal(frame[[f"{GYRO_COPY}_{i}" for i in range(n)]].to_numpy(float), raw["imu_yaw"]))

    # --- per-sample table
    sample = np.tile(np.arange(per_step * n), n_steps)
    step = np.repeat(np.arange(n_steps), per_step * n)
    t_step = sample * DT
    samples = pd.DataFrame(
        {
            "step": step,
            "window": sample // n,
            "sample": sample,
            "time": step * per_step * window_s + t_step,
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
            "wz": gyro["sign"] * gyro_raw.ravel(),
            "x_icp": by_step(X).ravel(),
            "y_icp": by_step(Y).ravel(),
            "yaw_icp": by_step(Yaw).ravel(),
            "vx_icp_drive": by_step(raw["icp_vel_x"]).ravel(),
            "vy_icp_drive": by_step(raw["icp_vel_y"]).ravel(),
        },
        columns=SAMPLE_COLUMNS,
    )

    # --- per-step table: the command, the steady means, the start state
    cl, cr = by_step(raw["cmd_left"]), by_step(raw["cmd_right"])
    wl, wr = by_step(raw["left_wheel_vel"]), by_step(raw["right_wheel_vel"])
    wz = gyro["sign"] * gyro_raw
    cmd_l, cmd_r = _held(cl[:, steady_slice]), _held(cr[:, steady_slice])
    early = ((cl[:, steady_slice] != cmd_l[:, None]) | (cr[:, steady_slice] != cmd_r[:, None])).sum(axis=1)
    with warnings.catch_warnings():  # a step whose every steady window is unusable has no ICP speed (NaN)
        warnings.simplefilter("ignore", RuntimeWarning)
        vx_s = np.nanmean(vx_w.reshape(n_steps, per_step)[:, 1:], axis=1)
        vy_s = np.nanmean(vy_w.reshape(n_steps, per_step)[:, 1:], axis=1)
    reversed_s = reversed_w.reshape(n_steps, per_step)[:, 1:].sum(axis=1)
    last = max(1, round(START_SECONDS / DT))
    start = {  # the previous step's last START_SECONDS (steady: its command held 4 s), or step 0's own start
        "vx": np.r_[vx_w.reshape(n_steps, per_step)[0, 0], vx_w.reshape(n_steps, per_step)[:-1, -1]],
        "vy": np.r_[vy_w.reshape(n_steps, per_step)[0, 0], vy_w.reshape(n_steps, per_step)[:-1, -1]],
        "wz": np.r_[wz[0, :last].mean(), wz[:-1, -last:].mean(axis=1)],
        "wl": np.r_[wl[0, :last].mean(), wl[:-1, -last:].mean(axis=1)],
        "wr": np.r_[wr[0, :last].mean(), wr[:-1, -last:].mean(axis=1)],
    }
    steps = pd.DataFrame(
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
            "vx_icp_drive": by_step(raw["icp_vel_x"])[:, steady_slice].mean(axis=1),
            "heading_icp": np.nansum(wz_w.reshape(n_steps, per_step)[:, 1:], axis=1) * window_s,
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

    # --- terrain and labels
    md = metadata["metadata"]
    meta_terrain = md.get("terrain")
    if terrain_class is None and not isinstance(meta_terrain, str):
        raise InputError(
            f"{folder / METADATA}: field 'metadata.terrain'",
            "missing",
            f"add it, or declare the session's terrain class ({declared_by})",
        )
    terrain = str(terrain_class if terrain_class is not None else meta_terrain).lower()
    agrees = folder_terrain_agrees(folder.name, str(meta_terrain)) if isinstance(meta_terrain, str) else None
    quirks = []
    if gyro["sign"] < 0:
        quirks.append(f"imu_yaw has the opposite sign to the ICP yaw rate here: negated ({gyro['basis']})")
    if copy:
        quirks.append(f"{GYRO_COPY}_i is a copy of imu_yaw_i (not an ICP yaw rate): not used")
    if agrees is False:
        quirks.append(f"the folder name {folder.name!r} does not name the metadata terrain {meta_terrain!r}")
    if terrain_class is not None and isinstance(meta_terrain, str) and terrain != meta_terrain.lower():
        quirks.append(f"terrain {terrain!r} declared by {declared_by} replaces metadata's {meta_terrain!r}")
    if reversed_w.any():
        quirks.append(
            f"the ICP moves against the wheels (opposite signs, both over {REVERSED_SPEED:g} m/s) in "
            f"{int(reversed_w.sum())} window(s) of {int((reversed_w.reshape(n_steps, per_step).any(axis=1)).sum())} "
            "step(s): those windows' ICP speed not used"
        )
    if early.any():
        quirks.append(
            f"the next command arrives up to {int(early.max())} sample(s) before the step's end in "
            f"{int((early > 0).sum())} step(s)"
        )
    meta = {
        "dataset": DATASET,
        "session": folder.name,
        "reader": "simpick.real.logs.drive",
        "robot": md.get("robot"),
        "traction": md.get("traction"),
        "terrain_class": terrain,
        "terrain_source": f"declared by {declared_by}" if terrain_class is not None else f"{folder / METADATA}",
        "metadata_terrain": meta_terrain,
        "folder_names_terrain": agrees,
        "only_execute_trajectories": bool(metadata.get("only_execute_trajectories", False)),
        "weather": md.get("weather"),
        "source": {**source, "content_sha256": content, "rows": rows, "samples_per_window": n},
        "geometry": geometry,
        "rate_hz": RATE_HZ,
        "windows_per_step": per_step,
        "window_s": window_s,
        "steady": f"{window_s:g}-{per_step * window_s:g} s of each step (rows flagged steady_state_mask)",
        "steps": n_steps,
        "gyro": gyro,
        "gyro_copy_column": {"column": GYRO_COPY, "equals_imu_yaw": copy, "used": False},
        "quirks": quirks,
    }
    return DriveSession(folder.name, folder.resolve(), samples, steps, meta)


def _held(values: np.ndarray) -> np.ndarray:
    """Per row, the value held longest (the step's command, where the next one may arrive early)."""
    out = np.empty(len(values))
    for k, row in enumerate(values):
        uniq, counts = np.unique(row, return_counts=True)
        out[k] = uniq[counts.argmax()]
    return out


def _gyro_sign(gyro: np.ndarray, icp: np.ndarray, declared: int | None, path: Path, declared_by: str) -> dict:
    """The sign that makes the gyro agree with the ICP yaw rate, from the correlation of the steps' steady means."""
    ok = np.isfinite(icp)
    turning = int((np.abs(icp[ok]) > SIGN_TURN).sum())
    corr = (
        float(np.corrcoef(gyro[ok], icp[ok])[0, 1])
        if ok.sum() >= 3 and np.ptp(gyro[ok]) > 0 and np.ptp(icp[ok]) > 0
        else float("nan")
    )
    basis = (
        f"correlation of the steps' steady gyro means with the ICP yaw rate {corr:+.4f} over {int(ok.sum())} "
        f"steps, {turning} turning faster than {SIGN_TURN} rad/s"
    )
    decided = turning >= MIN_SIGN_STEPS and abs(corr) >= MIN_SIGN_CORRELATION
    if declared is not None:
        if declared not in (1, -1):
            raise InputError(f"gyro_sign ({declared_by})", f"{declared!r} must be +1 or -1")
        if decided and int(np.sign(corr)) != declared:
            raise InputError(
                f"{path}: column 'imu_yaw_*'",
                f"gyro sign {declared:+d} declared by {declared_by}, "
                f"but the data say {int(np.sign(corr)):+d} ({basis})",
                "remove the declared gyro_sign (the reader fixes it from the data)",
            )
        return {"sign": declared, "by": f"declared by {declared_by}", "basis": basis, "correlation": corr}
    if not decided:
        raise InputError(
            f"{path}: column 'imu_yaw_*'",
            f"the gyro's sign cannot be fixed from the data ({basis}; needed: at least "
            f"{MIN_SIGN_STEPS} turning steps and |correlation| >= {MIN_SIGN_CORRELATION})",
            f"declare gyro_sign (+1 or -1) for this session ({declared_by})",
        )
    return {"sign": int(np.sign(corr)), "by": "the ICP yaw rate", "basis": basis, "correlation": corr}


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
