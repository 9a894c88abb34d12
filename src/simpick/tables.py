"""How a table is written: CSV at full precision (``%.17g``: a float read back is the float written,
so no reader needs a tolerance for rounding). Shared by the job modules of every stage.
"""

from __future__ import annotations

from pathlib import Path


def write_csv(frame, path: str | Path, index: bool = False) -> None:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    frame.to_csv(path, index=index, float_format="%.17g")
