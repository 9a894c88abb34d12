"""The study's job cost table (resources/engines/job_costs.csv) from a finished study's benchmark files.

Run from the repository root after a study (the eight-engine one measures every engine):
    .venv/bin/python bench/job_costs.py [results/benchmarks]
The rules' priorities read it (simpick.plan.costs): longest measured jobs start first.
"""

from __future__ import annotations

import argparse
import csv
import datetime
import platform
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from simpick.plan import costs  # noqa: E402
from simpick.plan.scheduling import COST_TABLE  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("benchmarks", nargs="?", default="results/benchmarks", type=Path)
    parser.add_argument("--out", default=ROOT / COST_TABLE, type=Path)
    parser.add_argument("--note", default="", help="how the study was run (the machine's other load, the config)")
    parser.add_argument("--keep", type=Path, help="an older table whose rows this study did not measure are kept")
    args = parser.parse_args()
    rows = costs.measure(args.benchmarks)
    if args.keep:
        measured = {(r["job"], r["engine"]) for r in rows}
        with args.keep.open() as handle:
            kept = [r for r in csv.DictReader(line for line in handle if not line.startswith("#"))]
        rows += [r for r in kept if (r["job"], r["engine"]) not in measured]
    if not rows:
        raise SystemExit(f"simpick: no validate, cpu_load or simulate benchmark files under {args.benchmarks}")
    header = (
        f"Median wall seconds and cases per job, by kind of job and model, measured by bench/job_costs.py from\n"
        f"{args.benchmarks} on {datetime.date.today()} ({platform.processor() or platform.machine()}, 2 cores).\n"
        + (f"{args.note}\n" if args.note else "")
        + "The rules' priority: (simpick.plan.costs). Refresh after a study: python bench/job_costs.py"
    )
    costs.write(rows, args.out, header)
    print(f"{len(rows)} rows -> {args.out}")


if __name__ == "__main__":
    main()
