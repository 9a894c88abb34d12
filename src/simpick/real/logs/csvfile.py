"""Load a CSV file so that every way it can be broken becomes an InputError naming it.

Rows keep their place (blank lines are not skipped, only trailing ones are dropped), so
data row i is file line i + 2 and errors can name the line. Header names are stripped of
surrounding spaces; duplicated header names are an error rather than pandas' silent
``name.1`` renaming; a row with more fields than the header is an error naming its line.
"""

from __future__ import annotations

import csv
import hashlib
import io
import warnings
from pathlib import Path

import pandas as pd

from simpick.errors import InputError


def file_info(path: Path) -> dict:
    data = path.read_bytes()
    return {"path": str(path.resolve()), "bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()}


def check_file(path: str | Path, what: str = "file") -> Path:
    path = Path(path)
    if not path.exists():
        raise InputError(str(path), f"{what} not found", "check the path")
    if not path.is_file():
        raise InputError(str(path), f"{what} is not a regular file")
    if path.stat().st_size == 0:
        raise InputError(str(path), f"{what} is empty (0 bytes)")
    return path


def load_csv(path: str | Path) -> pd.DataFrame:
    """The CSV as read by pandas (types inferred), or an InputError naming the file."""
    path = check_file(path, "CSV file")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(str(path), f"not UTF-8 text (byte {exc.start})", "save the file as UTF-8 CSV") from None
    except OSError as exc:
        raise InputError(str(path), f"cannot be read: {exc.strerror or exc}") from None
    if not text.strip():
        raise InputError(str(path), "file is empty (only blank space)")
    if "\x00" in text:
        raise InputError(str(path), "contains NUL bytes: not a text CSV")

    first = text.splitlines()[0]
    if not first.strip():
        raise InputError(str(path), "line 1 is blank; the header must be on line 1", "remove the leading blank lines")
    try:
        header = next(csv.reader(io.StringIO(first)))
    except (csv.Error, StopIteration) as exc:
        raise InputError(str(path), f"unreadable header line: {exc}") from None
    names = [h.strip() for h in header]
    seen: set[str] = set()
    for name in names:
        if name in seen:
            raise InputError(
                f"{path}: column {name!r}", "appears twice in the header", "give every column a unique name"
            )
        seen.add(name)

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", pd.errors.ParserWarning)
            warnings.simplefilter("ignore", pd.errors.DtypeWarning)
            frame = pd.read_csv(io.StringIO(text), index_col=False, skip_blank_lines=False, low_memory=False)
    except pd.errors.EmptyDataError:
        raise InputError(str(path), "file has no header and no data") from None
    except pd.errors.ParserWarning:
        line, count = _first_long_row(text, len(names))
        raise InputError(
            str(path),
            f"not a well-formed CSV: line {line} has {count} fields but the header has {len(names)}",
            "every row needs as many comma-separated fields as the header",
        ) from None
    except pd.errors.ParserError as exc:
        detail = str(exc).replace("Error tokenizing data. C error: ", "").strip()
        raise InputError(
            str(path),
            f"not a well-formed CSV: {detail or 'a row has more fields than the header'}",
            "every row needs as many comma-separated fields as the header",
        ) from None
    except (ValueError, TypeError, OverflowError, csv.Error) as exc:
        raise InputError(str(path), f"not a readable CSV: {exc}") from None

    frame.columns = [str(c).strip() for c in frame.columns]
    # drop trailing blank lines (all cells empty) but keep inner ones so rows map to lines
    empty = frame.isna().all(axis=1).to_numpy()
    end = len(frame)
    while end and empty[end - 1]:
        end -= 1
    frame = frame.iloc[:end].reset_index(drop=True)
    if frame.empty:
        raise InputError(str(path), "has a header but no data rows")
    return frame


def _first_long_row(text: str, width: int) -> tuple[int, int]:
    """(line number, field count) of the first row with more fields than the header."""
    for number, row in enumerate(csv.reader(io.StringIO(text)), start=1):
        if len(row) > width:
            return number, len(row)
    return 0, 0
