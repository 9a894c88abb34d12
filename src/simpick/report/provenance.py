"""Where the report was built: package versions and the machine."""

from __future__ import annotations

import os
import platform
import sys
from importlib import metadata
from pathlib import Path

PACKAGES = (
    "simpick",
    "numpy",
    "pandas",
    "pyarrow",
    "mujoco",
    "pybullet",
    "snakemake",
    "matplotlib",
    "jinja2",
    "weasyprint",
    "pyyaml",
    "psutil",
)


def package_versions(packages=PACKAGES) -> list[tuple[str, str]]:
    """(name, version) for Python and each installed package; missing ones are skipped."""
    out = [("python", platform.python_version())]
    for name in packages:
        try:
            out.append((name, metadata.version(name)))
        except metadata.PackageNotFoundError:
            continue
    return out


def cpu_model() -> str | None:
    path = Path("/proc/cpuinfo")
    try:
        for line in path.read_text(encoding="utf-8", errors="replace").splitlines():
            if line.lower().startswith(("model name", "hardware", "processor\t: arm")):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or None


def machine() -> list[tuple[str, str]]:
    rows = [
        ("platform", platform.platform()),
        ("machine", platform.machine()),
        ("python executable", sys.executable),
    ]
    model = cpu_model()
    if model:
        rows.append(("CPU model", model))
    logical = os.cpu_count()
    try:
        import psutil

        physical = psutil.cpu_count(logical=False)
        cores = f"{physical} physical, {logical} logical" if physical else f"{logical} logical"
        rows.append(("CPU cores", cores))
        rows.append(("memory", f"{psutil.virtual_memory().total / 2**30:.1f} GiB"))
    except ImportError:
        rows.append(("CPU cores", f"{logical} logical"))
    return rows
