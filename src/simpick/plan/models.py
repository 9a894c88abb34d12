"""The models a study runs: the configured engines this machine can run (the others named with why
not), each simulator's catalog profiles run as models of their own, and the reference baselines.

Which models exist is settled first and apart from everything else: the sources, the costs and the
answer all iterate over these lists, and what leaves an engine out (not installed, its venv's build
failed) or folds a profile into the engine or profile whose settings it repeats is reasoning of its own.
"""

from __future__ import annotations

from simpick.engines import get_engine, unavailable
from simpick.engines.catalog import load_catalog
from simpick.engines.simulators import MODEL_SETTINGS, engine_of, model_name
from simpick.plan.errors import PlanError


def _build_failure(engine: str) -> str:
    """Why an engine's own virtual environment could not be built, where `make engine-venvs` kept pip's
    last error lines (``.venv-<engine>.failed`` beside the venv); empty otherwise."""
    from simpick.engines import isolated

    if engine not in isolated.MODULES:
        return ""
    failed = isolated.venv_python(engine).parents[2] / f".venv-{engine}.failed"
    if not failed.exists():
        return ""
    lines = [line.strip() for line in failed.read_text(errors="replace").splitlines() if line.strip()]
    return f"; its build failed: {' / '.join(lines)}" if lines else ""


class ModelPlanning:
    """The study's models (a mixin of :class:`simpick.plan.Plan`, set up after its robot)."""

    def __init__(self):
        config = self.config
        # Engines this machine cannot run (simpick.engines.unavailable: not installed): the study
        # runs without them, and its report lists them.
        self.unavailable = {e: why + _build_failure(e) for e, why in unavailable(config["engines"]).items()}
        self.engines = [e for e in config["engines"] if e not in self.unavailable]
        if not self.engines:
            raise PlanError(f"none of the configured engines can run here: {self.unavailable}")
        # Simulators as rows (simpick.engines.simulators): each simulator's profiles whose engine this study runs,
        # as models of their own. They run the validation and every real-data source like an engine, never
        # the lab scenario or the CPU load (their engine's figures), and their settings are the catalog's.
        self.catalog = load_catalog(config["simulators"]["catalog"])
        self.simulators, self.simulators_left_out = self._simulators()
        config["profiles"] = {
            model_name(sim, variant): self._profile_settings(sim, variant)
            for sim in self.simulators
            for variant in config["simulators"]["variants"]
        }
        # A profile whose settings are exactly its engine's in this study (MuJoCo and Drake as tuned: every
        # setting simpick's engine block makes is an MJCF attribute or a Drake tag) runs nothing of its own:
        # its figures are the engine's, the same traces (a run is deterministic in its settings).
        # The same holds between profiles: a tuned profile the search left at its shipped settings reads those.
        self.profile_results = {}
        for p, settings in config["profiles"].items():
            same = [
                m
                for m, s in [
                    (engine_of(p), config["engines"].get(engine_of(p))),
                    *((q, config["profiles"][q]) for q in self.profile_results if self.profile_results[q] == q),
                ]
                if s == settings
            ]
            self.profile_results[p] = same[0] if same else p
        self.profiles = [p for p, model in self.profile_results.items() if model == p]
        # Reference models (kinematic, coulomb) join the real-data comparison only, never the scores.
        self.baselines = list(config.get("baselines") or {})
        self.real_models = self.engines + self.profiles + self.baselines
        self.validated = self.engines + self.profiles

    def _profile_settings(self, simulator: str, variant: str) -> dict:
        """A profile's full adapter settings: the adapter's defaults, the study's robot-model settings of that
        engine (its wheel actuators: simpick.engines.simulators.MODEL_SETTINGS), then the catalog's profile."""
        engine = engine_of(model_name(simulator, variant))
        block = self.config["engines"].get(engine) or {}
        model = {k: value for k, value in block.items() if k in MODEL_SETTINGS.get(engine, ())}
        settings = model | self.catalog.settings(simulator, variant, self.robot.name)
        return get_engine(engine).settings_model.model_validate(settings).model_dump(mode="json")

    def _simulators(self):
        """(simulators whose profiles run, {simulator: why not} for the catalog's others)."""
        wanted = self.config["simulators"]["run"]
        run, out = [], {}
        for name, sim in self.catalog.simulators.items():
            if wanted is not None and name not in wanted:
                out[name] = "not in simulators.run"
            elif sim.engine is None:
                out[name] = sim.not_reproduced
            elif sim.engine in self.unavailable:
                out[name] = f"its engine {sim.engine} cannot run here: {self.unavailable[sim.engine]}"
            elif sim.engine not in self.engines:
                out[name] = f"its engine {sim.engine} is not among this study's engines"
            else:
                run.append(name)
        return run, out
