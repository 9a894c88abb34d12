"""Engine-neutral terrain: a seeded list of primitive shapes with one friction coefficient.

A terrain file is plain JSON so every engine adapter reads exactly the same geometry:
boxes (centre, yaw, full size) and spheres (centre, radius), all resting on a flat
ground plane at z = 0. Primitives, not height grids: a 1 cm grid of the gravel strip
steps 20-100x slower than the same strip as primitives (METHOD.md section 2).

The strip is ``tiles`` 1 m x 1 m tiles in a row along +x starting at x = 0, centred on y = 0,
like the paper's lab set-up (Farley et al. 2022, section 3.1.1).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np

from simpick.errors import InputError

SCHEMA = "simpick.inputs.terrain/1"
TILE = 1.0  # m
TILES = 4  # a strip of four 1 m x 1 m tiles (paper s3.1.1): the terrains' default length


class Box(NamedTuple):
    """A static box: centre (m), yaw about z (rad), full size (m)."""

    x: float
    y: float
    z: float
    yaw: float
    size_x: float
    size_y: float
    size_z: float


class Sphere(NamedTuple):
    """A static sphere: centre and radius, m."""

    x: float
    y: float
    z: float
    radius: float


@dataclass(frozen=True)
class Terrain:
    """The terrain an engine builds: static shapes on the ground plane z = 0, all with one friction
    coefficient (the plane's own is ``Scenario.ground_friction``). :meth:`of` reads a terrain file's
    dict (:func:`load`, :func:`generate`); the shapes are typed rows, so an adapter unpacks
    ``for x, y, z, yaw, sx, sy, sz in terrain.boxes``."""

    friction: float
    boxes: tuple[Box, ...] = ()
    spheres: tuple[Sphere, ...] = ()
    name: str = "flat"
    seed: int | None = None  # the seed the shapes were drawn with (None: no random layout)

    @classmethod
    def of(cls, value: Terrain | Mapping) -> Terrain:
        """``value`` itself, or the Terrain of a terrain file's dict (its schema keys ignored)."""
        if isinstance(value, Terrain):
            return value
        return cls(
            friction=float(value["friction"]),
            boxes=tuple(Box(*(float(v) for v in row)) for row in value.get("boxes", ())),
            spheres=tuple(Sphere(*(float(v) for v in row)) for row in value.get("spheres", ())),
            name=str(value.get("name", "flat")),
            seed=value.get("seed"),
        )

    @classmethod
    def flat(cls, friction: float, name: str = "flat") -> Terrain:
        """No shapes: the robot drives on the ground plane alone."""
        return cls(friction=float(friction), name=name)


def _tile_centres(tiles: int) -> list[float]:
    return [TILE * (i + 0.5) for i in range(tiles)]


def _box(x, y, z, yaw, sx, sy, sz) -> list[float]:
    return [round(float(v), 6) for v in (x, y, z, yaw, sx, sy, sz)]


def flat_tiles(rng: np.random.Generator, tiles: int, thickness: float) -> dict:
    """Artificial turf: flat tiles of the given thickness."""
    boxes = [_box(cx, 0.0, thickness / 2, 0.0, TILE, TILE, thickness) for cx in _tile_centres(tiles)]
    return {"boxes": boxes, "spheres": []}


def plywood_layers(
    rng: np.random.Generator,
    tiles: int,
    base: float,
    layer: float,
    pieces_per_tile: int,
    piece_min: float,
    piece_max: float,
) -> dict:
    """Irregular plywood pieces in two layers on a base board (top = base + 2 layers).

    Layer-one pieces lie anywhere on a tile; each layer-two piece sits on a layer-one piece,
    smaller than it, so the top layer never floats.
    """
    boxes = [_box(cx, 0.0, base / 2, 0.0, TILE, TILE, base) for cx in _tile_centres(tiles)]
    for cx in _tile_centres(tiles):
        for _ in range(int(pieces_per_tile)):
            sx, sy = rng.uniform(piece_min, piece_max, size=2)
            yaw = rng.uniform(-math.pi, math.pi)
            reach = 0.5 * math.hypot(sx, sy)
            margin = max(0.0, TILE / 2 - reach)
            x = cx + rng.uniform(-margin, margin)
            y = rng.uniform(-margin, margin)
            boxes.append(_box(x, y, base + layer / 2, yaw, sx, sy, layer))
            if rng.random() < 0.5:
                shrink = rng.uniform(0.4, 0.8)
                boxes.append(
                    _box(x, y, base + 1.5 * layer, yaw + rng.uniform(-0.5, 0.5), sx * shrink, sy * shrink, layer)
                )
    return {"boxes": boxes, "spheres": []}


def gravel_bed(
    rng: np.random.Generator,
    tiles: int,
    bed: float,
    stones_per_tile: int,
    radius_min: float,
    radius_max: float,
    max_height: float,
) -> dict:
    """Stones (spheres, partly sunk in a gravel bed) whose tops stay below ``max_height``."""
    boxes = [_box(cx, 0.0, bed / 2, 0.0, TILE, TILE, bed) for cx in _tile_centres(tiles)]
    spheres = []
    stones_per_tile = int(stones_per_tile)
    for cx in _tile_centres(tiles):
        r = rng.uniform(radius_min, radius_max, size=stones_per_tile)
        x = cx + rng.uniform(-TILE / 2, TILE / 2, size=stones_per_tile)
        y = rng.uniform(-TILE / 2, TILE / 2, size=stones_per_tile)
        top = np.minimum(bed + r * rng.uniform(0.6, 1.6, size=stones_per_tile), max_height)
        z = top - r
        spheres += [[round(float(v), 6) for v in row] for row in zip(x, y, z, r)]
    return {"boxes": boxes, "spheres": spheres}


def flat(rng: np.random.Generator, tiles: int) -> dict:
    """Nothing but the ground plane (the real-data terrain classes: friction only)."""
    return {"boxes": [], "spheres": []}


RULES = {"flat": flat, "flat_tiles": flat_tiles, "plywood_layers": plywood_layers, "gravel_bed": gravel_bed}


def generate(name: str, rule: str, seed: int, friction: float, tiles: int = TILES, **params) -> dict:
    """Build one terrain description; the same arguments always give the same description."""
    if rule not in RULES:
        raise InputError(f"terrains.{name}.rule", f"unknown rule {rule!r}", f"use one of {sorted(RULES)}")
    rng = np.random.default_rng(seed)
    try:
        shapes = RULES[rule](rng, tiles=tiles, **params)
    except TypeError as exc:
        raise InputError(f"terrains.{name}", f"parameters do not fit rule {rule!r}: {exc}") from None
    top = max([b[2] + b[6] / 2 for b in shapes["boxes"]] + [s[2] + s[3] for s in shapes["spheres"]] + [0.0])
    return {
        "schema": SCHEMA,
        "name": name,
        "rule": rule,
        "seed": int(seed),
        "params": params,
        "friction": float(friction),
        "tiles": int(tiles),
        "tile_size": TILE,
        "top_height": round(top, 6),
        "boxes_columns": ["x", "y", "z", "yaw", "size_x", "size_y", "size_z"],
        "spheres_columns": ["x", "y", "z", "radius"],
        **shapes,
    }


def save(desc: dict, path: str | Path) -> None:
    Path(path).write_text(json.dumps(desc, indent=1, sort_keys=True))


def load(path: str | Path) -> dict:
    path = Path(path)
    try:
        desc = json.loads(path.read_text())
    except (OSError, json.JSONDecodeError) as exc:
        raise InputError(str(path), f"cannot read terrain: {exc}", "regenerate it with snakemake") from None
    if desc.get("schema") != SCHEMA:
        raise InputError(str(path), f"schema is {desc.get('schema')!r}, expected {SCHEMA!r}")
    for key, width in (("boxes", 7), ("spheres", 4)):
        rows = desc.get(key)
        if not isinstance(rows, list) or any(len(r) != width for r in rows):
            raise InputError(f"{path}: {key}", f"expected a list of rows of {width} numbers")
        if rows and not np.isfinite(np.asarray(rows, dtype=float)).all():
            raise InputError(f"{path}: {key}", "contains NaN or infinite values")
    if not (0.0 <= float(desc.get("friction", -1)) <= 10.0):
        raise InputError(f"{path}: friction", f"{desc.get('friction')!r} is not a friction in [0, 10]")
    return desc
