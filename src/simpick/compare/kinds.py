"""How each kind of source's traces are compared with their reference (the kind is a source's
``DRIVEN``, simpick.sources): the lab against the paper's statistics, a segment against its real
window's statistics, a replayed run against its real log window by window, a replayed step unit against
the real robot's steady figures of that step (simpick.compare.steps). One function a kind,
the same arguments: the traces, the files they are compared with (``inputs``) and the settings."""

from __future__ import annotations

import pandas as pd

from simpick.compare import metrics
from simpick.compare.real import replay_compare, segment_compare
from simpick.compare.rows import DETAIL_COLUMNS, RUN_COLUMNS, axis_rows, case_test, run_row
from simpick.compare.settings import NoSettings, ReplaySettings, SegmentSettings
from simpick.compare.steps import step_errors
from simpick.inputs.published import load_published
from simpick.inputs.reference import lab_reference
from simpick.simulate.step_rows import STEP_COLUMNS, hung_row, step_row
from simpick.simulate.traces import read_trace

PER_TEST_COLUMNS = [
    "engine",
    "terrain",
    "motion",
    "test",
    "run",
    "kind",
    "status",
    "reasons",
    "error_angular",
    "error_linear",
]


def compare_lab(traces: list[str], inputs: dict, params: dict):
    """The lab tests against the paper's real statistics (simpick.inputs.reference, ``inputs["published"]``):
    per engine, test, quantity and axis (``detail``), and Eq. 7 per test where the paper has a
    reference (``per_test``; a failed run of such a test is a failed row). No settings (:class:`NoSettings`)."""
    NoSettings.model_validate(params)
    reference = lab_reference(load_published(inputs["published"]))
    detail, per_test, runs = [], [], []
    for path in traces:
        frame, meta = read_trace(path)
        runs.append(run_row(meta))
        ok = meta["health"]["status"] == "ok"
        ref = reference.get((meta["terrain"], meta["motion"]))
        rows = axis_rows(meta, metrics.trace_stats(frame) if ok else None, ref)
        detail += rows
        if ref is None:
            continue
        test = case_test(meta)
        row = {
            "engine": meta["engine"],
            "terrain": meta["terrain"],
            "motion": meta["motion"],
            "test": test,
            "run": test,
            "kind": "lab",
            "status": meta["health"]["status"],
            "reasons": "; ".join(meta["health"]["reasons"]),
        }
        if ok:
            row.update(
                {
                    f"error_{q}": metrics.eq7_sum(r["total_error"] for r in rows if r["quantity"] == q)
                    for q in ("angular", "linear")
                }
            )
        per_test.append(row)
    return (
        pd.DataFrame(per_test, columns=PER_TEST_COLUMNS),
        pd.DataFrame(detail, columns=DETAIL_COLUMNS),
        pd.DataFrame(runs, columns=RUN_COLUMNS),
    )


def compare_segments(traces: list[str], inputs: dict, params: dict):
    """Every simulated segment against its real window statistics (simpick.compare.real.segment_compare;
    :class:`SegmentSettings`: the track)."""
    return segment_compare(inputs["segments"], traces, SegmentSettings.model_validate(params).track)


def compare_replay(traces: list[str], inputs: dict, params: dict):
    """Every replayed run against its real log, window by window (simpick.compare.real.replay_compare)."""
    return replay_compare(list(inputs["logs"]), traces, params)


def compare_steps(traces: list[str], inputs: dict, params: dict):
    """Every replayed step unit (traces of simpick.simulate.steps.prepare_step) against the real robot over
    its steady part (simpick.compare.steps.step_errors: the reader's case table ``inputs["cases"]`` and step
    table ``inputs["steps"]``): ``per_test`` the per-step errors (a metric a unit does not carry is NaN),
    ``detail`` the replayed step rows they rest on, ``runs`` each trace's timing and health. No settings
    (:class:`NoSettings`)."""
    NoSettings.model_validate(params)
    cases = pd.read_csv(inputs["cases"])
    by_case = cases.set_index("case", drop=False)
    rows, runs = [], []
    for path in traces:
        frame, meta = read_trace(path)
        runs.append(run_row(meta))
        case = by_case.loc[meta["test"]]
        if "warmup" in meta:
            rows.append(step_row(frame, meta, case))
        else:  # a hung trace (simpick.simulate.jobs.write_hung_trace): not run, its health record says why
            rows.append(hung_row(case, meta["engine"], "; ".join(meta["health"]["reasons"])))
    replayed = pd.DataFrame(rows, columns=STEP_COLUMNS)
    errors = step_errors(cases, pd.read_csv(inputs["steps"]), replayed)
    return errors, replayed, pd.DataFrame(runs, columns=RUN_COLUMNS)


# kind -> its comparison: (per_test, detail, runs) tables
BY_KIND = {"lab": compare_lab, "segments": compare_segments, "replay": compare_replay, "steps": compare_steps}
# kind -> the settings its comparison reads (rule compare's ``settings``, the source module's compare_settings)
SETTINGS = {"lab": NoSettings, "segments": SegmentSettings, "replay": ReplaySettings, "steps": NoSettings}
