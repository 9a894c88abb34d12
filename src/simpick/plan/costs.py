"""What a job of the study costs, per kind of job and model, measured in a finished study (its Snakemake
``benchmark:`` files), and the scheduling priority that follows from it.

With 2 cores, a study whose long jobs (DART, Drake, Newton and Genesis validation, CPU load and replay jobs)
start last ends with one core idle while the other finishes them. Snakemake starts the ready job of highest
``priority:`` first; the priority of a job is its measured wall time in seconds (longest first is the classic
rule for packing jobs onto a few machines), so the cost table is the only input and no figure is guessed.

The table (``resources/engines/job_costs.csv``, written by ``bench/job_costs.py`` from a study's
``results/benchmarks/``): one row per kind of job and model, the median wall time of its jobs in that study,
how many were measured and how many cases (traces) a measured job ran (its median). A simulate job runs
several cases (simpick.plan.sources.BATCHED), and how many changes with the study: its priority is the
measured cost of one case, ``wall_s / cases``, times its own cases. A model or kind the table lacks gets
priority 0: it starts after every measured job of the same readiness, and the packing measurement
(``bench/packing.py``) shows what it costs.
"""

from __future__ import annotations

import csv
import statistics
from pathlib import Path

# kind of job -> the benchmark files of one model (relative to results/benchmarks, {engine} filled in)
KINDS = {
    "validate": "validate/{engine}.tsv",
    "cpu_load": "cpu_load/{engine}.tsv",
    "lab": "simulate/lab/{engine}/*.tsv",  # a job per engine and terrain
    "segments": "simulate/segments/{engine}.tsv",  # a job per model
    # a dataset folder's replay (--config borealtc_dir=PATH; a job per run): the BorealTC folder's
    "replay": "simulate/borealtc/{engine}/*/*.tsv",
    # a DRIVE folder's replay (--config drive_dir=PATH; a job per model and session)
    "drive_replay": "drive/*/replay/{engine}/*.tsv",
}
COLUMNS = ("job", "engine", "wall_s", "jobs", "cases")


def _wall_seconds(path: Path) -> float | None:
    """The wall seconds of a Snakemake benchmark file (its last line: the last run), None if unreadable."""
    with path.open() as handle:
        rows = list(csv.DictReader(handle, delimiter="\t"))
    try:
        return float(rows[-1]["s"])
    except (IndexError, KeyError, ValueError):
        return None


def _cases(benchmarks: Path, path: Path) -> int:
    """How many cases a job ran: a simulate job's traces (``results/traces`` beside ``results/benchmarks``,
    under the benchmark file's own path: a folder for a job of several cases), else 1."""
    relative = path.relative_to(benchmarks).with_suffix("")
    if relative.parts[0] != "simulate":
        return 1
    traces = benchmarks.parent / "traces" / Path(*relative.parts[1:])
    return max(1, len(list(traces.rglob("*.parquet")))) if traces.is_dir() else 1


def measure(benchmarks: Path) -> list[dict]:
    """The cost table of the study whose ``results/benchmarks`` folder is ``benchmarks``: per kind of job
    and model, the median wall time of its jobs and the median of their cases (rows sorted by kind, then
    model)."""
    benchmarks = Path(benchmarks)
    models = set()
    for pattern in KINDS.values():
        top = pattern.split("{engine}")[0].rstrip("/")
        for folder in benchmarks.glob(top) if "*" in top else [benchmarks / top]:
            if folder.is_dir():
                models |= {p.stem if p.suffix == ".tsv" else p.name for p in folder.iterdir()}
    rows = []
    for kind, pattern in KINDS.items():
        for engine in sorted(models):
            paths = sorted(benchmarks.glob(pattern.format(engine=engine)))
            measured = [(w, _cases(benchmarks, p)) for p in paths if (w := _wall_seconds(p))]
            if measured:
                walls, cases = zip(*measured)
                rows.append(
                    {
                        "job": kind,
                        "engine": engine,
                        "wall_s": round(statistics.median(walls), 2),
                        "jobs": len(walls),
                        "cases": statistics.median(cases),
                    }
                )
    return rows


def write(rows: list[dict], path: Path, header: str) -> None:
    """Write the cost table, ``header`` (where and when it was measured) as its leading comment lines."""
    path = Path(path)
    with path.open("w", newline="") as handle:
        for line in header.strip().splitlines():
            handle.write(f"# {line}\n")
        writer = csv.DictWriter(handle, fieldnames=COLUMNS, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)


def load(path: Path) -> dict[tuple[str, str], float]:
    """(kind of job, model) -> measured wall seconds of one case (a job's over its cases; a row without
    ``cases`` measured jobs of one case); an absent table is an empty one (every priority 0)."""
    path = Path(path)
    if not path.exists():
        return {}
    with path.open() as handle:
        lines = [line for line in handle if not line.startswith("#")]
    return {
        (row["job"], row["engine"]): float(row["wall_s"]) / float(row.get("cases") or 1)
        for row in csv.DictReader(lines)
    }


def priority(costs: dict[tuple[str, str], float], job: str, engine: str, cases: int = 1) -> int:
    """Snakemake priority of a job of ``cases`` cases: their measured wall seconds, rounded (0 when not
    measured)."""
    return int(round(cases * costs.get((job, engine), 0.0)))
