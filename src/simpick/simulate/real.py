"""Driving an engine with real runs: a constant-command segment on its terrain class's flat ground, or
a whole run replayed by its recorded wheel speeds, each from its seeded start heading; the cases of
the segments and replay sources (simpick.sources: :func:`prepare_segment`, :func:`prepare_replay`).
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import lru_cache
from typing import Any

import numpy as np
import pandas as pd
from pydantic import Field

from simpick.errors import InputError
from simpick.inputs.terrain import generate
from simpick.real.logs import read_canonical
from simpick.real.segments import load_segments
from simpick.real.settings import TerrainClass
from simpick.simulate.imu import model_at_rate
from simpick.simulate.real_settings import RealCaseParams
from simpick.simulate.run import (
    Case,
    Recording,
    Unit,
    config_hash,
    run_case,
    run_commands,
    scenario_from,
    stable_seed,
)
from simpick.simulate.settings import SimulationParams


class RealUnitParams(RealCaseParams, Unit):
    """What a simulate job of the replay kind reads (the plan's simpick.sources.replay case_params): a
    real-data case's params on one model (its terrain class's ground) and which unit of cases it is."""


class SegmentsUnitParams(SimulationParams, Unit):
    """What a simulate job of the segments kind reads (the plan's simpick.sources.segments case_params): the
    model's simulation settings, the ground of each terrain class its segments lie on (a job runs every
    segment of the committed table on one model; each segment's class is the table's) and which cases."""

    classes: dict[str, TerrainClass] = Field(description="each terrain class's ground, by class name")

    def case(self, terrain_class: str) -> RealCaseParams:
        """One class's real-data case params: what a segment of it reads, as a job of one class read them."""
        if terrain_class not in self.classes:
            raise ValueError(f"no terrain class {terrain_class!r} in the unit's classes {sorted(self.classes)}")
        fields = {name: getattr(self, name) for name in SimulationParams.model_fields}
        return RealCaseParams(**fields, terrain_class=terrain_class, ground=self.classes[terrain_class])


def real_case(params: RealCaseParams | Mapping[str, Any]) -> RealCaseParams:
    """A real-data case's params, typed: a job's model extending :class:`RealCaseParams` as it is, else the
    mapping validated (the calibration's, simpick.studies.calibration, which are exactly these)."""
    return RealCaseParams.model_validate(params)


def noise_seed_of(p: RealCaseParams, *names: object) -> int:
    """The IMU noise seed of a replayed case: the study seed as the params carry it (the plan's canonical
    params hold every number as a float, and the seed is hashed with the names as written), so a replay's
    noise is the one it had when the jobs read the seed from the plain params."""
    return stable_seed(float(p.seed), *names)


def flat_terrain(name: str, friction: float) -> dict:
    return generate(name, "flat", 0, friction, tiles=0)


def start_heading(seed: int, dataset: object, terrain_class: object, run: object, case: object) -> float:
    """The start heading (rad, in [0, 2 pi)) of one real-data case: drawn uniformly from the config
    seed and the case's names, the same for every model (so paired comparisons stay paired), a
    different one for every case. Mechanics says a robot on isotropic flat ground turns the same
    whichever way it faces; an engine that does not (PyBullet's gain has a 90-degree period, 0.10
    along the world axes, 0.54 at 45 degrees) then shows that as spread over the runs,
    which every interval over runs carries, instead of a bias fixed by one chosen start (every case
    started at heading 0, PyBullet's worst, before the start headings were drawn). One heading per case costs no extra
    simulation; several per case would multiply the real-data simulation by their number."""
    u = stable_seed(int(seed), "start heading", str(dataset), str(terrain_class), str(run), str(case)) / 2.0**32
    return float(2.0 * np.pi * u)


def simulate_segment(seg: pd.Series, urdf: str, params: RealCaseParams | Mapping) -> tuple[pd.DataFrame, dict]:
    """One real segment's command driven on the params' model over its class's flat ground,
    from its seeded start heading (:func:`start_heading`)."""
    p = real_case(params)
    friction = p.ground.friction
    heading = start_heading(p.seed, seg.dataset, seg.terrain_class, seg.run, seg.name)
    case = Case(
        engine=p.engine,
        terrain=p.terrain_class,
        motion=seg.name,
        v=float(seg.v),
        w=float(seg.w),
        duration=float(seg.settle + seg.duration),
        start=(0.0, 0.0, heading),
    )
    scenario = scenario_from(p, urdf, flat_terrain(p.terrain_class, friction), ground_friction=friction)
    frame, meta = run_case(case, scenario, p.robot.track, Recording.from_params(p))
    meta.update(
        {
            "dataset": seg.dataset,
            "run": seg.run,
            "segment": seg.name,
            "start_heading_deg": float(np.degrees(heading)),
            "window": [float(seg.settle), float(seg.settle + seg.duration)],
            "friction_source": p.ground.source,
            "config_hash": config_hash(params if isinstance(params, Mapping) else p.model_dump(by_alias=True)),
        }
    )
    return frame, meta


def class_segments(segments_csv: str, terrain_class: str) -> pd.DataFrame:
    segments = load_segments(segments_csv)
    return segments[segments.terrain_class == terrain_class].set_index("segment")


@lru_cache(maxsize=4)
def _segment_table(segments_csv: str) -> pd.DataFrame:
    # read once per job: a unit's cases share its table
    return load_segments(segments_csv).set_index("segment")


def table_segment(segments_csv: str, name: str) -> pd.Series:
    """The row of segment ``name`` (its id) of a segment table; an InputError unless exactly one."""
    table = _segment_table(segments_csv)
    rows = table.loc[[name]] if name in table.index else table.iloc[:0]
    if len(rows) != 1:
        found = "no segment" if rows.empty else f"{len(rows)} segments named"
        raise InputError(segments_csv, f"has {found} {name!r}", "rerun snakemake")
    return rows.iloc[0]


def log_imu_rate(log) -> float:
    """A real log's IMU rate (Hz): the reader's measured median rate, else from its times."""
    rate = ((log.meta.get("rates") or {}).get("imu") or {}).get("median_hz")
    return float(rate) if rate else float(1.0 / np.median(np.diff(log.imu["time"].to_numpy(dtype=float))))


def replay_log(
    log, urdf: str, params: RealCaseParams | Mapping, duration: float | None = None
) -> tuple[pd.DataFrame, dict]:
    """Drive one engine with a real run's recorded wheel speeds (zero-order hold, from rest, from
    the run's seeded start heading: :func:`start_heading`)."""
    p = real_case(params)
    dt = p.physics.timestep
    cmd = log.wheel_commands(p.robot.track)
    end = float(min(log.imu.time.iloc[-1], cmd.time.iloc[-1]))
    t = dt * np.arange(int(round((end if duration is None else min(end, duration)) / dt)))
    held = np.clip(np.searchsorted(cmd.time.to_numpy(), t, side="right") - 1, 0, len(cmd) - 1)
    left, right = cmd.v_left.to_numpy()[held], cmd.v_right.to_numpy()[held]
    friction = p.ground.friction
    heading = start_heading(p.seed, log.meta.get("dataset"), p.terrain_class, log.meta["run_id"], log.meta["name"])
    scenario = scenario_from(
        p, urdf, flat_terrain(p.terrain_class, friction), ((0.0, 0.0, heading),), ground_friction=friction
    )
    wheels = scenario.robot.joint_speeds(left, right)  # (steps, driven wheels): the Husky's [l, r, l, r] / radius
    recording = Recording.from_params(p, imu=model_at_rate(p.imu.model_dump(), log_imu_rate(log), dt))
    frame, meta = run_commands(p.engine, wheels, scenario, recording, noise_seed_of(p, p.engine, log.meta["name"]))
    meta.update(
        {
            "terrain": p.terrain_class,
            "motion": f"replay-{log.meta['run_id']}",
            "dataset": log.meta.get("dataset"),
            "run": str(log.meta["run_id"]),
            "seed": float(p.seed),
            "replay_of": log.meta.get("source_files"),
            "real_imu_rate_hz": log_imu_rate(log),
            "start_heading_deg": float(np.degrees(heading)),
        }
    )
    return frame, meta


def prepare_segment(urdf: str, inputs: dict, params: Mapping, name: str):
    """A segment of the table (the segments source): its constant command on its class's flat
    ground (the unit's ground of the class the table gives it), compared in its window."""
    unit = SegmentsUnitParams.model_validate(params)
    seg = table_segment(inputs["segments"], name)
    if seg.terrain_class not in unit.classes:
        raise InputError(
            inputs["segments"],
            f"gives segment {name!r} class {seg.terrain_class!r}, not one of the job's",
            "rerun snakemake",
        )
    p = unit.case(seg.terrain_class)
    which = {
        "terrain": p.terrain_class,
        "motion": seg.name,
        "test": seg.name,
        "dataset": seg.dataset,
        "run": str(seg.run),
        "segment": seg.name,
        "window": [float(seg.settle), float(seg.settle + seg.duration)],
    }
    return which, lambda: simulate_segment(seg, urdf, p)


def prepare_replay(urdf: str, inputs: dict, params: Mapping, name: str):
    """A replayed run (the replay source: a dataset folder's or an own log) driven by its recorded
    wheel speeds."""
    p = RealUnitParams.model_validate(params)
    # the unit's logs are its cases' in order (one terrain class's runs: simpick.sources.replay.case_inputs)
    logs = [inputs["logs"]] if isinstance(inputs["logs"], str) else list(inputs["logs"])
    log = read_canonical(logs[list(p.cases).index(name)])
    run = str(log.meta["run_id"])
    which = {
        "terrain": p.terrain_class,
        "motion": f"replay-{run}",
        "test": f"{p.terrain_class}-{run}",
        "dataset": log.meta.get("dataset"),
        "run": run,
    }
    return which, lambda: replay_log(log, urdf, p)
