"""Reading one input file as the report expects it: a path that must exist, a CSV read with its
text and bool columns typed and its required columns checked, the lab detail table's views, and a
figure file's key in the report.

These are the checks every input goes through, whichever rule wrote it."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pandas as pd

from simpick.errors import InputError
from simpick.report.load.columns import (
    BOOL_COLUMNS,
    COLUMNS,
    TEXT_COLUMNS,
)


def _path(name: str, value: Any) -> Path:
    if isinstance(value, (list, tuple)):
        if len(value) != 1:
            raise InputError(f"report input {name!r}", f"expected one path, got {len(value)}")
        value = value[0]
    p = Path(str(value))
    if not p.is_file():
        raise InputError(str(p), f"report input {name!r} does not exist", "run the rule that writes it first")
    return p


def _paths(name: str, value: Any) -> list[Path]:
    values = [value] if isinstance(value, (str, Path)) else list(value)
    out = []
    for v in values:
        p = Path(str(v))
        if not p.is_file():
            raise InputError(str(p), f"report input {name!r} does not exist", "run the rule that writes it first")
        out.append(p)
    return out


def _csv(name: str, path: Path, index: str | None = None) -> pd.DataFrame:
    try:
        head = pd.read_csv(path, nrows=0)
    except (pd.errors.EmptyDataError, pd.errors.ParserError, UnicodeDecodeError) as exc:
        raise InputError(str(path), f"not a readable CSV: {exc}") from None
    bools = {c for c in head.columns if c in BOOL_COLUMNS.get(name, ()) or c.endswith("_closest")}
    dtypes = {c: "string" for c in head.columns if (c in TEXT_COLUMNS or c.endswith("_outcome")) and c not in bools}
    df = pd.read_csv(path, dtype=dtypes, keep_default_na=True)
    for c in dtypes:
        df[c] = df[c].fillna("").astype(str)
    for c in bools:
        df[c] = df[c].astype(str).str.strip().str.lower().isin(["true", "1", "1.0"])
    have = set(df.columns)
    missing = [c for c in COLUMNS.get(name, ()) if c not in have]
    if missing:
        raise InputError(str(path), f"columns {missing} are missing", "rerun the rule that writes it")
    if index is not None:
        if index not in df.columns:
            # The index column may have been written without a name.
            first = df.columns[0]
            if first.startswith("Unnamed"):
                df = df.rename(columns={first: index})
            else:
                raise InputError(str(path), f"index column {index!r} is missing")
        df[index] = df[index].astype(str)
        df = df.set_index(index)
    return df


# The lab's per-axis table (results/metrics/lab/detail.csv: simpick.sources.lab) holds the
# simulated statistics, the paper's and the errors between them; the report reads three views of it.
DETAIL_VIEWS = {
    "trace_stats": lambda d: d[["engine", "terrain", "motion", "quantity", "axis", "mean", "range", "status"]],
    "reference_stats": lambda d: (
        d[d["ref_mean"].notna()]
        .drop_duplicates(["terrain", "motion", "quantity", "axis"])[
            ["terrain", "motion", "quantity", "axis", "ref_mean", "ref_range", "source"]
        ]
        .rename(columns={"ref_mean": "mean", "ref_range": "range"})
        .reset_index(drop=True)
    ),
    "per_test_errors": lambda d: d[d["total_error"].notna()][
        ["engine", "terrain", "motion", "quantity", "axis", "range_error", "mean_error", "total_error"]
    ].reset_index(drop=True),
}


def figure_key(path: str | Path) -> str:
    """A figure file's name in the report: its path under the last ``figures`` folder, no suffix
    (results/report/figures/traces/grass/straight.png -> traces/grass/straight)."""
    parts = Path(path).with_suffix("").parts
    if "figures" not in parts:
        return Path(path).stem
    i = len(parts) - 1 - parts[::-1].index("figures")
    return "/".join(parts[i + 1 :])
