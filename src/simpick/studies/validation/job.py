"""The workflow's validation job: every case of one engine in one process, each under the watchdog,
one record per case."""

from __future__ import annotations

import json
import sys
import time
import traceback
from pathlib import Path
from typing import Any

from pydantic import Field

from simpick.engines import get_engine
from simpick.errors import InputError
from simpick.inputs.robot.settings import RobotParams
from simpick.params import JobParams, PhysicsStep
from simpick.simulate.watchdog import DEFAULT_TIMEOUT_S, Watchdog, hung_reason
from simpick.studies.validation.cases import Setup, failed_record, run_case
from simpick.studies.validation.settings import ValidationCase


class ValidateParams(JobParams):
    """What rule validate's job reads: the model, its settings, the robot, the timestep and every case (not the
    IMU model, the health limits or the tolerances, so editing those reruns no engine's validation)."""

    engine: str
    engine_settings: dict[str, Any] = Field(
        description="the model's settings as the config gives them; its adapter's own settings model checks them "
        "(the config's engines block at planning time, the adapter in the job)"
    )
    physics: PhysicsStep
    robot: RobotParams
    cases: dict[str, ValidationCase] = Field(description="case name -> its kind and settings, in the config's order")


def validate_job(
    outputs: list[str],
    urdf: str | Path,
    params: dict,
    timeout: float = DEFAULT_TIMEOUT_S,
    calibrated: str | None = None,
) -> list[dict]:
    """The workflow's per-engine job: every case of ``params`` (:class:`ValidateParams`) on one engine in one
    process (the robot and the engine's module are loaded once), one JSON record per case in ``outputs``
    (``.../{case}.json``), in the order of its cases.

    ``timeout``: the job's hang limit in s of wall time (simpick.simulate.watchdog.runtime_timeout of the rule's
    runtime), shared evenly by its cases: each case runs under the watchdog with ``timeout / cases``. A
    case still running then is recorded as failed (hung) and the cases after it, which cannot run in the
    stopped process, as failed (not run), so the summary lists every case. A case whose engine raises is
    recorded as failed with the error (the traceback goes to the job's log) and the next case runs; a bad
    case (its model refuses it) still stops the job.

    ``calibrated``: a calibrated profile's fit (simpick.studies.simulator_calibration), whose settings are merged
    over the params' and recorded in every record."""
    from simpick.simulate.calibrated import with_calibrated

    params, provenance = with_calibrated(params, calibrated)
    p = ValidateParams.model_validate(params)
    cases = p.cases
    paths = {Path(p).stem: Path(p) for p in outputs}
    if sorted(paths) != sorted(cases):
        raise ValueError(f"validate_job: outputs for {sorted(paths)}, cases {sorted(cases)}")
    setup = Setup(
        engine=p.engine,
        robot=p.robot.spec(urdf),
        timestep=p.physics.timestep,
        max_wheel_torque=p.robot.max_wheel_torque,
        track=p.robot.track,
        settings=p.engine_settings,
    )
    version = get_engine(setup.engine).version()  # before any case: the watchdog's records need it
    limit = float(timeout) / len(cases)
    names = list(cases)

    def failed(name: str, reason: str, wall: float = 0.0) -> dict:
        print(f"simpick: validate {setup.engine} {name}: {reason}", file=sys.stderr)
        return failed_record(setup, version, name, cases[name], reason, wall)

    results = []
    for i, name in enumerate(names):

        def hung(i: int = i) -> None:
            _write_record(paths[names[i]], failed(names[i], hung_reason(limit), limit))
            for later in names[i + 1 :]:
                _write_record(paths[later], failed(later, f"not run: {names[i]} hung before it"))

        start = time.perf_counter()
        with Watchdog(limit, hung):
            try:
                result = run_case(setup, name, cases[name])
            except InputError:
                raise
            except Exception as exc:  # noqa: BLE001 - recorded as the case's failure; the others run on
                traceback.print_exc()
                result = failed(name, f"crashed: {type(exc).__name__}: {exc}", time.perf_counter() - start)
        result = result | provenance
        _write_record(paths[name], result)
        results.append(result)
    return results


def _write_record(path: Path, result: dict) -> None:
    """Atomically: a killed job leaves a temp file, never a truncated record."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".partial")
    tmp.write_text(json.dumps(result, indent=1, sort_keys=True, allow_nan=True))
    tmp.replace(path)
