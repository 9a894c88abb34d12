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
"""

from __future__ import annotations

import argparse
import csv
import datetime
import re
from pathlib import Path

STAMP = re.compile(r"^\[(\w{3} \w{3} +\d+ \d\d:\d\d:\d\d \d{4})\]$")
START = re.compile(r"^(?:local)?(?:rule|checkpoint) (\w+):$")
JOBID = re.compile(r"^\s+jobid: (\d+)$")
FINISHED = re.compile(r"^Finished jobid: (\d+) \(Rule: (\w+)\)$")
BENCH = re.compile(r"^\s+benchmark: (\S+)$")


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
            pending = {"rule": m.group(1), "start": stamp, "end": None, "benchmark": None}
        elif pending and (m := BENCH.match(line)):
            pending["benchmark"] = m.group(1)
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--label", required=True)
    parser.add_argument("--time", required=True, type=Path, help="/usr/bin/time -v output of the run")
    parser.add_argument("--log", required=True, type=Path, help="the run's Snakemake output")
    parser.add_argument("--load", type=Path, help="/proc/stat samples taken during the run")
    parser.add_argument("--root", type=Path, default=Path("."), help="the folder the run ran in")
    parser.add_argument("--csv", type=Path, help="append the row here")
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
