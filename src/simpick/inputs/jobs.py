"""The inputs stage's jobs: a terrain strip generated from its rule and seed, and the paper's
published tables recomputed (Table 11).
"""

from __future__ import annotations

from pathlib import Path


def terrain_job(output: str, name: str, seed: int, spec: dict) -> None:
    from simpick.inputs import terrain
    from simpick.seeds import stable_seed

    spec = dict(spec)
    rule, friction = spec.pop("rule"), spec.pop("friction")
    tiles = int(spec.pop("tiles", terrain.TILES))
    desc = terrain.generate(name, rule, stable_seed(int(seed), "terrain", name), friction, tiles, **spec)
    Path(output).parent.mkdir(parents=True, exist_ok=True)
    terrain.save(desc, output)


def published_job(published_file: str, outdir: str) -> None:
    from simpick.inputs.published import load_published, write_outputs

    write_outputs(load_published(published_file), outdir)
