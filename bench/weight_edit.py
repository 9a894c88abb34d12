"""The weight-edit rerun: wall time of ``snakemake --cores 2`` after one weight of the config is edited,
on a study that is complete, and where that time goes.

Run from the repository root after a complete study (``make study``):

    .venv/bin/python bench/weight_edit.py [--repeats 3] [--weight ui] [--cores 2]

Each repeat writes a copy of config.yaml with one more point on ``--weight`` (a new edit each time, so
each run has work to do), and times the whole command with /usr/bin/time: Snakemake's start and DAG,
every job, and the PDF. Beside the wall time it reads each job's own benchmark file
(results/benchmarks/<rule>.tsv, where the rule has one) and the jobs Snakemake ran. At the end the
study is brought back to the config's own weights (not timed). Prints a table; with --out writes it
as CSV too. Timings are measured here, never asserted by a test: they depend on the machine's load,
which is printed with them.
"""

from __future__ import annotations

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
SNAKEMAKE = Path(sys.executable).with_name("snakemake")
# the rule of the weight path (the report job, which weighs the scores before it writes the page), and those
# beside it that keep a benchmark file (rules/scores.smk, rules/tree.smk, rules/report.smk)
BENCHMARKS = (
    "scores",
    "verdict",
    "figure_tree",
    "report_evidence",
    "report",
)


def _run(config: Path, cores: int, log: Path, extra: list[str] = ()) -> tuple[float, list[str]]:
    """Wall seconds of one Snakemake run (GNU time's %e) and the rules of the jobs it ran; ``extra``:
    more arguments to Snakemake."""
    timing = log.with_suffix(".time")
    cmd = [
        "/usr/bin/time",
        "-f",
        "%e",
        "-o",
        str(timing),
        str(SNAKEMAKE),
        "--cores",
        str(cores),
        "--configfile",
        str(config),
        *extra,
    ]
    with open(log, "w") as fh:
        done = subprocess.run(cmd, cwd=ROOT, stdout=fh, stderr=subprocess.STDOUT, env=os.environ.copy(), check=False)
    if done.returncode:
        sys.exit(f"snakemake failed (exit {done.returncode}); its output: {log}")
    rules = re.findall(r"^(?:local)?rule (\w+):", log.read_text(), flags=re.M)
    return float(timing.read_text().split()[-1]), rules


def _job_seconds(since: float) -> dict[str, float]:
    """rule -> seconds of its job, for the jobs of this run (a benchmark file written since ``since``)."""
    out = {}
    for rule in BENCHMARKS:
        path = ROOT / "results" / "benchmarks" / f"{rule}.tsv"
        if path.is_file() and path.stat().st_mtime >= since:
            lines = path.read_text().splitlines()
            if len(lines) > 1:
                out[rule] = float(lines[1].split("\t")[0])
    return out


def _report_log(since: float) -> dict[str, float]:
    """The report job's own split of its time (results/logs/report.log, written since ``since``): HTML,
    the body's PDF, the join with the evidence's PDF and the page numbers."""
    path = ROOT / "results" / "logs" / "report.log"
    if not path.is_file() or path.stat().st_mtime < since:
        return {}
    text = path.read_text()
    found = {}
    for key, pattern in (
        ("report_html", r"report: HTML (\d+\.\d+) s"),
        ("report_body_pdf", r"\(body (\d+\.\d+) s"),
        ("report_join", r"numbered (\d+\.\d+) s"),
    ):
        m = re.search(pattern, text)
        if m:
            found[key] = float(m.group(1))
    return found


def main(argv: list[str] | None = None) -> None:
    global ROOT
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--weight", default="ui", help="the weight to edit (a key of the config's weights)")
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--out", type=Path, help="also write the table as CSV here")
    parser.add_argument(
        "--workdir",
        type=Path,
        default=ROOT,
        help="the study's folder (a checkout with its results/; default: this repository)",
    )
    parser.add_argument(
        "--snakemake-args",
        default="",
        help="more arguments to Snakemake, as one string (to compare, e.g. '--scheduler greedy')",
    )
    args = parser.parse_args(argv)
    ROOT = args.workdir.resolve()

    config = yaml.safe_load((ROOT / "config.yaml").read_text())
    base = float(config["weights"][args.weight])
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(args.repeats):
            config["weights"][args.weight] = base + i + 1
            edited = Path(tmp) / f"edited{i}.yaml"
            edited.write_text(yaml.safe_dump(config, sort_keys=False))
            load, start = os.getloadavg()[0], time.time()
            wall, rules = _run(edited, args.cores, Path(tmp) / f"run{i}.log", args.snakemake_args.split())
            rows.append(
                {
                    "repeat": i + 1,
                    "wall_s": wall,
                    "load_1min": load,
                    "jobs": " ".join(sorted(rules)),
                    **{f"{k}_s": v for k, v in _job_seconds(start).items()},
                    **{f"{k}_s": v for k, v in _report_log(start).items()},
                }
            )
            print(rows[-1], flush=True)
        config["weights"][args.weight] = base  # back to the study's own weights (not timed)
        restore = Path(tmp) / "restore.yaml"
        restore.write_text(yaml.safe_dump(config, sort_keys=False))
        _run(restore, args.cores, Path(tmp) / "restore.log", args.snakemake_args.split())
    walls = [r["wall_s"] for r in rows]
    print(
        f"weight-edit rerun, {args.cores} cores: median {statistics.median(walls):.2f} s "
        f"(min {min(walls):.2f}, max {max(walls):.2f}, n {len(walls)})"
    )
    for key in sorted({k for r in rows for k in r if k.endswith("_s") and k != "wall_s"}):
        vals = [r[key] for r in rows if key in r]
        print(f"  {key[:-2]}: median {statistics.median(vals):.2f} s")
    if args.out:
        import csv

        with open(args.out, "w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(dict.fromkeys(k for r in rows for k in r)))
            writer.writeheader()
            writer.writerows(rows)


if __name__ == "__main__":
    main()
