"""The models a study runs: the configured engines this machine can run (the others named with why
not), each simulator's catalog profiles run as models of their own, and the reference baselines.

Which models exist is settled first and apart from everything else: the sources, the costs and the
answer all iterate over these lists, and what leaves an engine out (not installed, its venv's build
failed) or folds a profile into the engine or profile whose settings it repeats is reasoning of its own.
"""

from __future__ import annotations

import importlib

from simpick.engines import PROFILE_ADAPTERS, get_engine, unavailable
from simpick.engines.catalog import load_catalog
from simpick.engines.simulators import MODEL_SETTINGS, SEPARATOR, engine_of, model_name, split
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
        # The configured engines are the plain settings' engines block (simpick.config.load.plain: the configured
        # entries in the config's order, each with its adapter's settings in full), keyed by engine name; the
        # typed study's block has a field for every known adapter, and its set of configured ones no order.
        configured = config["engines"]  # keyed by engine name, in the config's order (above)
        # Engines this machine cannot run (simpick.engines.unavailable: not installed): the study
        # runs without them, and its report lists them.
        self.unavailable = {e: why + _build_failure(e) for e, why in unavailable(configured).items()}
        self.engines = [e for e in configured if e not in self.unavailable]
        if not self.engines:
            raise PlanError(f"none of the configured engines can run here: {self.unavailable}")
        # Simulators as rows (simpick.engines.simulators): each simulator's profiles whose engine this study runs,
        # as models of their own. They run the validation and every real-data source like an engine, never
        # the lab scenario or the CPU load (their engine's figures), and their settings are the catalog's.
        simulators = self.settings.simulators
        self.catalog = load_catalog(simulators.catalog)
        self.simulators, self.simulators_left_out = self._simulators()
        # the profiles' full settings, keyed by profile name, join the plain settings beside the engines' block
        # (simpick.sources.base.model_settings reads a model's settings there): no section of the typed study
        # holds them
        self.calibrated_left_out = self._calibrated_left_out()
        variants = [v for v in simulators.variants if v != "calibrated" or not self.calibrated_left_out]
        # profile -> its full adapter settings: the plan's own, read by the plan's jobs' params from here
        self.profile_settings: dict[str, dict] = {
            model_name(sim, variant): self._profile_settings(sim, variant)
            for sim in self.simulators
            for variant in variants
        }
        config["profiles"] = self.profile_settings  # simpick.sources.base.model_settings reads a model's there
        # The calibrated profiles (simpick.studies.simulator_calibration): per simulator, whether a setting it
        # exposes moves its turning here ({simulator: why not} for the others). Their fitted values come from a
        # job, so their plan-time settings are the tuned ones: one with settings to fit runs as a model of its
        # own (its jobs merge the fit's file at run time), one without reads its tuned profile's results.
        self.calibration_spaces, self.calibrated, self.calibrated_why_not = self._calibration_spaces(variants)
        # A profile whose settings are exactly its engine's in this study (MuJoCo and Drake as tuned: every
        # setting simpick's engine block makes is an MJCF attribute or a Drake tag) runs nothing of its own:
        # its figures are the engine's, the same traces (a run is deterministic in its settings).
        # The same holds between profiles: a tuned profile the search left at its shipped settings reads those.
        self.profile_results = {}
        profiles = self.profile_settings
        for p, settings in profiles.items():
            if p in self.calibrated:  # its settings are the fit's, known only when its job has run
                self.profile_results[p] = p
                continue
            if p.endswith(f"{SEPARATOR}calibrated"):  # nothing to fit: the tuned profile is the best it reaches
                self.profile_results[p] = self.profile_results[p.rsplit(SEPARATOR, 1)[0] + f"{SEPARATOR}tuned"]
                continue
            same = [
                m
                for m, s in [
                    (engine_of(p), configured.get(engine_of(p))),
                    *(
                        (q, profiles[q])
                        for q in self.profile_results
                        if self.profile_results[q] == q and q not in self.calibrated
                    ),
                ]
                if s == settings
            ]
            self.profile_results[p] = same[0] if same else p
        self.profiles = [p for p, model in self.profile_results.items() if model == p]
        # Reference models (kinematic, coulomb) join the real-data comparison only, never the scores.
        self.baselines = list(config["baselines"])  # keyed by reference model, in the config's order (plain)
        self.real_models = self.engines + self.profiles + self.baselines
        self.validated = self.engines + self.profiles

    def _profile_settings(self, simulator: str, variant: str) -> dict:
        """A profile's full adapter settings: the adapter's defaults, the study's robot-model settings of that
        engine (its wheel actuators: simpick.engines.simulators.MODEL_SETTINGS), then the catalog's profile."""
        engine = engine_of(model_name(simulator, variant))
        block = self.config["engines"].get(engine) or {}  # keyed by engine name: its full settings (plain)
        model = {k: value for k, value in block.items() if k in MODEL_SETTINGS.get(engine, ())}
        settings = model | self.catalog.settings(simulator, variant, self.robot.name)
        return get_engine(engine).settings_model.model_validate(settings).model_dump(mode="json")

    def _calibrated_left_out(self) -> str:
        """Why this study runs no calibrated profile (empty when it does): it fits on the real robot's runs with
        the calibration's split, the committed segments where they are this robot's, else DRIVE's steps where the
        profiles replay them (:attr:`calibration_source`)."""
        if "calibrated" not in self.settings.simulators.variants:
            return "not in simulators.variants"
        if self.settings.calibration is None:
            return "the study has no calibration section (its split: test_fraction, seed, target classes)"
        if self.calibration_source is None:
            if self.settings.drive_dir:
                return (
                    "the profiles do not replay DRIVE's steps here (simulators.drive: false), and the calibrated "
                    "profile is judged on held-out steps: set simulators.drive: true"
                )
            return (
                "no real runs of this robot to fit on here (the committed segments are the Husky's): give its "
                "DRIVE steps (drive_dir) with simulators.drive: true, its own logs (own_logs) with "
                "accuracy.reference: own, or a segments table of its own runs (real_data.segments, real_data.robot)"
            )
        return ""

    @property
    def calibration_source(self) -> str | None:
        """The real runs the calibrated profiles fit on and are judged on: ``replay`` (a dataset folder's runs,
        where the verdict rests on them), ``own`` (the user's own logs, where the verdict rests on them:
        accuracy.reference own), ``segments`` (the committed segments, where they are this robot's), ``drive``
        (DRIVE's steps, where the profiles replay them) or None (none of these)."""
        # the verdict rests on the full replay (simpick.plan.answer.accuracy_source), known from the settings
        # alone: the dataset folder is opened after this planning step
        replayed = self.settings.borealtc_dir and self.settings.accuracy.reference not in ("paper", "own")
        if self.real_data_robot and replayed:
            return "replay"
        if self.settings.own_logs and self.settings.accuracy.reference == "own":
            # the user's own logs, where the verdict rests on them: fitted and judged as the full replay's runs
            return "own"
        if self.real_data_robot and self.settings.real_data.segments:
            return "segments"
        if self.settings.drive_dir and self.settings.simulators.drive:
            return "drive"
        return None

    def _calibration_spaces(self, variants):
        """(search spaces, calibrated profiles with settings to fit, {simulator: why its calibrated profile fits
        nothing}) over the run simulators (simpick.studies.simulator_calibration.resolve)."""
        from simpick.studies.simulator_calibration import load_search_spaces, resolve

        if "calibrated" not in variants or not self.simulators:
            return {}, [], {}
        path = self.settings.simulators.calibration
        spaces = load_search_spaces(path)
        fitted, why_not = [], {}
        for sim in self.simulators:
            ok, why = resolve(path, sim, spaces.get(sim), self.catalog.simulators[sim].engine)
            if ok:
                fitted.append(model_name(sim, "calibrated"))
            else:
                why_not[sim] = why
        return spaces, fitted, why_not

    def _simulators(self):
        """(simulators whose profiles run, {simulator: why not} for the catalog's others)."""
        wanted = self.settings.simulators.run
        run, out = [], {}
        for name, sim in self.catalog.simulators.items():
            if wanted is not None and name not in wanted:
                out[name] = "not in simulators.run"
            elif sim.engine is None:
                out[name] = sim.not_reproduced
            elif sim.engine in self.unavailable:
                out[name] = f"its engine {sim.engine} cannot run here: {self.unavailable[sim.engine]}"
            elif sim.engine in PROFILE_ADAPTERS:
                # an engine that runs only behind profiles: checked here, as the configured ones are above
                why = unavailable([sim.engine]).get(sim.engine)
                adapter = get_engine(sim.engine)
                if why is not None:
                    out[name] = f"its engine {sim.engine} cannot run here: {why}"
                elif self.robot.suspension and not adapter.simulates_suspension:
                    out[name] = f"its engine {sim.engine} does not simulate {self.robot.name}'s passive suspension"
                else:
                    run.append(name)
            elif sim.engine not in self.engines:
                out[name] = f"its engine {sim.engine} is not among this study's engines"
            else:
                run.append(name)
        return run, out

    # --- the params of the jobs that simulate or compare a source's cases, validated against their jobs' models
    # (simpick.simulate, simpick.compare) ---

    def simulate_params(self, source: str, engine: str, group: str, names: list[str]) -> dict:
        """A simulate job's params (its source module's, :meth:`case_params`), validated against its kind's
        model (:data:`simpick.simulate.jobs.PARAMS`) and passed as the source module builds them: their keys in
        its order, which their repr, Snakemake's fingerprint, shows (a canonical dump would reorder them and so
        rerun every simulation)."""
        from simpick.plan.jobs import job_params
        from simpick.simulate.jobs import PARAMS

        params = self.case_params(source, engine, group, names)
        module, _, name = PARAMS[self.source_of(source).DRIVEN].partition(":")
        job_params(f"simulate ({source})", getattr(importlib.import_module(module), name), params)
        return params

    def compare_params(self, source: str) -> dict:
        """Rule compare's settings for a source: its module's compare settings, validated against what its kind's
        comparison reads (:data:`simpick.compare.kinds.SETTINGS`)."""
        from simpick.compare.kinds import SETTINGS
        from simpick.plan.jobs import job_params

        model = SETTINGS[self.source_of(source).DRIVEN]
        return job_params("compare", model, self.compare_settings(source))

    def summarise_params(self, source: str) -> dict:
        """Rule summarise's settings for a source: its group column and the statistics
        (:class:`simpick.compare.settings.SummariseSettings`)."""
        from simpick.compare.settings import SummariseSettings
        from simpick.plan.jobs import job_params

        data = {"group": self.sources[source]["group"], "statistics": self.settings.statistics.model_dump()}
        return job_params("summarise", SummariseSettings, data)

    def drive_replay_params(self, model: str, session: str) -> dict:
        """Rule drive_replay's params (:class:`simpick.simulate.steps.SessionReplayParams`): what every
        simulation on the model reads, every terrain class's ground, how the steps are replayed (the whole
        ``drive_replay`` section, as the jobs have always been given it) and the session."""
        from simpick.plan.jobs import job_params
        from simpick.simulate.steps import SessionReplayParams
        from simpick.sources.base import model_settings

        study = self.settings
        data = {
            "engine": model,
            "engine_settings": model_settings(self.config, model),
            "physics": study.physics.model_dump(mode="json"),
            "robot": self._robot(),
            "imu": study.imu.model_dump(mode="json"),
            "health": study.health.model_dump(mode="json"),
            "seed": study.seed,
            "classes": {name: c.model_dump(mode="json") for name, c in study.real_data.classes.items()},
            "replay": study.drive_replay.model_dump(mode="json"),
            "session": session,
        }
        return job_params("drive_replay", SessionReplayParams, data)

    # --- the calibrated profiles (rules/simulators.smk: simulator_split, simulator_calibrate) ---

    CALIBRATION_DIR = "results/simulators/calibration"

    def calibration_file(self, simulator: str) -> str:
        """The fit of a simulator's calibrated profile (rule simulator_calibrate)."""
        return f"{self.CALIBRATION_DIR}/{simulator}.yaml"

    def calibration_files(self) -> list[str]:
        """Every run simulator's fit (its searchable false ones say why and what they reach)."""
        return [self.calibration_file(s) for s in self.simulators] if self.calibration_spaces else []

    @property
    def model_profiles(self) -> list[str]:
        """The profiles that get a model a user opens as it is (rule simulator_models): those of a simulator that
        has a model writer (simpick.engines.simulator_models.WRITERS, by simulator: Gazebo Classic and Webots share
        the ODE adapter) able to write the study's robot, aliases of an engine's results included."""
        from simpick.engines.simulator_models import WRITERS

        def writer(profile: str):
            parts = split(profile)
            return WRITERS.get(parts[0]) if parts else None

        return [p for p in self.profile_results if (w := writer(p)) is not None and w.writes(self.robot)]

    MODELS_DIR = "results/simulators/models"

    def model_files(self) -> dict[str, str]:
        """profile -> its model's path (rule simulator_models; a calibrated terrain class's beside it, named
        ``<profile>-<class>``, where the fit gives the class a file of its own)."""
        from simpick.engines.simulator_models import WRITERS

        return {p: f"{self.MODELS_DIR}/{p}.{WRITERS[split(p)[0]].suffix}" for p in self.model_profiles}

    def model_notes(self) -> dict[str, str]:
        """profile -> the words beside its model's link where no loader of its simulator runs here (the writer's
        ``opened_here``): its fields are checked, the file is not opened in the simulator."""
        from simpick.engines.simulator_models import WRITERS, not_opened_note

        return {
            p: not_opened_note(self.catalog.simulators[split(p)[0]].label)
            for p in self.model_profiles
            if not WRITERS[split(p)[0]].opened_here
        }

    def model_code_roots(self) -> tuple[str, ...]:
        """The modules rule simulator_models' job reaches by name only: its profiles' engines' adapters (the
        validation's run_case finds an adapter in the registry), as rule validate's code counts them."""
        return tuple(sorted({m for p in self.model_profiles for m in self.engine_modules(p)}))

    def simulator_models_input(self) -> dict:
        """Rule simulator_models' input: the robot's description and the fits of the calibrated model profiles."""
        fitted = dict.fromkeys(
            p.rsplit(SEPARATOR, 1)[0] for p in self.model_profiles if p.endswith(f"{SEPARATOR}calibrated")
        )
        calibrations = [self.calibration_file(s) for s in fitted] if self.calibration_spaces else []
        return {"urdf": self.settings.robot.urdf, "calibrations": calibrations}

    def calibrated_input(self, model: str) -> dict:
        """A model's jobs' extra input: a calibrated profile's fit, whose settings they merge at run time."""
        if model in self.calibrated:
            return {"calibrated": self.calibration_file(model.rsplit(SEPARATOR, 1)[0])}
        return {}

    def unit_inputs(self, source, engine, group, names):
        """The files a simulate job reads: its source's (case_inputs) and a calibrated profile's fit."""
        return self.case_inputs(source, group, names) | self.calibrated_input(engine)

    def validation_inputs(self, engine):
        """The files a validate job reads: the robot and a calibrated profile's fit."""
        return {"urdf": self.settings.robot.urdf} | self.calibrated_input(engine)

    def calibration_real_input(self) -> dict:
        """The real runs rule simulator_split splits and simulator_calibrate fits on: the committed segments
        (``segments``), the full replay's steady turning windows (``windows``, rule real_turning) with the
        calibration's split of its runs (``calibration_split``) and their logs (``logs``), or DRIVE's steps, case
        and wheels tables (``steps``, ``cases``, ``wheels``, written by its import step)."""
        if self.calibration_source == "replay":
            # and the runs' canonical logs, which the fit replays as the replay's simulate jobs do
            return {
                "windows": f"{self.replay}/turning/windows.csv",
                "calibration_split": f"{self.cal_dir}/split.csv",
                "logs": self.real_logs(self.replay_set.name),
            }
        if self.calibration_source == "own":
            # the user's logs: their steady turning windows (rule real_turning over source own), split here by
            # run as the committed segments are, and the logs the fit replays
            return {"windows": f"{self.own}/turning/windows.csv", "logs": self.real_logs("own")}
        if self.calibration_source == "drive":
            from simpick.sources import module as source_module

            # and the case and wheels tables, which the fit's step replays read as DRIVE's replay does
            root = source_module("drive").root(self.settings)
            return {"steps": f"{root}/steps.csv", "cases": f"{root}/cases.csv", "wheels": f"{root}/wheels.parquet"}
        return {"segments": self.settings.real_data.segments}

    def simulator_split_params(self) -> dict:
        """Rule simulator_split's params: the calibration's test share and seed."""
        cal = self.settings.calibration
        return {"test_fraction": float(cal.test_fraction), "seed": int(cal.seed)}

    def simulator_calibrate_params(self, simulator: str) -> dict:
        """Rule simulator_calibrate's params (simpick.studies.simulator_calibration.CalibrateParams)."""
        from simpick.plan.jobs import job_params
        from simpick.studies.simulator_calibration import CalibrateParams

        study = self.settings
        space = self.calibration_spaces.get(simulator)
        tuned = model_name(simulator, "tuned")
        data = {
            "simulator": simulator,
            "engine": engine_of(tuned),
            "robot_name": self.robot.name,
            "source": {
                "drive": f"drive-{study.drive_dataset}",
                "replay": f"replay-{self.replay_set.name if self.replay_set else ''}",
                "own": "replay-own",
            }.get(self.calibration_source, f"segments-{self.dataset}"),
            "engine_settings": self.profile_settings[tuned],
            "physics": {"timestep": study.physics.timestep},
            "robot": self._robot(),
            "statistics": study.statistics.model_dump(mode="json"),
            "seed": int(study.seed),
            "searchable": model_name(simulator, "calibrated") in self.calibrated,
            "why_not": self.calibrated_why_not.get(simulator),
            "space": space.model_dump(mode="json") if space is not None else {"searchable": False, "why_not": "-"},
            # the target's firm classes; none named: every class (calibration.target.classes)
            "classes": list(study.calibration.target.classes or study.real_data.classes),
            "grounds": {
                c: float(study.real_data.classes[c].friction)
                for c in (study.calibration.target.classes or study.real_data.classes)
            },
        }
        calibrated = model_name(simulator, "calibrated")
        if self.calibration_source in ("replay", "own"):
            from simpick.sources.base import real_params

            data["kind"] = "replay"
            data["replay_window"] = float(study.real_data.window)
            if model_name(simulator, "calibrated") in self.calibrated:
                # each class's replay simulate job's case params for the calibrated profile (its plan-time settings)
                data["replay_cases"] = {
                    c: real_params(study, calibrated, self.model_settings(calibrated), c) for c in data["grounds"]
                }
        if self.calibration_source == "drive":
            # DRIVE's sessions name their terrain in their steps table, known when the job runs: the fit pools
            # the target classes among them (every class of them where none is a target), so every class's
            # ground is given
            data["kind"] = "drive"
            data["grounds"] = {c: float(k.friction) for c, k in study.real_data.classes.items()}
            from simpick.sources import module as source_module

            drive = source_module("drive")
            data["drive_tolerance"] = float(drive.compare_settings(study)["tolerance"])
            if model_name(simulator, "calibrated") in self.calibrated:
                # DRIVE's replay params for the calibrated profile (its plan-time settings), less the session
                case = drive.case_params(study, "drive", {}, calibrated, self.model_settings(calibrated), "", [])
                data["steps_case"] = {k: v for k, v in case.items() if k != "session"}
        searchable = model_name(simulator, "calibrated") in self.calibrated
        if searchable and self.calibration_source == "segments" and "segments" in self.sources:
            # the committed segments: the fit replays the training runs' turning segments as the calibrated
            # profile's simulate job replays them (its params over every segment, its plan-time settings)
            names = [name for _, name in self.sources["segments"]["cases"]]
            data["segments_case"] = self.case_params("segments", model_name(simulator, "calibrated"), None, names)
        return job_params("simulator_calibrate", CalibrateParams, data)
