"""What the DRIVE sessions say about the real robot, and the cases they give an engine to replay.

DRIVE commands each wheel pair at random constant speeds for one step and measures the result
(:mod:`simpick.real.logs.drive`), so its steps sample the whole command space (BorealTC's runs hold
a few commands each). Per step, over its steady part:

* the yaw-rate gain: the gyro yaw rate (sign fixed per file) over the kinematic yaw rate of the
  measured wheels, ``w_kin = r (w_R - w_L) / B``, counted where ``|w_kin| > MIN_TURN``; the same with
  the ICP yaw rate (``gain_icp``) checks the gyro against the lidar;
* the forward-speed ratio: the lidar-ICP forward speed over the kinematic one
  ``v_kin = r (w_L + w_R) / 2``, counted where ``|v_kin| > MIN_SPEED``.

Repeatability: the real robot's gain differs between steps of the same command. DRIVE draws its
commands at random, so no command repeats exactly; two turning steps are *similar* when both
wheels' commanded speeds differ by at most ``tolerance`` (default :data:`SIMILAR`, 1 rad/s = 0.3 m/s
at the Warthog's rim, under 4 % of its command range). Over all similar pairs of a group, the spread
is the median |gain_i - gain_j| and the single-step standard deviation sqrt(mean((gain_i - gain_j)^2) / 2)
(a pair's difference has twice one step's variance). It is the floor no model can beat.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from simpick.errors import InputError
from simpick.real.datasets import DatasetProblems
from simpick.real.logs.drive import read_drive
from simpick.real.steps import (  # noqa: F401 - the step units' figures, shared with any reader of steps
    BINS,
    MIN_SPEED,
    MIN_TURN,
    SIMILAR,
    gain_against_command,
    gain_bins,
    pair_sd,
    repeatability,
    similar_pairs,
    write_wheels,
)
from simpick.tables import write_csv

SPIN_SPEED = 0.05  # m/s: below this commanded forward speed a turn is a spin on the spot (turn radius 0)

STEP_COLUMNS = [
    "dataset",
    "session",
    "terrain_class",
    "gyro_sign",
    "step",
    "cmd_left",
    "cmd_right",
    "v_cmd",
    "w_cmd",
    "cmd_turn_radius",
    "cmd_wheel_speed_difference",
    "wheel_left",
    "wheel_right",
    "v_kin",
    "w_kin",
    "yaw_rate",
    "yaw_rate_icp",
    "turning",
    "gain",
    "gain_icp",
    "v_icp",
    "icp_reversed",
    "v_icp_drive",
    "speed_ratio",
    "speed_ratio_drive",
]
TABLE_COLUMNS = [
    "terrain_class",
    "session",
    "steps",
    "gyro_sign",
    "turning_steps",
    "gain_median",
    "gain_q25",
    "gain_q75",
    "gain_icp_median",
    "similar_pairs",
    "repeat_median_abs_diff",
    "repeat_sd",
    "rho_speed",
    "p_speed",
    "rho_radius",
    "p_radius",
    "rho_difference",
    "p_difference",
    "speed_steps",
    "speed_ratio_median",
    "speed_ratio_q25",
    "speed_ratio_q75",
    "speed_ratio_drive_median",
    "icp_reversed_steps",
]
CASE_COLUMNS = [
    "case",
    "dataset",
    "session",
    "terrain_class",
    "step",
    "start_from",
    "start_vx",
    "start_vy",
    "start_wz",
    "start_wheel_left",
    "start_wheel_right",
    "cmd_left",
    "cmd_right",
    "steady_start",
    "steady_end",
    "wheel_left",
    "wheel_right",
    "yaw_rate",
    "yaw_rate_icp",
    "v_icp",
    "heading_icp",
    "heading_gyro",
    "gain",
    "source_sha1",
]


def _sessions(data):
    return data.sessions if hasattr(data, "sessions") else tuple(data)


def step_table(data, *, min_turn: float = MIN_TURN, min_speed: float = MIN_SPEED) -> pd.DataFrame:
    """One row per step of every session (a :class:`~simpick.real.logs.drive.DriveDataset` or sessions):
    the command (wheel angular speeds, rad/s, and the body twist they ask for), the measured wheels'
    kinematic twist, the gyro and ICP yaw rates, the ICP forward speed, the gain and the speed ratio."""
    frames = []
    for s in _sessions(data):
        g = s.meta["geometry"]
        r, b = g["wheel_radius"], g["wheel_baseline"]
        st = s.steps
        v_cmd, w_cmd = r * (st.cmd_left + st.cmd_right) / 2, r * (st.cmd_right - st.cmd_left) / b
        v_kin, w_kin = r * (st.wheel_left + st.wheel_right) / 2, r * (st.wheel_right - st.wheel_left) / b
        turning = w_kin.abs() > min_turn
        moving = v_kin.abs() > min_speed
        with np.errstate(divide="ignore", invalid="ignore"):
            radius = np.where(v_cmd.abs() < SPIN_SPEED, 0.0, (v_cmd / w_cmd).abs())
        frames.append(
            pd.DataFrame(
                {
                    "dataset": s.meta["dataset"],
                    "session": s.name,
                    "terrain_class": s.terrain_class,
                    "gyro_sign": s.meta["gyro"]["sign"],
                    "step": st.step,
                    "cmd_left": st.cmd_left,
                    "cmd_right": st.cmd_right,
                    "v_cmd": v_cmd,
                    "w_cmd": w_cmd,
                    "cmd_turn_radius": radius,
                    "cmd_wheel_speed_difference": r * (st.cmd_right - st.cmd_left),
                    "wheel_left": st.wheel_left,
                    "wheel_right": st.wheel_right,
                    "v_kin": v_kin,
                    "w_kin": w_kin,
                    "yaw_rate": st.wz_gyro,
                    "yaw_rate_icp": st.wz_icp,
                    "turning": turning,
                    "gain": (st.wz_gyro / w_kin).where(turning),
                    "gain_icp": (st.wz_icp / w_kin).where(turning),
                    "v_icp": st.vx_icp,
                    "icp_reversed": st.icp_reversed,
                    "v_icp_drive": st.vx_icp_drive,
                    "speed_ratio": (st.vx_icp / v_kin).where(moving),
                    "speed_ratio_drive": (st.vx_icp_drive / v_kin).where(moving),
                },
                columns=STEP_COLUMNS,
            )
        )
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame(columns=STEP_COLUMNS)


def _spearman(x, y) -> tuple[float, float]:
    from scipy.stats import spearmanr

    x, y = np.asarray(x, float), np.asarray(y, float)
    if len(x) < 4 or np.ptp(x) <= 1e-9 or np.ptp(y) <= 1e-9:  # a constant has no rank to correlate
        return math.nan, math.nan
    result = spearmanr(x, y)
    return float(result.statistic), float(result.pvalue)


def _summary(g: pd.DataFrame, tolerance: float) -> dict:
    t = g[g.turning & g.gain.notna()]
    m = g[g.speed_ratio.notna()]
    row = {
        "steps": len(g),
        "turning_steps": len(t),
        "gain_median": t.gain.median(),
        "gain_q25": t.gain.quantile(0.25),
        "gain_q75": t.gain.quantile(0.75),
        "gain_icp_median": t.gain_icp.median(),
        **repeatability(g, tolerance),
        "speed_steps": len(m),
        "speed_ratio_median": m.speed_ratio.median(),
        "speed_ratio_q25": m.speed_ratio.quantile(0.25),
        "speed_ratio_q75": m.speed_ratio.quantile(0.75),
        "speed_ratio_drive_median": m.speed_ratio_drive.median(),
        "icp_reversed_steps": int((g.icp_reversed > 0).sum()),
    }
    for name, column in (
        ("speed", t.v_cmd.abs()),
        ("radius", t.cmd_turn_radius),
        ("difference", t.cmd_wheel_speed_difference.abs()),
    ):
        row[f"rho_{name}"], row[f"p_{name}"] = _spearman(column, t.gain)
    return row


def turning_table(steps: pd.DataFrame, tolerance: float = SIMILAR) -> pd.DataFrame:
    """Per terrain and session, then per terrain over its sessions (session "all"): the gain's median
    and quartiles (gyro; and with the ICP yaw rate), its repeatability between similar commands, Spearman's
    rank correlation (rho, p) of the gain with the commanded |speed|, turn radius and |wheel-speed
    difference|, the ICP forward speed over the kinematic one (ours; and DRIVE's smoothed one), and how many
    steps had an ICP window moving against the wheels (left out of the ICP speed: the reader's quirks).
    Similar pairs are sought within a session (per-session rows) or within a terrain (pooled rows)."""
    rows = []
    for terrain, by_terrain in steps.groupby("terrain_class", sort=True):
        for session, g in by_terrain.groupby("session", sort=True):
            rows.append(
                {
                    "terrain_class": terrain,
                    "session": session,
                    "gyro_sign": int(g.gyro_sign.iloc[0]),
                    **_summary(g, tolerance),
                }
            )
        rows.append({"terrain_class": terrain, "session": "all", "gyro_sign": None, **_summary(by_terrain, tolerance)})
    return pd.DataFrame(rows, columns=TABLE_COLUMNS)


def replay_cases(data, *, min_turn: float = MIN_TURN) -> pd.DataFrame:
    """One replay case per step of every session: where it starts (the previous step's end: ICP body
    velocity over that step's last steady window, gyro yaw rate and wheel speeds over its last 0.5 s; step 0
    from its own start), what the wheels were told and did (command and steady measured wheel speeds, rad/s;
    the engines replay the measured wheel speeds, :meth:`DriveSession.wheel_commands`), the steady window
    compared (s from the step's start), and the real values an engine is compared with over it."""
    frames = []
    for s in _sessions(data):
        st = s.steps
        g = s.meta["geometry"]
        w_kin = g["wheel_radius"] * (st.wheel_right - st.wheel_left) / g["wheel_baseline"]
        frames.append(
            pd.DataFrame(
                {
                    "case": [f"{s.name}/{k:03d}" for k in st.step],
                    "dataset": s.meta["dataset"],
                    "session": s.name,
                    "terrain_class": s.terrain_class,
                    "step": st.step,
                    "start_from": st.start_from,
                    "start_vx": st.start_vx,
                    "start_vy": st.start_vy,
                    "start_wz": st.start_wz,
                    "start_wheel_left": st.start_wheel_left,
                    "start_wheel_right": st.start_wheel_right,
                    "cmd_left": st.cmd_left,
                    "cmd_right": st.cmd_right,
                    "steady_start": st.steady_start,
                    "steady_end": st.t_end,
                    "wheel_left": st.wheel_left,
                    "wheel_right": st.wheel_right,
                    "yaw_rate": st.wz_gyro,
                    "yaw_rate_icp": st.wz_icp,
                    "v_icp": st.vx_icp,
                    "heading_icp": st.heading_icp,
                    "heading_gyro": st.heading_gyro,
                    "gain": (st.wz_gyro / w_kin).where(w_kin.abs() > min_turn),
                    "source_sha1": s.meta["source"]["git_blob_sha1"],
                },
                columns=CASE_COLUMNS,
            )
        )
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame(columns=CASE_COLUMNS)


def open_drive(folder, *, declared=None, classes=None, name: str = "drive"):
    """The DRIVE dataset behind a folder the user named, read with the config's declaration of it
    (``real_data.datasets.<name>``: its per-session overrides) and checked against the config's terrain
    classes (``real_data.classes``; None: not checked). Every session whose terrain has no ground model is
    one problem; they are raised together (:class:`~simpick.real.datasets.DatasetProblems`)."""
    declared = dict(declared or {})
    kind = declared.get("kind", "drive")
    if kind != "drive":
        raise InputError(
            f"real_data.datasets.{name}.kind",
            f"is {kind!r}, not 'drive'",
            f"set kind: drive for the DRIVE folder {folder}",
        )
    overrides = {k: dict(v or {}) for k, v in (declared.get("sessions") or {}).items()}
    dataset = read_drive(folder, sessions=overrides, declared_by=f"real_data.datasets.{name}.sessions in the config")
    if classes is not None:
        problems = [
            unmodelled_terrain(str(s.folder), s.terrain_class, s.meta["terrain_source"], s.name, name)
            for s in dataset.sessions
            if s.terrain_class not in classes
        ]
        if problems:
            raise DatasetProblems(problems)
    return dataset


def unmodelled_terrain(where: str, terrain: str, source: str, session: str, name: str = "drive") -> InputError:
    """The problem of a DRIVE session whose terrain class has no ground model in ``real_data.classes``:
    ``where`` the file (and field) it comes from, ``source`` where the class was read or declared."""
    return InputError(
        where,
        f"terrain class {terrain!r} ({source}) has no ground model",
        f"add it under real_data.classes, e.g. real_data: {{classes: "
        f'{{{terrain}: {{friction: 0.6, source: "where 0.6 comes from"}}}}}}, or '
        f"declare the session's terrain_class under real_data.datasets.{name}.sessions.{session}",
    )


SESSION_COLUMNS = [
    "session",
    "kept",
    "same_as",
    "robot",
    "terrain_class",
    "terrain_source",
    "metadata_terrain",
    "folder_names_terrain",
    "only_execute_trajectories",
    "steps",
    "gyro_sign",
    "gyro_fixed_by",
    "gyro_basis",
    "wheel_radius",
    "wheel_baseline",
    "geometry_source",
    "git_blob_sha1",
    "content_sha256",
    "quirks",
]


def session_table(dataset) -> pd.DataFrame:
    """One row per session folder read: what was kept, where its terrain, gyro sign and geometry come from,
    its file's identity and its quirks; a duplicate's row names the session kept in its place."""
    rows = []
    for s in dataset.sessions:
        m = s.meta
        rows.append(
            {
                "session": s.name,
                "kept": True,
                "same_as": "",
                "robot": m.get("robot"),
                "terrain_class": s.terrain_class,
                "terrain_source": m["terrain_source"],
                "metadata_terrain": m.get("metadata_terrain"),
                "folder_names_terrain": m["folder_names_terrain"],
                "only_execute_trajectories": m["only_execute_trajectories"],
                "steps": m["steps"],
                "gyro_sign": m["gyro"]["sign"],
                "gyro_fixed_by": m["gyro"]["by"],
                "gyro_basis": m["gyro"]["basis"],
                "wheel_radius": m["geometry"]["wheel_radius"],
                "wheel_baseline": m["geometry"]["wheel_baseline"],
                "geometry_source": m["geometry"]["source"],
                "git_blob_sha1": m["source"]["git_blob_sha1"],
                "content_sha256": m["source"]["content_sha256"],
                "quirks": "; ".join(m["quirks"]),
            }
        )
    for d in dataset.duplicates:
        rows.append(
            {
                "session": d["session"],
                "kept": False,
                "same_as": d["same_as"],
                "terrain_class": d["terrain"],
                "content_sha256": d["content_sha256"],
                "quirks": "same arrays as "
                + d["same_as"]
                + ("" if d["labels_agree"] else f" (labelled {d['kept_terrain']} there)"),
            }
        )
    return pd.DataFrame(rows, columns=SESSION_COLUMNS)


def wheel_table(session) -> pd.DataFrame:
    """A session's measured wheel speeds over every step as the wheels table (simpick.real.steps.WHEEL_COLUMNS):
    rim speeds, what :meth:`~simpick.real.logs.drive.DriveSession.wheel_commands` gives per step."""
    r = session.meta["geometry"]["wheel_radius"]
    s = session.samples
    return pd.DataFrame(
        {
            "session": session.name,
            "step": s.step.to_numpy(),
            "time": s.t_step.to_numpy(),
            "v_left": r * s.wheel_left.to_numpy(),
            "v_right": r * s.wheel_right.to_numpy(),
            "wheel_radius": float(r),
        }
    )


def write_tables(dataset, outputs: dict[str, str], *, tolerance: float = SIMILAR) -> None:
    """The DRIVE tables of a dataset read by :func:`open_drive`, to the paths the caller names (keys
    ``sessions``, ``steps``, ``turning``, ``bins``, ``cases``, as CSV, and ``wheels``, the wheels table the
    replay drives, as Parquet; a key left out is not written)."""
    steps = step_table(dataset)
    tables = {
        "sessions": lambda: session_table(dataset),
        "steps": lambda: steps,
        "turning": lambda: turning_table(steps, tolerance),
        "bins": lambda: gain_against_command(steps),
        "cases": lambda: replay_cases(dataset),
    }
    unknown = sorted(set(outputs) - set(tables) - {"wheels"})
    if unknown:
        raise ValueError(f"unknown DRIVE table(s) {unknown}; known: {sorted(tables) + ['wheels']}")
    for key, path in outputs.items():
        if key == "wheels":
            write_wheels([wheel_table(s) for s in _sessions(dataset)], path)
        else:
            write_csv(tables[key](), path)


def tables_job(folder: str, declared: dict, name: str, outputs: dict[str, str]) -> None:
    """Rule drive_tables: the DRIVE folder the user named, read with its declaration, into its four tables."""
    write_tables(open_drive(folder, declared=declared, name=name), outputs)
