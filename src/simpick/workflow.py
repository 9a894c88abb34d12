"""What each Snakemake job does, as plain functions of paths and parameters.

``scripts/*.py`` only unpack ``snakemake.input/params/output`` and call one function here,
so every job can be run and tested without Snakemake.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from simpick.errors import InputError
from simpick.tables import write_csv
from simpick.watchdog import DEFAULT_TIMEOUT_S


def terrain_job(output: str, name: str, seed: int, spec: dict) -> None:
    from simpick import terrain
    from simpick.seeds import stable_seed

    spec = dict(spec)
    rule, friction = spec.pop("rule"), spec.pop("friction")
    tiles = int(spec.pop("tiles", terrain.TILES))
    desc = terrain.generate(name, rule, stable_seed(int(seed), "terrain", name), friction, tiles, **spec)
    Path(output).parent.mkdir(parents=True, exist_ok=True)
    terrain.save(desc, output)


# --- one simulate path for every case ----------------------------------------------------------
# A case is one row of a source's case table (simpick.sources: the lab's terrain x motion, the
# committed segments, a dataset folder's runs, the user's own logs): what is driven, never by which
# engine. Every case is stepped by simulate_job under the watchdog and written as a trace whose
# metadata names it the same way (TRACE_KEYS), whatever its source.

TRACE_KEYS = ("source", "test", "engine", "terrain", "motion", "dataset", "run", "segment", "window")


def simulate_job(outputs: list[str], urdf: str, inputs: dict, params: dict, after_hung=None) -> list[dict]:
    """A unit's cases (``params["cases"]``, one trace each in ``outputs``) on one model, each under
    the watchdog: a case still running after ``health.timeout`` s of wall time is written as a
    failed (hung) trace, and so are the unit's cases after it, which cannot run in the stopped
    process; the source's compare job lists them like any failed run. ``params["kind"]`` says how
    a case is driven (lab, segments, replay: its simpick.sources module's ``prepare_case``, imported
    by name); ``inputs`` holds the files it reads. ``after_hung``: called once the hung traces are
    written, before the process ends (a job that compares its own traces, the sweep, does so then)."""
    from simpick import sources
    from simpick.simulate import config_hash
    from simpick.traces import write_trace
    from simpick.watchdog import Watchdog

    if len(outputs) != len(params["cases"]):
        raise ValueError(f"{len(params['cases'])} cases for {len(outputs)} outputs")
    prepare = sources.module(params["kind"]).prepare_case
    units = []
    for name, output in zip(params["cases"], outputs):
        described, run = prepare(urdf, inputs, params, name)
        which = {key: None for key in TRACE_KEYS} | described | {"source": params["source"], "engine": params["engine"]}
        units.append((which, run, output))
    timeout = params["health"]["timeout"]
    done = []
    for i, (which, run, output) in enumerate(units):
        def hung(i=i):
            write_hung_trace(units[i][2], units[i][0], params, timeout)
            for later, _, path in units[i + 1:]:
                write_hung_trace(path, later, params, timeout, reason=f"not run: {units[i][0]['test']} hung before it")
            if after_hung is not None:
                after_hung()

        with Watchdog(timeout, hung):
            frame, meta = run()
        meta = meta | which | {"config_hash": config_hash(params)}
        write_trace(frame, meta, output)
        done.append(meta)
    return done


def write_hung_trace(output: str, which: dict, params: dict, timeout: float, reason: str | None = None) -> None:
    """An empty trace whose health record says the engine hung (or ``reason``), so the run is
    reported. ``which``: the metadata that names the case (TRACE_KEYS), so the job that compares
    it finds it like any other."""
    from simpick.simulate import config_hash
    from simpick.traces import COLUMNS, write_trace
    from simpick.watchdog import hung_reason

    waited = 0.0 if reason else float(timeout)  # a case not run used no time
    reason = reason or hung_reason(timeout)
    print(f"simpick: {which['engine']} {which['source']} {which['test']}: {reason}", file=sys.stderr)
    write_trace({c: [] for c in COLUMNS},
                {"engine_version": "", **which,
                 "timestep": params["physics"]["timestep"], "seed": params["seed"], "steps": 0, "sim_time": 0.0,
                 "wall_time": waited, "cpu_time": float("nan"), "real_time_factor": None,
                 "health": {"status": "failed", "reasons": [reason]}, "config_hash": config_hash(params)},
                output)


def cpu_job(output: str, terrain_file: str, urdf: str, params: dict, timeout: float = DEFAULT_TIMEOUT_S) -> None:
    """The CPU-load measurement of one engine (simpick.cpuload), under the watchdog: still running
    after ``timeout`` s of wall time (simpick.watchdog.runtime_timeout of the rule's runtime), the
    job writes :func:`simpick.cpuload.hung_result` instead, which the scores leave out and name."""
    from simpick.cpuload import hung_result, measure
    from simpick.health import HealthLimits
    from simpick.watchdog import Watchdog

    def write(result: dict) -> None:
        Path(output).parent.mkdir(parents=True, exist_ok=True)
        Path(output).write_text(json.dumps(result, indent=1))

    def hung() -> None:
        result = hung_result(params, timeout)
        print(f"simpick: cpu_load {params['engine']}: {result['health']['reasons'][0]}", file=sys.stderr)
        write(result)

    cpu = params["cpu_load"]
    with Watchdog(timeout, hung):
        result = measure(params["engine"], urdf=urdf, terrain_file=terrain_file, motion=params["motion"],
                         timestep=params["physics"]["timestep"],
                         ground_friction=params["physics"]["ground_friction"],
                         max_wheel_torque=params["robot"]["max_wheel_torque"], track=params["robot"]["track"],
                         engine_settings=params["engine_settings"], duration=cpu["duration"],
                         repeats=int(cpu["repeats"]), robots_average=int(cpu["robots_average"]),
                         robots_intense=int(cpu["robots_intense"]), spacing=cpu["spacing"],
                         robot_options=params["robot"],
                         limits=HealthLimits(**params["health"]) if params.get("health") else None)
    write(result)


# --- one compare and one summarise step for every source --------------------------------------

def compare_job(kind: str, traces: list[str], inputs: dict, params: dict, outputs: dict[str, str]) -> None:
    """One source's traces against what they are compared with, by its kind's module (simpick.sources,
    imported by name: a job of one kind runs no other's comparison): the paper's reference statistics
    (lab), each segment's real window statistics (segments), the real log window by window
    (replay). Writes ``per_test`` (Eq. 7 per model and test: what scores and summaries use),
    ``detail`` (the rows a test's error sums: per axis, or per window for a replay) and ``runs``
    (each trace's timing and health)."""
    from simpick import sources

    per_test, detail, runs = sources.module(kind).compare(traces, inputs, params)
    write_csv(per_test, outputs["per_test"])
    write_csv(detail, outputs["detail"])
    write_csv(runs, outputs["runs"])


def summarise_job(per_test: str, runs: str, params: dict, outputs: dict[str, str]) -> None:
    """A source's per-test rows summed and summarised (:func:`source_tables`), each table written
    to its ``outputs`` entry."""
    import pandas as pd

    tests = pd.read_csv(per_test, dtype={"run": str, "test": str})
    run_table = pd.read_csv(runs, dtype={"terrain": str, "motion": str, "test": str})
    for name, table in source_tables(tests, run_table, params["group"], params.get("statistics")).items():
        write_csv(table, outputs[name])


def source_tables(tests, run_table, group: str, statistics: dict | None = None) -> dict:
    """A source's per-test rows (its compare job's ``per_test``) and run rows (``runs``) summed and
    summarised, the same way for every source and for the sweep at each timestep (simpick.sweep):
    Eq. 7 totals over the tests every model completed (``imu_errors``), the real-time factor over
    the tests every model ran healthily (``rtf``), per model and ``group`` (terrain or terrain
    class) means with intervals and paired verdicts over independent runs (``summary``,
    ``pairwise``: simpick.realdata.summary_table, pairwise_table)."""
    from simpick import metrics
    from simpick.realdata import pairwise_table, summary_table

    return {"imu_errors": metrics.eq7_totals(tests, engines=run_table.engine.unique()),
            "rtf": equal_rtf(run_table),
            "summary": summary_table(tests, group, statistics),
            "pairwise": pairwise_table(tests, group, statistics)}


def equal_rtf(runs) -> "pd.DataFrame":
    """Eq. 2 per engine over the same tests for every engine: a test any engine failed is left
    out for all (an engine failing the slowest terrain would otherwise look faster) and named
    in ``excluded``; an engine with no run of a test leaves that test out too."""
    import pandas as pd

    from simpick import metrics

    if "test" not in runs:  # a run table without the test column (TRACE_KEYS) names it by terrain/motion
        runs = runs.assign(test=runs.terrain + "/" + runs.motion)
    runs = runs.assign(test=runs.test.astype(str))
    engines = sorted(runs.engine.unique())
    ok = runs[runs.status == "ok"]
    common = set.intersection(*(set(ok[ok.engine == e].test) for e in engines)) if engines else set()
    excluded = ";".join(sorted(set(runs.test) - common))
    rows = []
    for engine in engines:
        g = ok[(ok.engine == engine) & ok.test.isin(common)]
        rows.append({"engine": engine, "sim_time": g.sim_time.sum(), "wall_time": g.wall_time.sum(),
                     "real_time_factor": (metrics.real_time_factor(g.sim_time, g.wall_time) if len(g)
                                          else float("nan")),
                     "n_runs": len(g), "tests": ";".join(sorted(common)), "excluded": excluded})
    return pd.DataFrame(rows, columns=["engine", "sim_time", "wall_time", "real_time_factor", "n_runs", "tests",
                                       "excluded"])


def scores_job(engines: list[str], imu_errors: str, rtf: str, cpu_files: list[str], qualitative: str,
               weights: dict, outputs: dict[str, str], sources: dict | None = None) -> None:
    """The scores and the weighted table; with ``outputs["provenance"]`` also the record of what
    they rest on (:func:`score_provenance`; ``sources`` as it describes), which the report reads
    instead of working it out again."""
    import pandas as pd
    import yaml

    from simpick import scoring

    try:
        facts = yaml.safe_load(Path(qualitative).read_text())
    except (OSError, yaml.YAMLError) as exc:
        raise InputError(qualitative, f"cannot read qualitative facts: {exc}") from None
    missing = [e for e in engines if e not in (facts or {})]
    if missing:
        raise InputError(qualitative, f"no facts for engines {missing}", "add a record per engine")
    rows = {}
    for engine in engines:
        try:
            rows[engine] = scoring.qualitative_scores(facts[engine])
        except ValueError as exc:
            raise InputError(f"{qualitative}: {engine}", str(exc)) from None

    rtf_frame = pd.read_csv(rtf).set_index("engine")
    errors = pd.read_csv(imu_errors)
    cpu = {c["engine"]: c for c in (json.loads(Path(f).read_text()) for f in cpu_files)}
    # a CPU run that failed its health check is not a load to compare: that engine's score is NaN
    # (listed as excluded in the weighted table), the others are scored among themselves
    cpu = {e: c for e, c in cpu.items() if (c.get("health") or {}).get("status", "ok") == "ok"}

    def column(values: dict) -> dict:
        return {e: values.get(e, float("nan")) for e in engines}

    quantitative = {
        "real_time_factor": scoring.real_time_factor_scores(column(rtf_frame.real_time_factor.to_dict())),
        "cpu_average": scoring.efficiency_scores(column({e: c["average"]["load_percent"] for e, c in cpu.items()})),
        "cpu_intense": scoring.efficiency_scores(column({e: c["intense"]["load_percent"] for e, c in cpu.items()})),
    }
    for quantity in ("angular", "linear"):
        q = errors[errors.quantity == quantity].set_index("engine").error.to_dict()
        quantitative[f"imu_{quantity}"] = scoring.accuracy_scores(column(q))
    for metric, values in quantitative.items():
        for engine in engines:
            rows[engine][metric] = values.get(engine, float("nan"))
    scores = pd.DataFrame.from_dict(rows, orient="index")[list(scoring.METRICS)]
    scores.index.name = "engine"
    write_csv(scores, outputs["scores"], index=True)
    write_csv(scoring.weighted_table(scores, weights), outputs["weighted"], index=True)
    if outputs.get("provenance"):
        record = score_provenance(engines, imu_errors, rtf, cpu_files, sources or {})
        Path(outputs["provenance"]).write_text(yaml.safe_dump(record, sort_keys=False))


def _failures(path: str | None) -> dict[str, list[str]]:
    """test -> "model: reasons" of every run in a per-test table (the lab runs.csv or a real-data
    *_per_test.csv) that did not finish healthily."""
    import pandas as pd

    if not path:
        return {}
    frame = pd.read_csv(path, dtype=str, keep_default_na=False)
    tests = frame["segment"] if "segment" in frame else frame["terrain"] + "/" + frame["motion"]
    out: dict[str, list[str]] = {}
    for test, row in zip(tests, frame.to_dict("records")):
        if row.get("status", "ok") != "ok":
            out.setdefault(test, []).append(f"{row['engine']} {row['status']}: {row.get('reasons') or 'no reason given'}")
    return out


def _split(cells) -> list[str]:
    return sorted({t for cell in cells for t in str(cell).split(";") if t.strip() and t != "nan"})


def score_provenance(engines: list[str], imu_errors: str, rtf: str, cpu_files: list[str], sources: dict) -> dict:
    """What the scores rest on, as results/scores/provenance.yaml records it: the errors file of
    the accuracy scores, its tests and the tests left out (a test any model failed is left out
    for all: metrics.eq7_totals) with the failures that left each out; the same for the
    real-time factor (equal_rtf); which engines' CPU runs were scored and why the others were not.

    ``sources``: ``accuracy`` (``reference``, ``set``: lab, segments, replay or own, ``dataset``),
    ``accuracy_tests`` (the per-test table beside the errors file), ``runs`` (the lab runs.csv)
    and ``cpu_test`` (the CPU runs' terrain/motion); each optional."""
    import pandas as pd

    errors = pd.read_csv(imu_errors, dtype=str, keep_default_na=False)
    errors = errors[errors.engine.isin(engines)]
    why = _failures(sources.get("accuracy_tests"))
    lab_why = _failures(sources.get("runs"))

    def left_out(tests: list[str], reasons: dict) -> list[dict]:
        return [{"test": t, "why": "; ".join(reasons.get(t) or ["not completed by every model"])} for t in tests]

    rtf_frame = pd.read_csv(rtf, dtype=str, keep_default_na=False)
    cpu = [json.loads(Path(f).read_text()) for f in cpu_files]
    failed_cpu = [c for c in cpu if (c.get("health") or {}).get("status", "ok") != "ok"]
    return {
        "accuracy": {
            **dict(sources.get("accuracy") or {}),
            "errors_file": str(imu_errors),
            "per_test_file": sources.get("accuracy_tests"),
            "engines": list(engines),
            "tests": _split(errors.get("tests", [])),
            "excluded": left_out(_split(errors.get("excluded", [])), why),
        },
        "real_time_factor": {
            "file": str(rtf),
            "tests": _split(rtf_frame.get("tests", [])),
            "excluded": left_out(_split(rtf_frame.get("excluded", [])), lab_why),
        },
        "cpu": {
            "files": [str(f) for f in cpu_files],
            "test": sources.get("cpu_test"),
            "engines": sorted(c["engine"] for c in cpu if c not in failed_cpu),
            "excluded": [{"engine": c["engine"], "why": "; ".join(c["health"].get("reasons") or ["failed"])}
                         for c in failed_cpu],
        },
    }


def published_job(published_file: str, outdir: str) -> None:
    from simpick.published import load_published, write_outputs

    write_outputs(load_published(published_file), outdir)


class logged:
    """Send a job's stderr to its log; report a bad input as one clear line, not a traceback."""

    def __init__(self, log_path: str):
        self.log_path = Path(log_path)

    def __enter__(self):
        import sys

        self.log_path.parent.mkdir(parents=True, exist_ok=True)
        self._stderr = sys.stderr
        sys.stderr = self.log_path.open("w")
        return self

    def __exit__(self, exc_type, exc, tb):
        import sys

        log, sys.stderr = sys.stderr, self._stderr
        if exc_type is not None and issubclass(exc_type, InputError):
            print(f"simpick: {exc}", file=log)
            print(f"simpick: {exc}", file=sys.stderr)
            log.close()
            raise SystemExit(1)
        if exc_type is not None:
            import traceback

            traceback.print_exception(exc_type, exc, tb, file=log)
        log.close()
        return False
