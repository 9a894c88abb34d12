"""Run Snakemake in this process and write its own CPU seconds (not its jobs') to a JSON file at exit.

    /usr/bin/time -v -o time.txt python bench/snakemake_own_cpu.py own.json --cores 2 > run.log 2>&1
    python bench/packing.py --label cold --time time.txt --log run.log --own own.json

Every argument after the file goes to Snakemake. The figure is resource.getrusage(RUSAGE_SELF) of this
process: planning the DAG, scheduling, checking outputs, metadata, and any job Snakemake runs in its own
process; the jobs started as processes are counted by `time` (children) and by each job's log.
"""

from __future__ import annotations

import atexit
import json
import resource
import sys
from pathlib import Path


def _write(path: Path) -> None:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    path.write_text(json.dumps({"cpu_s": usage.ru_utime + usage.ru_stime}) + "\n")


if __name__ == "__main__":
    out = Path(sys.argv[1])
    atexit.register(_write, out)
    from snakemake.cli import main

    sys.argv = ["snakemake", *sys.argv[2:]]
    main()
