"""The calibrated profile's search space: per simulator, the adapter settings the fit may change, read from
``resources/simulators/calibration.yaml`` and checked against the simulators and their adapters."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal

import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from simpick.engines.simulators import SIMULATORS

CALIBRATED = "calibrated"


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class SearchSetting(_Strict):
    """One adapter setting the fit may change, as the simulator exposes it."""

    exposed_as: str = Field(description="how the simulator's user sets it, in the simulator's own names")
    bounds: tuple[float, float] = Field(description="[low, high] of the adapter's value")
    source: str = Field(description="where the simulator reads it: repository path:line, or a manual page")
    log: bool = Field(False, description="fitted over the logarithm of its value (a setting spanning decades)")
    part: Literal["contact", "actuator"] = Field(
        "contact",
        description="what it belongs to: the wheel-ground contact (friction, slip, compliance) or the wheel "
        "actuator (a servo's gain, a drive's stiffness or damping, an effort limit); the fit reports each part's "
        "share of what it gained",
    )

    @model_validator(mode="after")
    def _ordered(self):
        if not self.bounds[0] < self.bounds[1]:
            raise ValueError(f"bounds {list(self.bounds)}: low must be below high")
        if self.log and not self.bounds[0] > 0:
            raise ValueError(f"bounds {list(self.bounds)}: a log setting needs a positive low bound")
        return self


class Required(_Strict):
    """An adapter setting the fitted ones need (Webots' asymmetric friction follows the wheel)."""

    value: Any
    exposed_as: str
    source: str


class SearchSpace(_Strict):
    """A simulator's calibrated-profile search space."""

    searchable: bool = Field(description="a setting it exposes moves the steady turning")
    settings: dict[str, SearchSetting] = {}
    requires: dict[str, Required] = {}
    why_not: str | None = Field(None, description="searchable false: why, quoting the source")
    scan: Annotated[int, Field(ge=0, le=12)] = Field(
        0,
        description="the fit first evaluates the first setting at this many points over its bounds and starts "
        "from the best (0: from the tuned profile): where the engine's gain jumps with it, a local fit cannot leave "
        "the jump it starts in; the reason is given beside it",
    )
    order: list[str] = Field(
        [],
        description="the order the fit takes the settings in where the training runs identify fewer than all of "
        "them (a class with one training run fits the first alone); the settings it does not name follow, sorted",
    )
    if_unbound: str | None = Field(
        None, description="the simulator exposes the settings, but simpick's adapter binds none of them: why"
    )
    optimizer: Literal["scipy", "mujoco.sysid"] = Field(
        "scipy",
        description="what fits the settings: scipy (scipy.optimize.least_squares, trf) or mujoco.sysid (MuJoCo's "
        "own system identification, mujoco.sysid.optimize with its optimizer 'mujoco', the intervals from its "
        "calculate_intervals); the residuals, the budget and the unidentifiability checks are the same",
    )

    @model_validator(mode="after")
    def _consistent(self):
        if self.searchable and not self.settings:
            raise ValueError("searchable true needs settings: the adapter settings the fit changes")
        if not self.searchable and not self.why_not:
            raise ValueError("searchable false needs why_not: why no setting it exposes moves the turning")
        if not self.searchable and (self.settings or self.requires):
            raise ValueError("searchable false takes no settings or requires")
        unknown = [k for k in self.order if k not in self.settings]
        if unknown or len(set(self.order)) != len(self.order):
            raise ValueError(
                f"order {self.order} must name settings of this entry, each once (settings: {sorted(self.settings)})"
            )
        return self

    def fit_order(self) -> list[str]:
        """The settings in the order the fit takes them: those ``order`` names first, then the others sorted."""
        return list(self.order) + sorted(k for k in self.settings if k not in self.order)


class SearchSpaceError(ValueError):
    """A search-space file that cannot be used: the message names the file, the entry and the fix."""


def load_search_spaces(path: str | Path) -> dict[str, SearchSpace]:
    """Read and check the search spaces: registered simulators only, each entry complete, each setting with
    its bounds and source. Which settings its adapter binds is checked by :func:`resolve`."""
    path = Path(path)
    try:
        raw = yaml.safe_load(path.read_text())
    except OSError as exc:
        raise SearchSpaceError(f"{path}: cannot be read ({exc.strerror}); simulators.calibration names it") from None
    except yaml.YAMLError as exc:
        raise SearchSpaceError(f"{path}: not valid YAML ({exc})") from None
    if not isinstance(raw, dict) or not isinstance(raw.get("simulators"), dict):
        raise SearchSpaceError(f"{path}: needs a top-level mapping 'simulators:' of simulator name -> search space")
    out = {}
    for name, entry in raw["simulators"].items():
        if name not in SIMULATORS:
            raise SearchSpaceError(
                f"{path}: simulators.{name}: not a registered simulator; registered: {sorted(SIMULATORS)}"
            )
        try:
            out[name] = SearchSpace.model_validate(entry)
        except ValidationError as exc:
            err = exc.errors()[0]
            where = ".".join(str(p) for p in err["loc"])
            raise SearchSpaceError(f"{path}: simulators.{name}{'.' + where if where else ''}: {err['msg']}") from None
    return out


def resolve(path: str | Path, name: str, space: SearchSpace | None, engine: str) -> tuple[bool, str | None]:
    """(whether the calibrated profile of simulator ``name`` has settings to fit here, why not): a setting its
    engine's settings model lacks stops the plan, unless the entry says why the adapter cannot bind it
    (``if_unbound``), in which case the profile keeps its tuned settings and says so."""
    from simpick.engines import get_engine

    if space is None:
        raise SearchSpaceError(
            f"{path}: simulators.{name}: missing; every simulator whose profiles run needs its search space "
            "(searchable: false with why_not where it exposes no turning setting)"
        )
    if not space.searchable:
        return False, space.why_not
    fields = get_engine(engine).settings_model.model_fields
    missing = [k for k in [*space.settings, *space.requires] if k not in fields]
    if missing:
        if space.if_unbound:
            return False, space.if_unbound
        raise SearchSpaceError(
            f"{path}: simulators.{name}.settings.{missing[0]}: the {engine} adapter has no such setting "
            f"(its settings: {sorted(fields)}); name an adapter setting, or say why it cannot be bound (if_unbound)"
        )
    return True, None
