"""The rest of a simulate job after one of its cases hung (:func:`simpick.simulate.jobs.resume`): run as
``python -m simpick.simulate.resume STATE`` in the job's process, which the hung one was replaced by; reads
what the job was given from ``STATE`` (JSON beside the job's log, removed once read) and runs its cases from
the one after the hung case on, appending to the job's log."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from simpick.joblog import logged
from simpick.simulate.jobs import simulate_job


def main(state_file: str) -> None:
    path = Path(state_file)
    state = json.loads(path.read_text())
    path.unlink()
    with logged(state["log"], append=True):
        simulate_job(
            state["outputs"], state["urdf"], state["inputs"], state["params"], log=state["log"], start=state["start"]
        )


if __name__ == "__main__":
    main(sys.argv[1])
