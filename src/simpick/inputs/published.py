"""The paper's published figures (Farley, Wang & Marshall 2022): ``resources/published/farley2022.yaml``,
read and checked to cover every simulator. Recomputing them is the score stage's
(:mod:`simpick.score.published`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

DEFAULT_PATH = Path(__file__).resolve().parents[3] / "resources" / "published" / "farley2022.yaml"

TOP_LEVEL_KEYS = ("simulators", "table3", "table4", "table10", "table11", "worked_example")


def load_published(path: str | Path = DEFAULT_PATH) -> dict[str, Any]:
    """Read the published-figures YAML and check that its blocks cover every simulator."""
    with open(path, encoding="utf-8") as fh:
        data = yaml.load(fh, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))  # libyaml: read when a run plans
    if not isinstance(data, dict):
        raise ValueError(f"{path}: expected a mapping at the top level")
    missing = [k for k in TOP_LEVEL_KEYS if k not in data]
    if missing:
        raise ValueError(f"{path}: missing top-level keys {', '.join(missing)}")
    sims = data["simulators"]
    blocks = {
        "table3.facts": data["table3"]["facts"],
        "table4.scores": data["table4"]["scores"],
        "table11.scores": data["table11"]["scores"],
        "table11.totals": data["table11"]["totals"],
    }
    for name, block in blocks.items():
        absent = [s for s in sims if s not in block]
        if absent:
            raise ValueError(f"{path}: {name} lacks {', '.join(absent)}")
    return data
