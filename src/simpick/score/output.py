"""How the score stage writes its tables: full precision, so that a float read back is the float
written and a reader (the report, the decision tree) computes nothing again."""

from __future__ import annotations

from pathlib import Path

FULL_PRECISION = "%.17g"


def write_csv(frame, path: str | Path, index: bool = False) -> None:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    frame.to_csv(path, index=index, float_format=FULL_PRECISION)
