"""DRIVE's files on disk (:mod:`simpick.real.logs.drive` reads what they hold): finding the session
folders, the dataset pickle unpickled only after its bytes look like one and identified as git does,
the session's metadata.yaml, and the wheel geometry from its DRIVE configuration."""

from __future__ import annotations

import hashlib
import io
import pickle
import warnings
from pathlib import Path

import pandas as pd
import yaml

from simpick.errors import InputError
from simpick.real.datasets import DatasetProblems

PICKLE = Path("model_training_datasets") / "slip_dataset_all.pkl"
METADATA = "metadata.yaml"


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


def unrecognised(folder: str | Path) -> list[tuple[Path, str]]:
    """(sub-folder, why) of every folder under ``folder`` that :func:`find_sessions` does not take for a
    session, so that planning names it rather than leaving it out in silence; [] where ``folder`` is one
    session itself."""
    folder = Path(folder)
    if not folder.is_dir() or (folder / METADATA).is_file() or (folder / PICKLE).is_file():
        return []
    if (folder / "calib_data").is_dir():
        folder = folder / "calib_data"
    found = []
    for p in sorted(p for p in folder.iterdir() if p.is_dir()):
        if p.name.startswith((".", "_")):
            found.append((p, "a hidden folder (its name starts with '.' or '_')"))
        elif not (p / METADATA).exists() and not (p / PICKLE).exists():
            found.append((p, f"holds neither {METADATA} nor {PICKLE}, so it is no DRIVE session"))
    return found


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
            # a ROS node's parameters in DRIVE's own file (its keys are DRIVE's: data, not a job's params)
            ros = node.get("ros__parameters") if isinstance(node, dict) else None
            if isinstance(ros, dict) and "wheel_radius" in ros and "wheel_baseline" in ros:
                found = {
                    "wheel_radius": float(ros["wheel_radius"]),
                    "wheel_baseline": float(ros["wheel_baseline"]),
                    "step_len": float(ros["step_len"]) if "step_len" in ros else None,
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
