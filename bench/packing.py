"""How well a study's jobs fill the cores: wall time against the CPU its jobs use.

A cold study on 2 cores cannot end before (its jobs' CPU seconds) / 2; the gap is a core left idle, mostly
while the last long jobs run alone. Measure a run (from the repository root, a cold results/):

    /usr/bin/time -v -o time.txt snakemake --cores 2 [--configfile config.yaml config/engines/...] > run.log 2>&1
    python bench/packing.py --label "six engines" --time time.txt --log run.log [--load load.txt]

``--load``: lines of ``<epoch> <the cpu line of /proc/stat>`` sampled during the run (bench/loadmon.sh),
to tell the machine's other work from the study's. Prints one markdown row and writes a CSV row
(--csv, appended). The figures:

- wall_s: the run's wall time; cpu_s: user + system seconds of snakemake and every job (its children);
  ratio: wall_s / (cpu_s / 2) (the packing target: <= 1.15);
- jobs_cpu_s: the sum of the jobs' Snakemake ``benchmark:`` cpu_time (sampled every 30 s after the first
  15, so a long job's last seconds are missed: a lower bound);
- busy: the mean number of jobs running (2 = both cores always busy), from the log's start and finish
  times; the share of the wall time with one core idle for want of a ready job;
- other_cpu_s: CPU the rest of the machine used meanwhile (from --load), which slows the run's jobs.

The breakdown of the wall time beyond the jobs' work (2 x wall_s on 2 cores): jobs_own_cpu_s, the CPU each
job's process reports at its end (simpick.joblog.COST: imports and children included; Snakemake's
benchmark files sample it and miss the last seconds); snakemake_own_cpu_s, Snakemake's own process (run it
through bench/snakemake_own_cpu.py, --own); unattributed_cpu_s, the rest of `time`'s CPU (jobs' scripts'
preambles before the log opens, jobs that report nothing); idle_core_s, 2 x wall - `time`'s CPU, a core
with nothing to run (meaningful on an otherwise idle machine only: other_cpu_s says).
"""

from __future__ import annotations

import argparse
import csv
import datetime
import json
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from simpick.joblog import read_cost  # noqa: E402 - after the path to the checkout's src

STAMP = re.compile(r"^\[(\w{3} \w{3} +\d+ \d\d:\d\d:\d\d \d{4})\]$")
START = re.compile(r"^(?:local)?(?:rule|checkpoint) (\w+):$")
JOBID = re.compile(r"^\s+jobid: (\d+)$")
FINISHED = re.compile(r"^Finished jobid: (\d+) \(Rule: (\w+)\)$")
BENCH = re.compile(r"^\s+benchmark: (\S+)$")
LOG = re.compile(r"^\s+log: (\S+)$")
WILDCARDS = re.compile(r"^\s+wildcards: (.+)$")
NODE = re.compile(r'^\s*(\d+)\[label = "([^"]*)"')
EDGE = re.compile(r"^\s*(\d+) -> (\d+)")


def _when(text: str) -> float:
    return datetime.datetime.strptime(" ".join(text.split()), "%a %b %d %H:%M:%S %Y").timestamp()


def jobs(log: Path) -> list[dict]:
    """Every job of a Snakemake log: rule, start, end (epoch seconds), benchmark file."""
    found: dict[str, dict] = {}
    stamp = None
    pending = None
    for line in log.read_text().splitlines():
        if m := STAMP.match(line):
            stamp, pending = _when(m.group(1)), None
        elif (m := START.match(line)) and stamp is not None:
            pending = {"rule": m.group(1), "start": stamp, "end": None, "benchmark": None, "log": None, "wildcards": {}}
        elif pending and (m := BENCH.match(line)):
            pending["benchmark"] = m.group(1)
        elif pending and (m := LOG.match(line)):
            pending["log"] = m.group(1).rstrip(",")
        elif pending and (m := WILDCARDS.match(line)):
            pending["wildcards"] = dict(item.split("=", 1) for item in m.group(1).split(", "))
        elif pending and (m := JOBID.match(line)):
            found[m.group(1)] = pending
        elif (m := FINISHED.match(line)) and m.group(1) in found:
            found[m.group(1)]["end"] = stamp
    return [j for j in found.values() if j["rule"] != "all"]


def busy(spans: list[dict], start: float, end: float) -> tuple[float, float]:
    """Mean number of jobs running over [start, end], and the share of it with fewer than 2 running."""
    events = sorted([(j["start"], 1) for j in spans] + [(j["end"], -1) for j in spans])
    running, last, area, short = 0, start, 0.0, 0.0
    for when, step in events + [(end, 0)]:
        area += running * (when - last)
        short += (when - last) if running < 2 else 0.0
        running, last = running + step, when
    wall = end - start
    return area / wall, short / wall


def replay(dot: Path, spans: list[dict], priority, cores: int = 2) -> dict:
    """Replay a run's jobs on ``cores`` idle cores: each job as long as it took in the run (its log's
    start to finish), started when its inputs are done (the DAG of ``snakemake --forceall --dag``), the
    ready job of highest ``priority(rule, wildcards)`` first, as Snakemake's scheduler picks with
    one-core jobs. The packing a schedule gives, free of the machine's other load: makespan against
    (sum of job times) / cores."""
    labels, deps = {}, {}
    for line in dot.read_text().splitlines():
        if m := NODE.match(line):
            rule, *rest = m.group(2).split("\\n")
            labels[m.group(1)] = (rule, dict(item.split(": ", 1) for item in rest))
            deps.setdefault(m.group(1), set())
        elif m := EDGE.match(line):
            deps.setdefault(m.group(2), set()).add(m.group(1))
    # a node's measured time: the log's job of the same rule and wildcards (labels may omit some: in order)
    pool: dict[str, list[dict]] = {}
    for j in sorted(spans, key=lambda j: j["start"]):
        pool.setdefault(j["rule"], []).append(j)
    duration, wild = {}, {}
    # nodes that show more wildcards first, so that a label showing none takes what is left
    for node, (rule, shown) in sorted(labels.items(), key=lambda kv: (-len(kv[1][1]), int(kv[0]))):
        if rule == "all":
            duration[node], wild[node] = 0.0, {}
            continue
        candidates = pool.get(rule, [])
        match = next((j for j in candidates if shown.items() <= j["wildcards"].items()), None)
        if match is None:
            raise SystemExit(f"packing: no job of the log matches DAG node {rule} {shown}")
        candidates.remove(match)
        duration[node], wild[node] = match["end"] - match["start"], match["wildcards"]
    done_at: dict[str, float] = {}
    running: list[tuple[float, str]] = []
    now, waiting = 0.0, set(labels)
    while waiting or running:
        ready = [n for n in waiting if all(d in done_at and done_at[d] <= now for d in deps[n])]
        ready.sort(key=lambda n: (-priority(labels[n][0], wild[n]), int(n)))
        for node in ready[: cores - len(running)]:
            waiting.discard(node)
            running.append((now + duration[node], node))
        running.sort()
        now, node = running.pop(0)
        done_at[node] = now
    total = sum(duration.values())
    return {"makespan_s": round(now, 1), "job_s": round(total, 1), "ratio": round(now / (total / cores), 3)}


def gnu_time(path: Path) -> dict:
    """wall, user and system seconds from /usr/bin/time -v."""
    text = path.read_text()
    user = float(re.search(r"User time \(seconds\): ([\d.]+)", text).group(1))
    system = float(re.search(r"System time \(seconds\): ([\d.]+)", text).group(1))
    clock = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)", text).group(1)
    wall = 0.0
    for part in clock.split(":"):
        wall = wall * 60 + float(part)
    return {"wall_s": wall, "cpu_s": user + system}


def machine_cpu(load: Path, start: float, end: float) -> float | None:
    """CPU seconds the whole machine used between start and end (from /proc/stat samples)."""
    rows = []
    for line in load.read_text().splitlines():
        parts = line.split()
        if len(parts) < 6 or parts[1] != "cpu":
            continue
        values = [int(v) for v in parts[2:]]
        idle = values[3] + values[4]
        rows.append((float(parts[0]), sum(values[:8]) - idle))
    inside = [r for r in rows if start - 5 <= r[0] <= end + 5]
    if len(inside) < 2:
        return None
    return (inside[-1][1] - inside[0][1]) / 100.0  # USER_HZ


def jobs_cpu(spans: list[dict], root: Path) -> float:
    total = 0.0
    for j in spans:
        if j["benchmark"] and (root / j["benchmark"]).exists():
            rows = list(csv.DictReader((root / j["benchmark"]).open(), delimiter="\t"))
            try:
                total += float(rows[-1]["cpu_time"])
            except (IndexError, KeyError, ValueError):
                pass
    return total


def jobs_logged(spans: list[dict], root: Path) -> tuple[float, float, int]:
    """CPU and wall seconds the jobs' own processes report at their end (simpick.joblog.COST: imports and
    children included, nothing sampled), summed, and how many jobs reported (a job whose script does not run
    inside simpick.joblog.logged, or that failed, writes no such line)."""
    cpu = wall = 0.0
    found = 0
    for j in spans:
        path = root / j["log"] if j["log"] else None
        cost = read_cost(path.read_text(errors="replace")) if path and path.is_file() else None
        if cost:
            cpu, wall, found = cpu + cost[0], wall + cost[1], found + 1
    return cpu, wall, found


def table_priority(costs_path: Path | None, cases: dict[str, int] | None = None):
    """The rules' priority of a job (rules/validate.smk, rules/simulate.smk: simpick.plan.costs) from a cost
    table; with no table every job's is 0 (Snakemake without priorities). ``cases``: the cases of a simulate
    job of each kind (a lab job's motions, a model's segments), which a DAG's labels do not give; one each if
    not given."""
    from simpick.plan import costs

    table = costs.load(costs_path) if costs_path else {}
    cases = cases or {}

    def priority(rule: str, wildcards: dict) -> int:
        engine = wildcards.get("engine", "")
        if rule in ("validate", "cpu_load"):
            kind = rule
        elif rule in ("simulate_segments", "simulate_lab"):
            kind = rule.removeprefix("simulate_")
        elif rule.startswith("simulate"):  # a replayed run, one a job or a class's in one (simulate_<source>_<class>)
            kind = "replay"
        else:
            return 0
        return costs.priority(table, kind, engine, cases.get(kind, 1))

    return priority


def default_cases() -> dict[str, int]:
    """The cases of a lab and a segments job in the default study (config.yaml): a terrain's motions, every
    committed segment."""
    import pandas as pd

    from simpick.config import read_study

    config = read_study([Path("config.yaml")])[1]
    return {"lab": len(config["motions"]), "segments": len(pd.read_csv(config["real_data"]["segments"]))}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--label", required=True)
    parser.add_argument("--time", required=True, type=Path, help="/usr/bin/time -v output of the run")
    parser.add_argument("--log", required=True, type=Path, help="the run's Snakemake output")
    parser.add_argument("--load", type=Path, help="/proc/stat samples taken during the run")
    parser.add_argument("--root", type=Path, default=Path("."), help="the folder the run ran in")
    parser.add_argument("--csv", type=Path, help="append the row here")
    parser.add_argument("--dag", type=Path, help="snakemake --forceall --dag of the run's config: replay its jobs")
    parser.add_argument("--costs", type=Path, help="with --dag: the cost table whose priorities the replay uses")
    parser.add_argument(
        "--own", type=Path, help="the JSON bench/snakemake_own_cpu.py wrote: Snakemake's own process's CPU seconds"
    )
    args = parser.parse_args()

    spans = [j for j in jobs(args.log) if j["end"] is not None]
    timed = gnu_time(args.time)
    start = min(j["start"] for j in spans)
    end = max(j["end"] for j in spans)
    mean_running, short = busy(spans, start, end)
    machine = machine_cpu(args.load, start, end) if args.load else None
    row = {
        "label": args.label,
        "jobs": len(spans),
        "wall_s": round(timed["wall_s"], 1),
        "cpu_s": round(timed["cpu_s"], 1),
        "ratio": round(timed["wall_s"] / (timed["cpu_s"] / 2), 3),
        "jobs_cpu_s": round(jobs_cpu(spans, args.root), 1),
        "mean_jobs_running": round(mean_running, 2),
        "share_one_core_idle": round(short, 3),
        "other_cpu_s": None if machine is None else round(max(machine - timed["cpu_s"], 0.0), 1),
    }
    # where the wall time goes beyond the jobs' measured work: 2 x wall = the jobs' own CPU (each job's
    # closing line) + Snakemake's own process + CPU of processes neither counts + core-seconds idle
    logged_cpu, logged_wall, reported = jobs_logged(spans, args.root)
    own = json.loads(args.own.read_text())["cpu_s"] if args.own else None
    row |= {
        "jobs_reporting_cost": reported,
        "jobs_own_cpu_s": round(logged_cpu, 1),
        "ratio_to_jobs_own_cpu": round(timed["wall_s"] / (logged_cpu / 2), 3) if logged_cpu else None,
        "snakemake_own_cpu_s": None if own is None else round(own, 1),
        "unattributed_cpu_s": None if own is None else round(timed["cpu_s"] - own - logged_cpu, 1),
        "idle_core_s": round(2 * timed["wall_s"] - timed["cpu_s"], 1),
        "jobs_mean_wall_s": round(logged_wall / reported, 2) if reported else None,
    }
    if args.dag:
        for name, path in (("unprioritised", None), ("prioritised", args.costs)):
            if name == "prioritised" and not path:
                continue
            for key, value in replay(args.dag, spans, table_priority(path, default_cases())).items():
                row[f"replay_{name}_{key}"] = value
    print("| " + " | ".join(str(v) for v in row.values()) + " |")
    if args.csv:
        new = not args.csv.exists()
        with args.csv.open("a", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(row), lineterminator="\n")
            if new:
                writer.writeheader()
            writer.writerow(row)


if __name__ == "__main__":
    main()
