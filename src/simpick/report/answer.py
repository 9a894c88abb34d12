"""The report's first page: the answer, per engine, as the verdict rule wrote it.

Three tables of ``results/verdict/`` hold it (simpick.score.verdict): ``answer.csv`` (one row per
engine: mechanics, each real-data metric's outcome against the best engine with its interval and
margin, the gain ratio, the real-time factor, the CPU load and the paper's weighted total),
``outcomes.csv`` (one row per metric and engine: the metric's label, unit, margin and where the
margin comes from) and ``answer.yaml`` (one sentence per user need, and the table rows it rests on).
This module only arranges their cells for the template: it computes no outcome, total or rank.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import pandas as pd

# The real-data metrics in the order the answer shows them (outcomes.csv's ``metric`` column).
METRIC_ORDER = ("gain_error", "heading_error", "speed_error")
OUTCOME_ORDER = ("best", "equivalent", "undetermined", "too few runs", "worse", "not measurable")
OUTCOME_CLASS = {
    "best": "best",
    "equivalent": "equivalent",
    "worse": "worse",
    "undetermined": "undetermined",
    "too few runs": "undetermined",
    "not measurable": "unmeasured",
}
# Each user need, the section of the report its sentence rests on (its figure), and that figure's name.
NEED_FIGURES = {
    "closest": ("answer-figure", "Figure 1"),
    "failed": ("health", "Health of the runs"),
    "fastest": ("quantitative", "the real-time factor table"),
    "settings": ("calibration", "the calibration figure"),
    "avoid": ("validation", "the analytic-mechanics figure"),
}
NEED_TITLES = {
    "closest": "Closest to the real robot",
    "failed": "Runs an engine failed",
    "fastest": "Fastest among those that pass mechanics",
    "settings": "To turn like the real robot",
    "avoid": "Avoid",
}


def _isnan(x: Any) -> bool:
    if x is None:
        return True
    try:
        return math.isnan(float(x))
    except (TypeError, ValueError):
        return str(x) == ""


def _value(x: Any) -> float | None:
    return None if _isnan(x) else float(x)


def _metrics(outcomes: pd.DataFrame | None, answer: pd.DataFrame) -> list[dict[str, Any]]:
    """The metrics the answer table has columns for, with label, unit, margin and its basis."""
    keys = [m for m in METRIC_ORDER if f"{m}_outcome" in answer.columns]
    keys += [
        c[: -len("_outcome")] for c in answer.columns if c.endswith("_outcome") and c[: -len("_outcome")] not in keys
    ]
    out = []
    for m in keys:
        info: dict[str, Any] = {"key": m, "label": m.replace("_", " "), "unit": "", "margin": None, "basis": ""}
        if outcomes is not None:
            sel = outcomes[outcomes["metric"] == m]
            if len(sel):
                first = sel.iloc[0]
                info.update(
                    label=str(first["label"]) or info["label"],
                    unit=str(first["unit"]),
                    margin=_value(first["margin"]),
                    basis=str(first["margin_basis"]),
                )
        out.append(info)
    return out


def _figure_ref(need: str, sentence: Mapping[str, Any], have: set[str]) -> dict[str, str] | None:
    anchor, name = NEED_FIGURES.get(need, (None, None))
    if sentence.get("figure"):  # the verdict may name the figure itself
        anchor, name = str(sentence["figure"]), str(sentence.get("figure_title") or sentence["figure"])
    if anchor is None or anchor not in have:
        return None
    return {"anchor": anchor, "name": name}


def answer_section(
    answer: pd.DataFrame | None,
    outcomes: pd.DataFrame | None,
    sentences: Mapping[str, Any] | None,
    engines: Sequence[str],
    figure_uri: str | None,
    sections: set[str],
    basis: str | None = None,
    units: str = "runs",
) -> dict[str, Any]:
    """The first page's table, sentences and figure. ``sections``: the anchors the report has,
    so that a sentence cites only a figure that is there. ``basis``: the headline's sentence naming the
    real data the answer rests on, ``units`` what its units are called ("runs", "steps"): both from
    results/verdict/headline.yaml."""
    if answer is None:
        return {
            "given": False,
            "basis": "",
            "flagged": [],
            "rows": [],
            "metrics": [],
            "sentences": [],
            "by_engine": {},
            "unmeasured": [],
        }
    metrics = _metrics(outcomes, answer)
    # a metric no engine could be measured on gets a line under the table, not a column of dashes
    unmeasured = [
        m for m in metrics if all(str(v) in ("not measurable", "", "nan") for v in answer[f"{m['key']}_outcome"])
    ]
    metrics = [m for m in metrics if m not in unmeasured]
    order = {e: i for i, e in enumerate(engines)}
    rows = []
    for r in answer.to_dict("records"):
        cells = {}
        for m in metrics:
            k = m["key"]
            outcome = str(r.get(f"{k}_outcome") or "")
            cells[k] = {
                "outcome": outcome,
                "css": OUTCOME_CLASS.get(outcome, "undetermined"),
                "diff": _value(r.get(f"{k}_diff")),
                "low": _value(r.get(f"{k}_low")),
                "high": _value(r.get(f"{k}_high")),
                "margin": _value(r.get(f"{k}_margin")),
            }
        failed = _value(r.get("mechanics_failed"))
        rows.append(
            {
                "engine": str(r["engine"]),
                "passes": str(r["mechanics"]) == "pass",
                "mechanics_failed": None if failed is None else int(failed),
                "mechanics_cases": None
                if _value(r.get("mechanics_cases")) is None
                else int(float(r["mechanics_cases"])),
                "mechanics_note": str(r.get("mechanics_note") or ""),
                "cells": cells,
                # the note's kinds ("yaw gain (12), incline (2)") under the count the cell already shows
                "mechanics_kinds": str(r.get("mechanics_note") or "").split(": ", 1)[-1],
                "gain_ratio": _value(r.get("gain_ratio")),
                "gain_ratio_calibrated": _value(r.get("gain_ratio_calibrated")),
                "rtf": _value(r.get("rtf")),
                "cpu_average": _value(r.get("cpu_average")),
                "cpu_intense": _value(r.get("cpu_intense")),
                "paper_total": _value(r.get("paper_total")),
                "paper_rank": None if _value(r.get("paper_rank")) is None else int(float(r["paper_rank"])),
                "paper_flag": str(r.get("paper_flag") or ""),
            }
        )
    # engines that pass the mechanics first, each group in the order of its outcomes on the first metric
    # (best, equivalent, undetermined, worse), then by the paper's rank: the table reads from the pick down
    first = metrics[0]["key"] if metrics else None
    rank = {o: i for i, o in enumerate(OUTCOME_ORDER)}
    rows.sort(
        key=lambda r: (
            not r["passes"],
            rank.get(r["cells"][first]["outcome"], len(rank)) if first else 0,
            r["paper_rank"] if r["paper_rank"] is not None else len(rows),
            order.get(r["engine"], len(order)),
        )
    )
    said = []
    for s in (sentences or {}).get("sentences") or []:
        need = str(s.get("need") or "")
        said.append(
            {
                "need": need,
                "title": NEED_TITLES.get(need, need),
                "text": str(s.get("text") or ""),
                "rests_on": [str(x) for x in s.get("rests_on") or []],
                "figure": _figure_ref(need, s, sections),
            }
        )
    return {
        "given": True,
        "basis": str(basis or ""),
        "units": units,
        "metrics": metrics,
        "unmeasured": unmeasured,
        "rows": rows,
        "by_engine": {r["engine"]: r for r in rows},
        "sentences": said,
        "figure_uri": figure_uri,
        "calibrated": any(r["gain_ratio_calibrated"] is not None for r in rows),
        "flagged": [r for r in rows if r["paper_flag"]],
    }
