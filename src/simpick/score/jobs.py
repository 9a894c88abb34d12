"""The score stage's jobs: the paper's scores and weighted table, and the record of what they rest on;
the paper's own published tables recomputed (Table 11).
"""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import yaml

from simpick.errors import InputError
from simpick.inputs.published import load_published
from simpick.score import scoring
from simpick.score.contributions import contributions, drivers
from simpick.score.published import write_outputs
from simpick.tables import write_csv


def scores_job(
    engines: list[str],
    imu_errors: str,
    rtf: str,
    cpu_files: list[str],
    qualitative: str,
    weights: dict | None,
    outputs: dict[str, str],
    sources: dict | None = None,
) -> None:
    """The paper's per-metric scores (``outputs["scores"]``), which read no weight; with
    ``outputs["weighted"]`` also the weighted table (:func:`weigh`), and with ``outputs["provenance"]``
    the record of what the scores rest on (:func:`score_provenance`; ``sources`` as it describes),
    which the report reads instead of working it out again. The workflow writes the scores and the
    record in one job (rule scores), which no weight edit reruns, and weighs them in another (rule
    weighted, :func:`weighted_job`)."""
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
    if outputs.get("weighted"):
        weigh(scores, weights or {}, outputs)
    if outputs.get("provenance"):
        record = score_provenance(engines, imu_errors, rtf, cpu_files, sources or {})
        Path(outputs["provenance"]).write_text(yaml.safe_dump(record, sort_keys=False))


def weigh(scores: pd.DataFrame, weights: dict, outputs: dict[str, str]) -> None:
    """The weighted table of ``scores`` (engine x metric) into ``outputs["weighted"]``; with
    ``outputs["contributions"]`` also each weight x score and what puts the leader ahead
    (``outputs["drivers"]``)."""
    weighted = scoring.weighted_table(scores, weights)
    write_csv(weighted, outputs["weighted"], index=True)
    if outputs.get("contributions"):
        contribution = contributions(weighted, weights)
        write_csv(contribution, outputs["contributions"])
        write_csv(drivers(contribution), outputs["drivers"])


def weighted_job(scores: str, weights: dict, outputs: dict[str, str]) -> None:
    """The weighted table, its contributions and drivers from the scores job's table (rule weighted):
    all a weight edit recomputes of the scores."""
    table = pd.read_csv(scores, index_col="engine")
    weigh(table, weights, outputs)


def _failures(path: str | None) -> dict[str, list[str]]:
    """test -> "model: reasons" of every run in a per-test table (the lab runs.csv or a real-data
    *_per_test.csv) that did not finish healthily."""
    if not path:
        return {}
    frame = pd.read_csv(path, dtype=str, keep_default_na=False)
    tests = frame["segment"] if "segment" in frame else frame["terrain"] + "/" + frame["motion"]
    out: dict[str, list[str]] = {}
    for test, row in zip(tests, frame.to_dict("records")):
        if row.get("status", "ok") != "ok":
            out.setdefault(test, []).append(
                f"{row['engine']} {row['status']}: {row.get('reasons') or 'no reason given'}"
            )
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
            "excluded": [
                {"engine": c["engine"], "why": "; ".join(c["health"].get("reasons") or ["failed"])} for c in failed_cpu
            ],
        },
    }


def published_job(published_file: str, outdir: str) -> None:
    """The paper's Table 11 recomputed from its own figures, the comparison with the printed scores
    and the worked example of Eq. 7 (simpick.score.published)."""
    write_outputs(load_published(published_file), outdir)
