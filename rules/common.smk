# Helpers shared by the rules: the config slices each rule may see, canonicalised.
import sys

from simpick.config import validate_or_exit


validate_or_exit(config, files=workflow.configfiles)

ENGINES = list(config["engines"])
TERRAINS = list(config["terrains"])
MOTIONS = list(config["motions"])


wildcard_constraints:
    engine="|".join(ENGINES),
    terrain="|".join(TERRAINS),
    motion="|".join(MOTIONS),


def canonical(value):
    """Builtin types only, sorted keys, numbers as floats: Snakemake fingerprints params by
    repr, so 4 and 4.0, or a reordered mapping, must not look like an edit."""
    if isinstance(value, dict):
        return {str(k): canonical(value[k]) for k in sorted(value)}
    if isinstance(value, (list, tuple)):
        return [canonical(v) for v in value]
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return value
    return float(value)


def all_traces():
    return expand(
        "results/traces/{engine}/{terrain}/{motion}.parquet",
        engine=ENGINES,
        terrain=TERRAINS,
        motion=MOTIONS,
    )


def engine_params(engine):
    """What every simulation on ``engine`` depends on, whatever it drives over."""
    robot = {k: v for k, v in config["robot"].items() if k != "urdf"}
    return canonical(
        {
            "engine": engine,
            "engine_settings": config["engines"][engine] or {},
            "physics": config["physics"],
            "robot": robot,
            "imu": config["imu"],
            "health": config["health"],
            "seed": config["seed"],
        }
    )


def simulation_params(engine, terrain, motion_name):
    """Everything one lab-study simulation depends on, and nothing else."""
    return engine_params(engine) | canonical(
        {
            "terrain": terrain,
            "motion_name": motion_name,
            "motion": config["motions"][motion_name],
        }
    )
