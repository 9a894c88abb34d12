"""Reading every input of the report or a figure job into a :class:`ReportData`: each given file
read and checked, a missing required one refused with the rule that writes it.

One function for the report and the figure jobs alike, so that both read the same tables the
same way."""

from __future__ import annotations

import json
from collections.abc import Mapping
from typing import Any

import pandas as pd
import yaml

from simpick.errors import InputError
from simpick.report.load.columns import (
    REAL_SETS,
    REAL_TABLES,
    VERDICT_TABLES,
)
from simpick.report.load.data import ReportData, Trace
from simpick.report.load.files import DETAIL_VIEWS, _csv, _path, _paths, figure_key
from simpick.score.equivalence import pooled


def load_inputs(inputs: Mapping[str, Any], required: tuple[str, ...] | None = None) -> ReportData:
    """Read every input that is given; raise :class:`InputError` for a missing required one
    (``required``: the report's by default; a figure job names what it draws from)."""
    from simpick.report.inputs import OPTIONAL_INPUTS, REQUIRED_INPUTS

    if required is None:
        required = REQUIRED_INPUTS
    for key in required:
        if inputs.get(key) in (None, "", []):
            raise InputError(f"report inputs[{key!r}]", "required input is not given")
    unknown = sorted(set(inputs) - set(REQUIRED_INPUTS) - set(OPTIONAL_INPUTS))
    if unknown:
        raise InputError("report inputs", f"unknown keys {unknown}")

    def given(key: str) -> bool:
        return inputs.get(key) not in (None, "", [])

    sources: dict[str, Any] = {}
    kw: dict[str, Any] = {}
    for key, index in (
        ("weighted", "engine"),
        ("runs", None),
        ("trace_stats", None),
        ("reference_stats", None),
        ("imu_errors", None),
        ("per_test_errors", None),
        ("rtf", None),
        ("table11", "simulator"),
        ("table11_comparison", None),
        ("endpoints", None),
    ):
        if given(key):
            p = _path(key, inputs[key])
            sources[key] = str(p)
            if key in DETAIL_VIEWS and "ref_mean" in pd.read_csv(p, nrows=0).columns:
                kw[key] = DETAIL_VIEWS[key](_csv("detail", p)).copy()
            else:
                kw[key] = _csv(key, p, index)

    for key in (
        "contributions",
        "drivers",
        "accuracy_errors",
        "accuracy_per_test",
        "segments",
        "replay_per_window",
        "validation",
        "validation_gains",
        "sweep",
        "calibration",
        "calibration_turning",
        "calibration_target",
        "real_turning",
    ):
        if given(key):
            p = _path(key, inputs[key])
            sources[key] = str(p)
            kw[key] = _csv(key, p)
    real: dict[str, dict[str, pd.DataFrame]] = {}
    for set_ in REAL_SETS:
        for table in REAL_TABLES:
            key = f"{set_}_{table}"
            if given(key):
                p = _path(key, inputs[key])
                sources[key] = str(p)
                real.setdefault(set_, {})[table] = _csv(key, p)
    kw["real"] = real
    verdict: dict[str, pd.DataFrame] = {}
    for table in VERDICT_TABLES:
        key = f"verdict_{table}"
        if given(key):
            p = _path(key, inputs[key])
            sources[key] = str(p)
            verdict[table] = _csv(key, p)
    if "outcomes" in verdict:  # the DRIVE comparison's outcomes where the answer rests on DRIVE: its pooled rows
        verdict["outcomes"] = pooled(verdict["outcomes"])
    kw["verdict"] = verdict
    for key in ("segments_provenance", "scores_provenance", "verdict_headline", "verdict_sentences"):
        if given(key):
            p = _path(key, inputs[key])
            try:
                with open(p, encoding="utf-8") as fh:
                    prov = yaml.safe_load(fh) or {}
            except yaml.YAMLError as exc:
                raise InputError(str(p), f"not valid YAML: {exc}") from None
            if not isinstance(prov, dict):
                raise InputError(str(p), "expected a mapping")
            kw[key] = prov
            sources[key] = str(p)
    for key in ("real_logs", "replay_traces"):
        if given(key):
            kw[key] = [str(p) for p in _paths(key, inputs[key])]
            sources[key] = kw[key]

    if given("figures"):
        figs, notes = {}, {}
        for p in _paths("figures", inputs["figures"]):
            if p.suffix == ".json":
                notes[figure_key(p)] = json.loads(p.read_text(encoding="utf-8"))
            else:
                figs[figure_key(p)] = str(p)
        kw["figures"], kw["figure_notes"] = figs, notes
        sources["figures"] = sorted(figs.values())

    runs = kw.get("runs")
    for col in ("engine_version", "config_hash"):
        if runs is not None and col not in runs.columns:
            runs[col] = ""

    if given("cpu"):
        cpu = []
        for p in _paths("cpu", inputs["cpu"]):
            try:
                rec = json.loads(p.read_text(encoding="utf-8"))
            except json.JSONDecodeError as exc:
                raise InputError(str(p), f"not valid JSON: {exc}") from None
            for k in ("engine", "average", "intense"):
                if k not in rec:
                    raise InputError(str(p), f"key {k!r} is missing")
            cpu.append(rec)
        kw["cpu"] = cpu
        sources["cpu"] = [str(p) for p in _paths("cpu", inputs["cpu"])]

    if given("qualitative"):
        p = _path("qualitative", inputs["qualitative"])
        with open(p, encoding="utf-8") as fh:
            q = yaml.safe_load(fh) or {}
        if not isinstance(q, dict):
            raise InputError(str(p), "expected a mapping engine -> fact record")
        if isinstance(q.get("engines"), dict):
            q = q["engines"]
        kw["qualitative"] = {str(k): v for k, v in q.items() if isinstance(v, dict)}
        sources["qualitative"] = str(p)

    if given("tree"):
        from simpick.score.tree import read_tree

        p = _path("tree", inputs["tree"])
        kw["tree"] = read_tree(str(p))
        sources["tree"] = str(p)

    if given("worked_example"):
        p = _path("worked_example", inputs["worked_example"])
        try:
            kw["worked_example"] = json.loads(p.read_text(encoding="utf-8"))
        except json.JSONDecodeError as exc:
            raise InputError(str(p), f"not valid JSON: {exc}") from None
        sources["worked_example"] = str(p)

    if given("traces"):
        from simpick.simulate.traces import read_trace

        traces = []
        for p in _paths("traces", inputs["traces"]):
            frame, meta = read_trace(p)
            # results/traces/<source>/{engine}/{terrain}/{motion}.parquet; metadata wins when present.
            engine = str(meta.get("engine") or p.parent.parent.name)
            terrain = str(meta.get("terrain") or p.parent.name)
            motion = str(meta.get("motion") or p.stem)
            traces.append(Trace(engine, terrain, motion, frame, meta, str(p)))
        kw["traces"] = traces
        sources["traces"] = [t.path for t in traces]

    kw.setdefault("weighted", None)
    kw.setdefault("runs", None)
    return ReportData(sources=sources, **kw)
