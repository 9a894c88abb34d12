"""A short fingerprint of the library code a rule runs, for its params.

Snakemake reruns a job when its params change, but it does not look into imported library
code: an edited metric under src/simpick would silently keep serving results computed by the
old code. Each rule therefore carries, as a param, the hash of the source files it depends on
(``rules/common.smk: code_version``), so editing one reruns exactly the jobs that use it.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

ROOT = Path(__file__).resolve().parent


def code_version(*names: str, root: Path | str = ROOT) -> str:
    """sha256 (16 hex digits) over the named files or folders under ``root`` (``.py`` and
    templates, sorted by path); a name that does not exist is an error, so a renamed
    module cannot silently drop out of the fingerprint."""
    root = Path(root)
    digest = hashlib.sha256()
    files = set()
    for name in names:
        path = root / name
        if path.is_dir():
            files.update(p for p in path.rglob("*") if p.is_file() and p.suffix in (".py", ".j2", ".css"))
        elif path.is_file():
            files.add(path)
        else:
            raise FileNotFoundError(f"code_version: {path} does not exist")
    for path in sorted(files):
        digest.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()[:16]
