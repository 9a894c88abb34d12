"""The inputs stage's job: a terrain strip generated from its rule and seed."""

from __future__ import annotations

from pathlib import Path

from simpick.inputs import terrain
from simpick.seeds import stable_seed


def terrain_job(output: str, name: str, seed: int, spec: dict) -> None:
    spec = dict(spec)
    rule, friction = spec.pop("rule"), spec.pop("friction")
    tiles = int(spec.pop("tiles", terrain.TILES))
    desc = terrain.generate(name, rule, stable_seed(int(seed), "terrain", name), friction, tiles, **spec)
    Path(output).parent.mkdir(parents=True, exist_ok=True)
    terrain.save(desc, output)
