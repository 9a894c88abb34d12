"""Seeds and fingerprints derived from names and parameters: identical across runs and processes.

A module of its own (plain hashing, no numpy) so that a job that only needs a seed, such as the
terrain job, does not import the simulation stack (simpick.simulate.run re-exports both).
"""

from __future__ import annotations

import hashlib
import json


def stable_seed(*parts: object) -> int:
    """A seed derived from names, identical across runs and Python processes."""
    digest = hashlib.sha256(json.dumps(parts, sort_keys=True, default=str).encode()).digest()
    return int.from_bytes(digest[:4], "little")


def config_hash(params: dict) -> str:
    return hashlib.sha256(json.dumps(params, sort_keys=True).encode()).hexdigest()[:16]
