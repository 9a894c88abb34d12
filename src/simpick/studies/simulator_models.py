"""The models a user opens as they are (rule simulator_models): each profile of a simulator that has a model writer
(:data:`simpick.engines.simulator_models.WRITERS`) as the robot on flat ground in that simulator's own format, headed
by the profile, where its values come from and the yaw-rate gains simpick's validation measures on it.

The gains are the validation's own: each claimed case (:func:`claimed_cases`) is run by
:func:`simpick.studies.validation.cases.run_case`, the function the validate job calls, on the model's settings, so a
profile's claim is the value its validate record holds for that case (a run is deterministic in its settings), and a
calibrated terrain class's model, which the validation does not run, is measured the same way. Nothing here reads a
written model back: tests/test_simulator_models.py (and test_gazebo_models.py, test_drake_models.py) open each with the
simulator's own loader alone and measure the same gains there; where no loader of the simulator installs here (Gazebo
Classic, Webots: the writer's ``opened_here``), tests/test_classic_models.py checks the file's fields against the
catalog's quoted values and the robot instead, and tests/test_vendor_models.py the keywords of the Python set-ups of
Isaac Lab and CoppeliaSim and of MORSE's builder script against their quoted names and the profile's values.
"""

from __future__ import annotations

import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pydantic import Field

from simpick.engines.simulator_models import WRITERS, TurningClaim
from simpick.engines.simulators import engine_of, split
from simpick.inputs.robot.settings import RobotParams
from simpick.params import JobParams, PhysicsStep, Positive
from simpick.score.simulator_settings import calibrated_settings, class_files, class_settings, read_fits, settings_text
from simpick.studies.validation.cases import Setup, run_case
from simpick.studies.validation.measures import DEFAULT_HEADING
from simpick.studies.validation.settings import ValidationCase

# no double hyphen: the line heads XML comments
REGENERATE = "regenerate: snakemake -c 2 results/simulators/models (docs/simulators.md)"


class ModelProfile(JobParams):
    """A profile as its model's job reads it."""

    settings: dict[str, Any] = Field(
        description="its adapter's settings in full (a calibrated profile: its tuned profile's; the job merges the fit)"
    )
    label: str = Field(description="the simulator's name in the catalog")
    basis: str = Field(description="where the profile's values come from (the catalog's basis of the profile)")


class SimulatorModelsParams(JobParams):
    """What rule simulator_models' job reads: the profiles that get a model, the robot, the step, the ground and
    the validation cases whose gains the models claim (not the tolerances or any weight)."""

    profiles: dict[str, ModelProfile] = Field(description="profile -> its settings and where they come from")
    robot: RobotParams
    physics: PhysicsStep
    ground_mu: Positive = Field(description="the models' ground friction (the settings files' ground)")
    cases: dict[str, ValidationCase] = Field(description="the turning cases each model claims (claimed_cases)")


def claimed_cases(cases: Mapping[str, ValidationCase], ground_mu: float) -> dict[str, ValidationCase]:
    """The validation's turning cases a model on flat ground of friction ``ground_mu`` claims the gain of: yaw_gain
    at that friction from heading 0 (the model's own pose), with the profile's own friction ratio (a case that sets
    its own runs other settings than the file's)."""
    return {
        name: case
        for name, case in cases.items()
        if case.kind == "yaw_gain"
        and case.mu == ground_mu
        and case.heading == DEFAULT_HEADING
        and case.friction_ratio is None
    }


def turning_claims(setup: Setup, cases: Mapping[str, ValidationCase]) -> list[TurningClaim]:
    """Each case's gain on ``setup`` as the validation measures it (run_case); a case that fails is not claimed."""
    claims = []
    for name, case in cases.items():
        record = run_case(setup, name, case)
        if record["status"] != "ok" or not record["checks"]:
            print(f"simpick: {setup.engine}: {name} not claimed: {'; '.join(record['reasons'])}", file=sys.stderr)
            continue
        check = record["checks"][0]
        duration = round(record["sim_time"], 9)
        claims.append(TurningClaim(name, check["v"], check["w"], duration, check["engine_value"]))
    return claims


def _models(profile: str, entry: ModelProfile, fit: dict | None, robot: str) -> list[tuple[str, dict, list[str]]]:
    """(file stem, settings, header lines: what the model is and where its values come from) of a profile's models:
    one, and for a calibrated profile (its tuned settings with its fit over them) one more per terrain class whose
    own fit has a settings file (simpick.score.simulator_settings.class_files); none for a calibrated profile
    without its fit."""
    simulator, variant = split(profile)

    def head(stem: str, cls: str = "") -> str:
        fitted = f", fitted for {cls}," if cls else ""
        return (
            f"simpick model: {robot} in {entry.label}, {variant} profile{fitted} on flat ground ({stem}): robot, "
            "actuators, contacts, ground and options"
        )

    if variant != "calibrated":
        return [(profile, entry.settings, [head(profile), f"values: {entry.basis}"])]
    if fit is None:
        return []
    fitted = ", ".join(f"{k} = {v}" for k, v in (fit.get("settings") or {}).items()) or "nothing fitted"
    values = (
        f"values: {entry.basis}; over it the fit (results/simulators/calibration/{simulator}.yaml, fitted on "
        f"{fit.get('source')}): {fitted}"
    )
    per_class = class_files(fit)
    out = []
    for tail, settings in calibrated_settings(engine_of(profile), entry.settings, fit).items():
        if not tail:
            out.append((profile, settings, [head(profile), values]))
            continue
        cls = tail.removeprefix("-")
        own = f"; and {cls}'s own {settings_text(class_settings(per_class[cls]))}, fitted on its training runs"
        out.append((profile + tail, settings, [head(profile + tail, cls), values + own]))
    return out


def simulator_models_job(inputs: Mapping[str, Any], params: dict, output: str) -> dict[str, list[TurningClaim]]:
    """results/simulators/models/: each profile's model (:class:`SimulatorModelsParams`), named by the profile (a
    calibrated terrain class's: ``<profile>-<class>``) with its format's suffixes (a model of several files: one
    per suffix); returns each model's claims."""
    p = SimulatorModelsParams.model_validate(params)
    urdf = inputs["urdf"]
    robot = p.robot.spec(urdf)
    fits = read_fits(dict(inputs))
    out = Path(output)
    out.mkdir(parents=True, exist_ok=True)
    written = {}
    for profile, entry in p.profiles.items():
        engine = engine_of(profile)
        write = WRITERS[split(profile)[0]].write
        for stem, settings, header in _models(profile, entry, fits.get(split(profile)[0]), robot.name):
            setup = Setup(
                engine=engine,
                robot=robot,
                timestep=p.physics.timestep,
                max_wheel_torque=p.robot.max_wheel_torque,
                track=p.robot.track,
                settings=settings,
            )
            claims = turning_claims(setup, p.cases)
            files = write(
                urdf,
                settings,
                p.ground_mu,
                [*header, REGENERATE],
                robot=p.robot,
                timestep=p.physics.timestep,
                claims=claims,
                name=f"{robot.name} ({stem})",
                stem=stem,
            )
            for tail, text in files.items():  # the file named <stem>.<suffix> (the plan's model_files) opens it
                (out / f"{stem}.{tail}").write_text(text)
            written[stem] = claims
            print(f"simpick: {stem}: " + ", ".join(f"{c.case} {c.gain:.4f}" for c in claims), file=sys.stderr)
    return written
