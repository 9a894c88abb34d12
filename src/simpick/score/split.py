"""The calibration's split of the real runs as the judging reads it: which runs trained a fit, which are held
out. A module of its own so that the calibration jobs, which read it, depend on nothing else of the scoring."""

from __future__ import annotations

from pathlib import Path

import pandas as pd


def read_split(path: str | Path) -> tuple[list[str], list[str]]:
    """(training runs, test runs), each ``class/run``."""
    split = pd.read_csv(path, dtype={"run": str, "unit": str})
    key = split.terrain_class.astype(str) + "/" + split.run.astype(str)
    train = sorted(set(key[split.set == "train"]))
    test = sorted(set(key[split.set == "test"]))
    both = sorted(set(train) & set(test))
    if both:
        raise ValueError(f"{path}: runs on both sides of the split: {both}")
    return train, test
