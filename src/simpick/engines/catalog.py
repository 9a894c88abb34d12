"""The simulator catalog (``resources/simulators/simulators.yaml``): what each simulator is, the facts
the paper's qualitative scores rest on (re-checked for 2026, a source per fact), and its two profiles,
each setting with the simulator's own name for it and the file and line (or manual page) it is read
from. Read once at planning time; every profile's settings are checked by its engine adapter's own
settings model there, so a misspelt setting or a value the adapter refuses stops the study before any job.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from simpick.engines.simulators import CATALOG_VARIANTS, SIMULATORS, VARIANTS, model_name


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class Setting(_Strict):
    """One engine setting of a profile."""

    value: Any = Field(description="the adapter's value (simpick.engines.<engine> settings model)")
    exposed_as: str = Field(
        description="how the simulator's user sets it (an SDF element, a PROTO field, an MJCF attribute, ...), "
        "or 'not exposed' for a value the simulator fixes"
    )
    source: str = Field(description="where the simulator's value is read: repository path:line, or a manual page")
    note: str | None = Field(None, description="what it means, and what it does here where measured")


class Profile(_Strict):
    """A simulator's set-up: its engine's settings beyond the adapter's defaults."""

    settings: dict[str, Setting] = Field({}, description="adapter setting -> the simulator's value")
    robots: dict[str, dict[str, Setting]] = Field(
        {},
        description="URDF <robot name> -> settings the robot's maker publishes for this simulator "
        "(Clearpath's Gazebo tags), over ``settings``",
    )
    basis: str = Field(description="how the set-up was found: the simulator's defaults, or the search behind it")
    differs: list[str] = Field(
        [], description="where simpick's reproduction differs from the simulator (fork, version, settings not bound)"
    )


class Qualitative(_Strict):
    """The paper's qualitative facts (its section 3.2 rules; simpick.score.scoring.qualitative_scores)."""

    free: bool
    open_source: bool
    ros: Literal["out_of_the_box", "official_plugin", "none"]
    languages: list[str]
    ui: Literal["full", "partial", "visualization", "none"]
    model_formats: list[str]
    urdf_sdf_via_manual_plugin: bool = False
    physics_engines: list[str]
    licence: str
    sources: dict[str, str] = Field(description="fact -> its source; every fact needs one")
    notes: dict[str, str] = {}

    @model_validator(mode="after")
    def _every_fact_sourced(self):
        facts = [f for f in type(self).model_fields if f not in ("sources", "notes", "urdf_sdf_via_manual_plugin")]
        missing = [f for f in facts if f not in self.sources]
        if missing:
            raise ValueError(f"facts without a source: {missing}; add each under sources:")
        unknown = sorted(set(self.sources) - set(type(self).model_fields))
        if unknown:
            raise ValueError(f"sources of unknown facts {unknown}")
        return self


SETTINGS_FORMATS = ("sdf", "webots", "coppeliasim", "mjcf", "isaaclab", "newton", "drake", "genesis")


class Simulator(_Strict):
    label: str = Field(description="the simulator's name in the report")
    release: str = Field(description="the release the facts and defaults were read from")
    status: str = Field(description="maintained, or end of life with the date")
    engine: str | None = Field(
        description="simpick's adapter reproducing its physics (simpick.engines.simulators.SIMULATORS)"
    )
    engine_build: str = Field(description="the engine and version the simulator itself runs, with the source")
    simpick_build: str | None = Field(description="what simpick runs instead (PyPI / Debian build), if anything")
    settings_format: Literal[SETTINGS_FORMATS] | None = Field(  # type: ignore[valid-type]
        description="the format of the settings file written for it"
    )
    qualitative: Qualitative
    shipped: Profile | None = None
    tuned: Profile | None = None
    not_reproduced: str | None = Field(None, description="why simpick cannot run it (it keeps its row)")

    @model_validator(mode="after")
    def _runnable_or_why(self):
        if self.engine is None and not self.not_reproduced:
            raise ValueError("a simulator with no engine needs not_reproduced: the reason")
        if self.engine is not None and (self.shipped is None or self.tuned is None):
            raise ValueError("a simulator simpick runs needs both profiles: shipped and tuned")
        return self


class Catalog(_Strict):
    simulators: dict[str, Simulator]
    path: str

    def profile(self, simulator: str, variant: str) -> Profile:
        """A variant's catalog profile (the calibrated variant's is the tuned one it starts from)."""
        return getattr(self.simulators[simulator], _catalog_variants(variant)[-1])

    def settings(self, simulator: str, variant: str, robot: str | None = None) -> dict[str, Any]:
        """The adapter settings of a profile for ``robot`` (URDF name): the tuned profile is the
        shipped one with the tuned values over it; the calibrated profile starts from the tuned one (its
        fitted values come from a job: simpick.studies.simulator_calibration)."""
        sim = self.simulators[simulator]
        out: dict[str, Any] = {}
        for v in _catalog_variants(variant):
            profile = getattr(sim, v)
            out.update({k: s.value for k, s in profile.settings.items()})
            if robot is not None:
                out.update({k: s.value for k, s in profile.robots.get(robot, {}).items()})
        return out

    def entries(self, simulator: str, variant: str, robot: str | None = None) -> dict[str, tuple[str, Setting]]:
        """setting -> (the profile that sets it, its entry), as :meth:`settings` merges them."""
        sim = self.simulators[simulator]
        out: dict[str, tuple[str, Setting]] = {}
        for v in _catalog_variants(variant):
            profile = getattr(sim, v)
            out.update({k: (v, s) for k, s in profile.settings.items()})
            if robot is not None:
                out.update({k: (f"{v} ({robot})", s) for k, s in profile.robots.get(robot, {}).items()})
        return out

    def runnable(self) -> list[str]:
        return [name for name, sim in self.simulators.items() if sim.engine is not None]

    def models(self, simulators: list[str] | None = None, variants=VARIANTS) -> list[str]:
        """Profile model names (``gazebo-shipped``) of ``simulators`` (default: every runnable one)."""
        names = self.runnable() if simulators is None else simulators
        return [model_name(s, v) for s in names for v in variants]


def _catalog_variants(variant: str) -> tuple[str, ...]:
    """The catalog's profiles a variant's settings merge, in order: the calibrated one's are the tuned one's."""
    if variant not in VARIANTS:
        raise KeyError(f"no simulator variant {variant!r}; the variants are {VARIANTS}")
    stop = "tuned" if variant == "calibrated" else variant
    return CATALOG_VARIANTS[: CATALOG_VARIANTS.index(stop) + 1]


class CatalogError(ValueError):
    """A catalog that cannot be used: the message names the file, the entry and the fix."""


def load_catalog(path: str | Path) -> Catalog:
    """Read and check the catalog: simulators known to the registry, each with its registered engine,
    every fact sourced, every profile's settings accepted by its engine's settings model."""
    from simpick.engines import get_engine

    path = Path(path)
    try:
        # libyaml's parser where PyYAML has it: the catalog is read three times when a run plans (the
        # config's checks and the plan), about 0.1 s each in Python's parser against 0.01 s
        raw = yaml.load(path.read_text(), Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))
    except OSError as exc:
        raise CatalogError(f"{path}: cannot be read ({exc.strerror}); simulators.catalog names it") from None
    except yaml.YAMLError as exc:
        raise CatalogError(f"{path}: not valid YAML ({exc})") from None
    if not isinstance(raw, dict) or not isinstance(raw.get("simulators"), dict):
        raise CatalogError(f"{path}: needs a top-level mapping 'simulators:' of simulator name -> entry")
    unknown = sorted(set(raw["simulators"]) - set(SIMULATORS))
    if unknown:
        raise CatalogError(
            f"{path}: simulators.{unknown[0]}: not a registered simulator; registered: {sorted(SIMULATORS)} "
            "(simpick.engines.simulators.SIMULATORS maps each to its engine)"
        )
    try:
        catalog = Catalog(simulators=raw["simulators"], path=str(path))
    except ValidationError as exc:
        err = exc.errors()[0]
        where = ".".join(str(p) for p in err["loc"])
        raise CatalogError(f"{path}: {where}: {err['msg']}") from None
    for name, sim in catalog.simulators.items():
        if sim.engine != SIMULATORS[name]:
            raise CatalogError(
                f"{path}: simulators.{name}.engine: {sim.engine!r}, but the registry runs it on "
                f"{SIMULATORS[name]!r} (simpick.engines.simulators.SIMULATORS); make them agree"
            )
        if sim.engine is None:
            continue
        model = get_engine(sim.engine).settings_model
        robots = {r for v in CATALOG_VARIANTS for r in getattr(sim, v).robots}
        for variant in CATALOG_VARIANTS:
            for robot in [None, *sorted(robots)]:
                settings = catalog.settings(name, variant, robot)
                try:
                    model.model_validate(settings)
                except ValidationError as exc:
                    err = exc.errors()[0]
                    key = ".".join(str(p) for p in err["loc"]) or "settings"
                    robot_part = f" with robots.{robot}" if robot else ""
                    raise CatalogError(
                        f"{path}: simulators.{name}.{variant}{robot_part}: {key}: {err['msg']} "
                        f"(the {sim.engine} adapter's settings: simpick.engines)"
                    ) from None
    return catalog
