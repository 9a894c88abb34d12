"""The workflow's validation job: every case of one engine in one process, each under the watchdog,
one record per case."""

from __future__ import annotations

import json
import sys
import time
import traceback
from pathlib import Path

from simpick.engines import get_engine
from simpick.errors import InputError
from simpick.inputs.robot import load_from_config
from simpick.simulate.watchdog import DEFAULT_TIMEOUT_S, Watchdog, hung_reason
from simpick.studies.validation.cases import Setup, failed_record, run_case


def validate_job(outputs: list[str], urdf: str | Path, params: dict, timeout: float = DEFAULT_TIMEOUT_S) -> list[dict]:
    """The workflow's per-engine job: every case of ``params["cases"]`` on one engine in one process
    (the robot and the engine's module are loaded once), one JSON record per case in ``outputs``
    (``.../{case}.json``), in the order of ``params["cases"]``.

    ``timeout``: the job's hang limit in s of wall time (simpick.simulate.watchdog.runtime_timeout of the rule's
    runtime), shared evenly by its cases: each case runs under the watchdog with ``timeout / cases``. A
    case still running then is recorded as failed (hung) and the cases after it, which cannot run in the
    stopped process, as failed (not run), so the summary lists every case. A case whose engine raises is
    recorded as failed with the error (the traceback goes to the job's log) and the next case runs; a bad
    case kind (InputError) still stops the job."""
    cases = params["cases"]
    paths = {Path(p).stem: Path(p) for p in outputs}
    if sorted(paths) != sorted(cases):
        raise ValueError(f"validate_job: outputs for {sorted(paths)}, cases {sorted(cases)}")
    setup = Setup(
        engine=params["engine"],
        robot=load_from_config({**params["robot"], "urdf": urdf}),
        timestep=params["physics"]["timestep"],
        max_wheel_torque=params["robot"]["max_wheel_torque"],
        track=params["robot"]["track"],
        settings=params["engine_settings"],
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
        _write_record(paths[name], result)
        results.append(result)
    return results


def _write_record(path: Path, result: dict) -> None:
    """Atomically: a killed job leaves a temp file, never a truncated record."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".partial")
    tmp.write_text(json.dumps(result, indent=1, sort_keys=True, allow_nan=True))
    tmp.replace(path)
