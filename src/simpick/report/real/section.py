"""The real-data section of the report: per real-data set and terrain class, every engine against
the real robot (simpick.compare.real's tables), and the data of the yaw-rate-gain figure.

It formats the summarise job's tables into the blocks the template lays out, computing no
statistic itself."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from simpick.report import figures
from simpick.report.load import REAL_SETS, ReportData
from simpick.report.real.common import (
    ERROR_FIGURES,
    FIGURE_LABELS,
    REAL_TABLE_NAMES,
    REPLAY_EXTRA,
    SET_TITLES,
    SET_UNITS,
    _cell,
    _f,
    _isnan,
    class_order,
    statistics,
)
from simpick.report.real.sets import datasets

if TYPE_CHECKING:
    from simpick.report.params import EvidenceParams, RealGainFigureParams


def _real_gain(
    per_test: pd.DataFrame | None, summary: pd.DataFrame | None, cls: str, stats: Mapping[str, Any] | None = None
) -> tuple[dict | None, int]:
    """The real robot's yaw-rate gain over the class's tests, as the summarise job wrote it (the
    mean over runs and its interval from statistics.min_runs runs on, beside each model's row: the
    row of the model that completed most tests), and the number of its distinct turning tests."""
    n = 0
    if per_test is not None and "yaw_rate_gain_real" in per_test.columns:
        sel = per_test[per_test["terrain_class"] == cls].drop_duplicates("segment")
        n = int(np.isfinite([_f(x) for x in sel["yaw_rate_gain_real"]]).sum())
    if summary is not None and "yaw_rate_gain_real" in summary.columns:
        sel = summary[summary["terrain_class"] == cls]
        if len(sel):
            row = sel.sort_values("n_tests", ascending=False, kind="mergesort").iloc[0].to_dict()
            cell = _cell(row, "yaw_rate_gain_real")
            return {**cell, "n_runs": int(_f(row.get("n_runs"))) if not _isnan(row.get("n_runs")) else 0}, n
    return None, n


def _set_block(
    set_: str, tables: Mapping[str, pd.DataFrame], cls: str, engines: list[str], stats: Mapping[str, Any] | None = None
) -> dict[str, Any]:
    summary, per_test = tables.get("summary"), tables.get("per_test")
    real_gain, n_gain = _real_gain(per_test, summary, cls, stats)
    n_class = n_runs_class = None
    if per_test is not None:
        n_class = int(per_test[per_test["terrain_class"] == cls]["segment"].nunique())
        if "run" in per_test.columns:
            n_runs_class = int(per_test[per_test["terrain_class"] == cls]["run"].astype(str).nunique())
    rows = []
    if summary is not None:
        sel = summary[summary["terrain_class"] == cls]
        recs = {r["engine"]: r for r in sel.to_dict("records")}
        for e in [e for e in engines if e in recs] + [e for e in recs if e not in engines]:
            r = recs[e]
            n_turn = None
            if per_test is not None and "yaw_rate_gain_sim" in per_test.columns:
                pt = per_test[(per_test["terrain_class"] == cls) & (per_test["engine"] == e)]
                n_turn = int(np.isfinite([_f(x) for x in pt["yaw_rate_gain_sim"]]).sum())
            rows.append(
                {
                    "engine": e,
                    "n": int(_f(r["n_tests"])) if not _isnan(r["n_tests"]) else 0,
                    "n_runs": int(_f(r["n_runs"])) if not _isnan(r.get("n_runs")) else None,
                    "n_gain": n_turn,
                    "gain": _cell(r, "yaw_rate_gain_sim"),
                    "errors": {f: _cell(r, f) for f in ERROR_FIGURES},
                    "extra": {f: _cell(r, f) for f, _ in REPLAY_EXTRA},
                }
            )
    failed = []
    if per_test is not None:
        bad = per_test[(per_test["terrain_class"] == cls) & (per_test["status"].str.lower() != "ok")]
        failed = [
            {"engine": r["engine"], "test": r["segment"], "status": r["status"], "reasons": r["reasons"]}
            for r in bad.to_dict("records")
        ]
    extra = [(f, label) for f, label in REPLAY_EXTRA if summary is not None and f in summary.columns]
    return {
        "set": set_,
        "title": SET_TITLES.get(set_, set_),
        "unit": SET_UNITS.get(set_, "test"),
        "real_gain": real_gain,
        "n_gain_real": n_gain,
        "n_class": n_class,
        "n_runs": n_runs_class,
        "rows": rows,
        "failed": failed,
        "extra": extra,
        "given": summary is not None,
    }


def _blocks(
    data: ReportData,
    params: RealGainFigureParams | EvidenceParams,
    engines: list[str],
    classes: list[str],
    scored_set: str | None = None,
) -> tuple[list[str], list[dict], dict[str, list[dict]]]:
    """Per shown class and real-data set, the block of tables and verdicts (:func:`_set_block`);
    ``scored_set``: the set the accuracy scores rest on."""
    class_params = params.real_data.classes
    sets = [s for s in REAL_SETS if data.real.get(s)]
    stats = statistics(params.statistics)
    blocks_by_set: dict[str, list[dict]] = {s: [] for s in sets}
    class_blocks = []
    shown_classes = [
        c
        for c in classes
        if any(
            (t := data.real[s].get(k)) is not None and (t["terrain_class"] == c).any()
            for s in sets
            for k in ("summary", "per_test")
        )
    ]
    for cls in shown_classes:
        cp = class_params.get(cls)  # terrain class -> its ground: a mapping keyed by the data's class names
        item = {
            "cls": cls,
            "label": cls.replace("_", " "),
            "friction": cp.friction if cp else None,
            "source": cp.source if cp else None,
            "sets": [],
        }
        for s in sets:
            block = _set_block(s, data.real[s], cls, engines, stats)
            block["scored"] = s == scored_set
            item["sets"].append(block)
            blocks_by_set[s].append({"cls": cls, "block": block})
        class_blocks.append(item)
    return shown_classes, class_blocks, blocks_by_set


def gain_panels(
    data: ReportData, params: RealGainFigureParams, engines: list[str], colors: Mapping[str, str]
) -> list[dict]:
    """The yaw-rate-gain figure's panels (rule figure_real_gain): one per real-data set."""
    classes = class_order(data, params.real_data)
    _, _, blocks_by_set = _blocks(data, params, engines, classes)
    return _gain_panels(blocks_by_set, classes, engines, colors)


def _gain_panels(
    blocks_by_set: dict[str, list[dict]], classes: list[str], engines: list[str], colors: Mapping[str, str]
) -> list[dict]:
    panels = []
    for set_, blocks in blocks_by_set.items():
        shown = [
            b
            for b in blocks
            if b["block"]["real_gain"] is not None
            or any(r.get("gain") and not _isnan(r["gain"]["mean"]) for r in b["block"]["rows"])
        ]
        if not shown:
            continue
        cls = [b["cls"] for b in shown]
        bars = [
            {
                "label": figures.REAL_LABEL,
                "color": figures.REAL_COLOR,
                "real": True,
                "mean": [(b["block"]["real_gain"] or {}).get("mean") for b in shown],
                "low": [(b["block"]["real_gain"] or {}).get("low") for b in shown],
                "high": [(b["block"]["real_gain"] or {}).get("high") for b in shown],
            }
        ]
        have = [e for e in engines if any(r["engine"] == e for b in shown for r in b["block"]["rows"])]
        for e in have:
            cells = [
                next((r["gain"] for r in b["block"]["rows"] if r["engine"] == e and r.get("gain")), None) for b in shown
            ]
            bars.append(
                {
                    "label": e,
                    "color": colors.get(e, "#777777"),
                    "real": False,
                    "mean": [c["mean"] if c else None for c in cells],
                    "low": [c["low"] if c else None for c in cells],
                    "high": [c["high"] if c else None for c in cells],
                }
            )
        panels.append({"title": SET_TITLES.get(set_, set_), "classes": cls, "bars": bars})
    return panels


def _segments_table(data: ReportData, classes: list[str], engines: list[str]) -> list[dict[str, Any]] | None:
    seg = data.segments
    if seg is None:
        return None
    pt = data.real.get("segments", {}).get("per_test")
    results = {}
    if pt is not None:
        for r in pt.to_dict("records"):
            results[(r["engine"], r["segment"])] = r
    groups = []
    pos = {c: i for i, c in enumerate(classes)}
    for cls in sorted(set(seg["terrain_class"]), key=lambda c: (pos.get(c, len(pos)), c)):
        sel = seg[seg["terrain_class"] == cls].sort_values(["kind", "segment"])
        rows = []
        for r in sel.to_dict("records"):
            cells = []
            for e in engines:
                res = results.get((e, r["segment"]))
                if res is None:
                    cells.append(None)
                    continue
                cells.append(
                    {
                        "ok": str(res["status"]).lower() == "ok",
                        "status": res["status"],
                        "gain": _f(res.get("yaw_rate_gain_sim")),
                        "ang": _f(res.get("error_angular")),
                        "lin": _f(res.get("error_linear")),
                        "speed": _f(res.get("speed_sim")),
                    }
                )
            short = r["segment"][len(cls) + 1 :] if r["segment"].startswith(cls + "-") else r["segment"]
            rows.append({**r, "short": short, "cells": cells})
        groups.append({"cls": cls, "label": cls.replace("_", " "), "rows": rows})
    return groups


def real_section(
    data: ReportData,
    params: EvidenceParams,
    engines: list[str],
    colors: Mapping[str, str],
    classes: list[str],
    acc: dict | None,
) -> dict[str, Any]:
    rd = params.real_data
    class_params = rd.classes
    sets = [s for s in REAL_SETS if data.real.get(s)]
    missing: list[str] = []
    for s in sets:
        lacking = [t for t in REAL_TABLE_NAMES if t not in data.real[s]]
        if lacking:
            missing.append(f"{SET_TITLES[s]}: no {', '.join(f'{s}_{t}' for t in lacking)} input")
    given = bool(sets) or data.segments is not None
    # a source with no case, or none that any model completed: a normal outcome, said, not a crash
    empty = []
    for s_ in sets:
        pt = data.real[s_].get("per_test")
        if pt is not None and not (pt["status"].astype(str).str.lower() == "ok").any():
            empty.append({"set": s_, "title": SET_TITLES[s_], "n_rows": len(pt)})
    scored_set = acc.get("kind") if acc and acc.get("kind") in REAL_SETS else None
    stats = statistics(params.statistics)
    shown_classes, class_blocks, _ = _blocks(data, params, engines, classes, scored_set)

    # at a glance: per class and error, the closest engine and the class's typed outcome, as the summarise
    # job wrote them (simpick.compare.real.class_verdicts: <figure>_closest, <figure>_outcome)
    glance = []
    for s_ in sets:
        summary = data.real[s_].get("summary")
        if summary is None or not any(f"{f}_closest" in summary.columns for f in ERROR_FIGURES):
            continue
        rows = []
        for cls in shown_classes:
            sel = summary[summary["terrain_class"] == cls]
            if sel.empty:
                continue
            cells = {}
            for f in ERROR_FIGURES:
                closest = sel[sel[f"{f}_closest"]] if f"{f}_closest" in sel.columns else sel.iloc[0:0]
                cells[f] = (
                    {"engine": closest["engine"].iloc[0], "outcome": closest[f"{f}_outcome"].iloc[0]}
                    if len(closest)
                    else None
                )
            runs = sel["n_runs"].max() if "n_runs" in sel.columns else None
            rows.append(
                {
                    "cls": cls,
                    "label": cls.replace("_", " "),
                    "cells": cells,
                    "n_runs": None if _isnan(runs) else int(runs),
                }
            )
        glance.append({"set": s_, "title": SET_TITLES[s_], "rows": rows, "scored": s_ == scored_set})

    # the paired differences per class, as the compare job wrote them (pairwise.csv), for the appendix
    pairwise = []
    for s_ in sets:
        pw = data.real[s_].get("pairwise")
        if pw is None or pw.empty:
            continue
        pos = {c: i for i, c in enumerate(classes)}
        # the pairs with each class's closest engine (the summary's <figure>_closest), where the summary names
        # one: the comparisons its outcome rests on; every pair stays in pairwise.csv
        summary = data.real[s_].get("summary")
        closest = set()
        if summary is not None:
            for f in ERROR_FIGURES:
                if f"{f}_closest" in summary.columns:
                    sel = summary[summary[f"{f}_closest"]]
                    closest |= {(c, f, e) for c, e in zip(sel["terrain_class"], sel["engine"])}
        records = pw.to_dict("records")
        if closest:
            records = [
                r
                for r in records
                if (r["terrain_class"], r["figure"], r["engine_a"]) in closest
                or (r["terrain_class"], r["figure"], r["engine_b"]) in closest
            ]
        rows = sorted(records, key=lambda r: (pos.get(r["terrain_class"], len(pos)), r["figure"]))
        for r in rows:
            r["figure_label"] = FIGURE_LABELS.get(r["figure"], r["figure"])
            r.setdefault("n_runs", float("nan"))
            r.setdefault("p_value", float("nan"))
        pairwise.append(
            {"set": s_, "title": SET_TITLES[s_], "rows": rows, "with_closest": bool(closest), "n_all": len(pw)}
        )

    gain_file = data.figures.get("real_gain")
    gain_uri = figures.data_uri(gain_file) if gain_file else None
    turning_file = data.figures.get("real_turning")
    turning = {
        "uri": figures.data_uri(turning_file) if turning_file else None,
        "rows": data.real_turning.to_dict("records") if data.real_turning is not None else [],
    }

    # the full replay's figures (rule figure_replay): the PNG and the notes the job wrote beside it
    pos = {c: i for i, c in enumerate(classes)}
    replay_figs, replay_notes = [], []
    for key, note in sorted(data.figure_notes.items(), key=lambda kv: (pos.get(kv[1].get("cls"), len(pos)), kv[0])):
        if key.startswith("replay/") and note.get("drawn") and key in data.figures:
            replay_figs.append({**note, "band": tuple(note["band"]), "uri": figures.data_uri(data.figures[key])})
    undrawn = sorted(
        n.get("cls") for k, n in data.figure_notes.items() if k.startswith("replay/") and not n.get("drawn")
    )
    if undrawn:  # figure_replay had no real log of the class (simpick.report.draw.replay)
        replay_notes.append(f"no real log to draw for {', '.join(c.replace('_', ' ') for c in undrawn)}")

    limits_classes = [
        {
            "cls": c,
            "label": c.replace("_", " "),
            "friction": class_params[c].friction if c in class_params else None,
            "source": class_params[c].source if c in class_params else None,
        }
        for c in (list(class_params) + [c for c in shown_classes if c not in class_params])
    ]
    prov = data.segments_provenance or {}
    n_small = {}
    for item in class_blocks:
        for b in item["sets"]:
            ns = [r["n_runs"] if r.get("n_runs") is not None else r["n"] for r in b["rows"]]
            if ns:
                n_small.setdefault(b["set"], []).append((item["cls"], min(ns)))
    return {
        "given": given,
        "sets": sets,
        "missing": missing,
        "empty": empty,
        "classes": class_blocks,
        "pairwise": pairwise,
        "glance": glance,
        "gain_uri": gain_uri,
        "turning": turning,
        "segments": _segments_table(data, classes, engines),
        "provenance": {
            "derived_by": prov.get("derived_by"),
            "found": prov.get("segments_found"),
            "kept": prov.get("segments_kept"),
        },
        "replay": "replay" in sets,
        "replay_figs": replay_figs,
        "replay_notes": replay_notes,
        "limits_classes": limits_classes,
        "dataset": (rd.dataset or (acc or {}).get("dataset")),
        "dataset_text": prov.get("dataset"),
        "scored_set": scored_set,
        "window": rd.window,
        "segment_rules": rd.segment_rules.model_dump(mode="json") if rd.segment_rules else {},
        "n_small": n_small,
        "stats": stats,
        # a dataset folder was given (the plan states its dataset): its replay's results were wanted
        "replay_wanted": rd.datasets.replay is not None,
        "datasets": datasets(data, rd.datasets),
    }
