"""What each Snakemake job does, as plain functions of paths and parameters.

``scripts/*.py`` only unpack ``snakemake.input/params/output`` and call one function here,
so every job can be run and tested without Snakemake.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import yaml

from simpick.errors import InputError


def write_csv(frame, path: str | Path, index: bool = False) -> None:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    frame.to_csv(path, index=index, float_format="%.6g")


def terrain_job(output: str, name: str, seed: int, spec: dict) -> None:
    from simpick import terrain
    from simpick.simulate import stable_seed

    spec = dict(spec)
    rule, friction = spec.pop("rule"), spec.pop("friction")
    tiles = int(spec.pop("tiles", 4))
    desc = terrain.generate(name, rule, stable_seed(int(seed), "terrain", name), friction, tiles, **spec)
    Path(output).parent.mkdir(parents=True, exist_ok=True)
    terrain.save(desc, output)


def simulate_job(output: str, terrain_file: str, urdf: str, params: dict) -> dict | None:
    from simpick.health import HealthLimits
    from simpick.imu import ImuModel
    from simpick.simulate import Case, simulate_to_file
    from simpick.watchdog import Watchdog

    motion = params["motion"]
    case = Case(engine=params["engine"], terrain=params["terrain"], motion=params["motion_name"],
                v=motion["v"], w=motion["w"], duration=motion["duration"], start=tuple(motion["start"]))
    timeout = params["health"]["timeout"]
    which = {"engine": case.engine, "terrain": case.terrain, "motion": case.motion}
    with Watchdog(timeout, lambda: write_hung_trace(output, which, params, timeout)):
        return simulate_to_file(
            case, output, params=params, urdf=urdf, terrain_file=terrain_file,
            track=params["robot"]["track"], max_wheel_torque=params["robot"]["max_wheel_torque"],
            timestep=params["physics"]["timestep"], ground_friction=params["physics"]["ground_friction"],
            engine_settings=params["engine_settings"], imu=ImuModel(**params["imu"]),
            seed=int(params["seed"]), limits=HealthLimits(**params["health"]))


def write_hung_trace(output: str, which: dict, params: dict, timeout: float) -> None:
    """An empty trace whose health record says the engine hung, so the run is reported.
    ``which``: the metadata that names the run (engine, terrain, motion and, for a replay, its
    run and dataset), so the job that compares it finds it like any other."""
    from simpick.simulate import config_hash
    from simpick.traces import COLUMNS, write_trace

    reason = f"hung: no result after {timeout:g} s of wall time; the job was stopped"
    print(f"simpick: {which['engine']} {which['terrain']}/{which['motion']}: {reason}", file=sys.stderr)
    write_trace({c: [] for c in COLUMNS},
                {"engine_version": "", **which,
                 "timestep": params["physics"]["timestep"], "seed": params["seed"], "steps": 0, "sim_time": 0.0,
                 "wall_time": float(timeout), "cpu_time": float("nan"), "real_time_factor": None,
                 "health": {"status": "failed", "reasons": [reason]}, "config_hash": config_hash(params)},
                output)


def cpu_job(output: str, terrain_file: str, urdf: str, params: dict) -> None:
    from simpick.cpuload import measure
    from simpick.health import HealthLimits

    cpu = params["cpu_load"]
    result = measure(params["engine"], urdf=urdf, terrain_file=terrain_file, motion=params["motion"],
                     timestep=params["physics"]["timestep"],
                     ground_friction=params["physics"]["ground_friction"],
                     max_wheel_torque=params["robot"]["max_wheel_torque"], track=params["robot"]["track"],
                     engine_settings=params["engine_settings"], duration=cpu["duration"],
                     repeats=int(cpu["repeats"]), robots_average=int(cpu["robots_average"]),
                     robots_intense=int(cpu["robots_intense"]), spacing=cpu["spacing"],
                     limits=HealthLimits(**params["health"]) if params.get("health") else None)
    Path(output).parent.mkdir(parents=True, exist_ok=True)
    Path(output).write_text(json.dumps(result, indent=1))


def metrics_job(traces: list[str], published_file: str, outputs: dict[str, str]) -> None:
    """Per-trace statistics, errors against the real reference, run table, real-time factors."""
    import pandas as pd

    from simpick import metrics
    from simpick.published import load_published
    from simpick.reference import lab_reference
    from simpick.traces import read_trace

    reference = lab_reference(load_published(published_file))
    stats_rows, error_rows, runs = [], [], []
    for path in traces:
        frame, meta = read_trace(path)
        key = (meta["engine"], meta["terrain"], meta["motion"])
        health = meta["health"]
        runs.append({"engine": key[0], "terrain": key[1], "motion": key[2], "sim_time": meta["sim_time"],
                     "wall_time": meta["wall_time"], "cpu_time": meta["cpu_time"], "steps": meta["steps"],
                     "steps_per_s": meta["steps"] / meta["wall_time"],
                     "real_time_factor": meta["real_time_factor"], "status": health["status"],
                     "reasons": "; ".join(health["reasons"]), "engine_version": meta["engine_version"],
                     "config_hash": meta["config_hash"]})
        if health["status"] != "ok":
            continue
        stats = metrics.trace_stats(frame)
        for quantity, axes in stats.items():
            for axis, s in axes.items():
                stats_rows.append({"engine": key[0], "terrain": key[1], "motion": key[2], "quantity": quantity,
                                   "axis": axis, "mean": s["mean"], "range": s["range"], "status": "ok"})
            ref = reference.get(key[1:])
            if ref is None:
                continue
            for axis, e in metrics.axis_errors(axes, ref[quantity]).items():
                error_rows.append({"engine": key[0], "terrain": key[1], "motion": key[2],
                                   "quantity": quantity, "axis": axis, **e})
    runs = pd.DataFrame(runs)
    for _, run in runs[runs.status != "ok"].iterrows():
        for quantity in ("angular", "linear"):
            for axis in metrics.AXES:
                stats_rows.append({"engine": run.engine, "terrain": run.terrain, "motion": run.motion,
                                   "quantity": quantity, "axis": axis, "mean": float("nan"),
                                   "range": float("nan"), "status": "failed"})
    per_test = pd.DataFrame(error_rows, columns=["engine", "terrain", "motion", "quantity", "axis",
                                                 "range_error", "mean_error", "total_error"])

    ref_rows = [{"terrain": t, "motion": m, "quantity": q, "axis": a, **s, "source": ref["source"]}
                for (t, m), ref in reference.items() for q in ("angular", "linear") for a, s in ref[q].items()]

    # Eq. 7 per test from the per-axis rows; failed runs of referenced tests count as failed
    columns = ["engine", "test", "status", "error_angular", "error_linear"]
    ok_tests = [{"engine": e, "test": f"{t}/{m}", "status": "ok",
                 **{f"error_{q}": g[g.quantity == q].total_error.sum() for q in ("angular", "linear")}}
                for (e, t, m), g in per_test.groupby(["engine", "terrain", "motion"])]
    failed = [{"engine": r.engine, "test": f"{r.terrain}/{r.motion}", "status": "failed"}
              for r in runs[runs.status != "ok"].itertuples() if (r.terrain, r.motion) in reference]
    error_summary = metrics.eq7_totals(pd.DataFrame(ok_tests + failed, columns=columns), engines=runs.engine.unique())

    rtf = equal_rtf(runs)

    write_csv(pd.DataFrame(stats_rows), outputs["trace_stats"])
    write_csv(pd.DataFrame(ref_rows), outputs["reference_stats"])
    write_csv(per_test, outputs["per_test_errors"])
    write_csv(error_summary, outputs["imu_errors"])
    write_csv(runs, outputs["runs"])
    write_csv(rtf, outputs["rtf"])


def equal_rtf(runs) -> "pd.DataFrame":
    """Eq. 2 per engine over the same tests for every engine: a test any engine failed is left
    out for all (an engine failing the slowest terrain would otherwise look faster) and named
    in ``excluded``; an engine with no run of a test leaves that test out too."""
    import pandas as pd

    from simpick import metrics

    runs = runs.assign(test=runs.terrain + "/" + runs.motion)
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
