"""Turn the loaded inputs into the template's context, render the HTML, write the PDF."""

from __future__ import annotations

import datetime as _dt
import math
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from simpick.report import figures
from simpick.report.draw import test_label
from simpick.report.draw import weights_of as _weights
from simpick.report.load import ReportData
from simpick.score.scoring import DEFAULT_WEIGHTS, METRIC_LABELS, METRICS, QUALITATIVE_METRICS, QUANTITATIVE_METRICS

TEMPLATE_DIR = Path(__file__).resolve().parent / "templates"
TEMPLATE = "report.html.j2"
DEFAULT_TITLE = "simpick: which physics engine reproduces the Husky best?"

ROS_TEXT = {
    "out_of_the_box": "out of the box",
    "official_plugin": "official plugin (installed by hand)",
    "none": "none",
}
UI_TEXT = {"full": "full", "partial": "partial", "visualization": "visualization only", "none": "none"}
FACT_ROWS = ("free", "open_source", "ros", "languages", "ui", "model_formats", "physics_engines")
QUANTITY_UNITS = {"angular": "rad/s", "linear": "m/s²"}
# one colour per metric of the paper's weighted table (qualitative in darker, quantitative in distinct hues)
METRIC_PALETTE = (
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#d62728",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#7f7f7f",
    "#bcbd22",
    "#17becf",
    "#aec7e8",
    "#ffbb78",
)


# --------------------------------------------------------------------------
# Formatting (Jinja filters)
# --------------------------------------------------------------------------


def _isnan(x: Any) -> bool:
    if x is None:
        return True
    try:
        return math.isnan(float(x))
    except (TypeError, ValueError):
        return False


def fmt(x: Any, digits: int = 3) -> str:
    """A number with ``digits`` decimals; very small non-zero values in 3 significant figures."""
    if _isnan(x):
        return "–"
    try:
        v = float(x)
    except (TypeError, ValueError):
        return str(x)
    if math.isinf(v):
        return "∞" if v > 0 else "−∞"
    if digits >= 3 and v != 0 and abs(v) < 0.5 * 10 ** (-digits):
        return f"{v:.2e}".replace("-", "−")
    s = f"{v:.{digits}f}"
    if s.startswith("-"):
        s = "−" + s[1:]
    return "0." + "0" * digits if s == "−0." + "0" * digits else s


def fmt_num(x: Any) -> str:
    """A weight or other round figure: no decimals when it is a whole number."""
    if _isnan(x):
        return "–"
    v = float(x)
    return f"{v:.0f}" if v == round(v) else fmt(v, 2)


def fmt_sig(x: Any) -> str:
    """A measurement spanning orders of magnitude (a real-time factor): 3 significant figures."""
    if _isnan(x):
        return "–"
    v = float(x)
    return f"{v:.3g}" if abs(v) < 1000 else f"{v:,.0f}".replace(",", "\u2009")


def fmt_int(x: Any) -> str:
    if _isnan(x):
        return "–"
    return f"{int(round(float(x))):,}".replace(",", "\u2009")


def fmt_signed(x: Any, digits: int = 3) -> str:
    s = fmt(x, digits)
    if s not in ("–",) and not s.startswith("−") and float(x) != 0:
        s = "+" + s
    return s


def fmt_yes_no(x: Any) -> str:
    if isinstance(x, bool):
        return "yes" if x else "no"
    return "–" if x is None else str(x)


def soft_lower(text: str) -> str:
    """Lower-case the first letter unless the first word is an acronym (IMU, UI, ROS)."""
    if len(text) > 1 and text[0].isupper() and text[1].islower():
        return text[0].lower() + text[1:]
    return text


# --------------------------------------------------------------------------
# Context
# --------------------------------------------------------------------------


def _test_order(data: ReportData, config: Mapping[str, Any]) -> list[tuple[str, str]]:
    seen: list[tuple[str, str]] = []
    frames = [data.runs]
    for df in (data.trace_stats, data.per_test_errors, data.reference_stats):
        if df is not None:
            frames.append(df)
    for df in frames:
        for t, m in zip(df["terrain"], df["motion"]):
            if (t, m) not in seen:
                seen.append((t, m))
    terrains = list((config.get("terrains") or {}).keys())
    motions = list((config.get("motions") or {}).keys())

    def key(tm):
        t, m = tm
        return (
            terrains.index(t) if t in terrains else len(terrains),
            motions.index(m) if m in motions else len(motions),
            seen.index(tm),
        )

    return sorted(seen, key=key)


def _engine_order(data: ReportData, first: list[str] | None = None) -> list[str]:
    """The engines in the ranking's order (weighted.csv), then any other engine a table names. With
    ``first`` (the study's engines, the figures' order) the order reads no weight: the engines the
    tables name, those in ``first`` in its order, then the others as they come (the appendices)."""
    engines = list(data.weighted.index) if first is None else []
    frames = [data.runs, data.trace_stats, data.imu_errors, data.rtf, data.accuracy_errors]
    frames += [tables.get(k) for tables in data.real.values() for k in ("summary", "per_test")]
    for df in frames:
        if df is not None:
            for e in df["engine"]:
                if e not in engines:
                    engines.append(e)
    if first is not None:
        pos = {e: i for i, e in enumerate(first)}
        engines.sort(key=lambda e: pos.get(e, len(pos)))  # stable: the others as they came
    return engines


def _ranking(data: ReportData, weights: dict[str, float]) -> dict[str, Any]:
    """The paper's ranking and weighted table as the scores job wrote them: totals and ranks from
    weighted.csv, every weight x score cell from contributions.csv (simpick.score.contributions)."""
    w = data.weighted
    rows = []
    for e in w.index:
        excluded = [m for m in str(w.loc[e, "excluded"]).split(",") if m.strip()]
        rows.append(
            {
                "engine": e,
                "rank": int(w.loc[e, "rank"]) if not _isnan(w.loc[e, "rank"]) else None,
                "total": float(w.loc[e, "total"]),
                "excluded": [METRIC_LABELS.get(m.strip(), m.strip()) for m in excluded],
            }
        )
    metric_rows, bars = [], []
    c = data.contributions
    if c is not None:
        cells = {(r["engine"], r["metric"]): r for r in c.to_dict("records")}
        for m in dict.fromkeys(c["metric"]):
            first = c[c["metric"] == m].iloc[0]
            metric_rows.append(
                {
                    "key": m,
                    "label": first["label"],
                    "weight": first["weight"],
                    "group": first["group"],
                    "cells": [
                        {
                            "score": cells[(e, m)]["score"],
                            "weighted": cells[(e, m)]["points"],
                            "nan": bool(cells[(e, m)]["excluded"]),
                        }
                        if (e, m) in cells
                        else {"score": None, "weighted": None, "nan": True}
                        for e in w.index
                    ],
                }
            )
        for e in w.index:
            bars.append(
                {
                    "engine": e,
                    "parts": [
                        {"metric": r["metric"], "label": r["label"], "weighted": r["points"]}
                        for r in c[c["engine"] == e].to_dict("records")
                    ],
                }
            )
        for r in rows:
            sel = c[c["engine"] == r["engine"]]
            r["share"] = sel["share"].iloc[0] if len(sel) else None
    gap = None
    d = data.drivers
    if d is not None and len(rows) >= 2 and len(d):
        second = d[d["engine"] == rows[1]["engine"]]
        if len(second):
            # the drivers table orders the metrics by how far each puts the leader ahead (order 1 first)
            second = second.sort_values("order", kind="mergesort")
            gap = {
                "leader": second["leader"].iloc[0],
                "second": rows[1]["engine"],
                "value": second["gap"].iloc[0],
                "drivers": [
                    (r["label"], r["difference"]) for r in second.head(3).to_dict("records") if r["difference"] > 0
                ],
                "against": [
                    (r["label"], r["difference"])
                    for r in second.iloc[::-1].head(3).to_dict("records")
                    if r["difference"] < 0
                ],
            }
    return {
        "rows": rows,
        "metric_rows": metric_rows,
        "bars": bars,
        "max_total": sum(weights.values()),
        "engines": list(w.index),
        "given": c is not None,
        "gap": gap,
    }


def _qualitative(data: ReportData, engines: list[str], ref_order: list[str] | None = None) -> dict[str, Any] | None:
    """The qualitative facts per engine (columns in ``engines``' order). The sources are numbered
    walking ``ref_order`` (default ``engines``): the appendices list them, and read no weight, so the
    body numbers them in the same weight-free order whatever its columns' order."""
    q = data.qualitative
    if not q:
        return None
    shown = [e for e in engines if e in q] + [e for e in q if e not in engines]
    order = ref_order if ref_order is not None else engines
    numbered = [e for e in order if e in q] + [e for e in q if e not in order]
    refs: list[dict[str, Any]] = []
    ref_index: dict[str, int] = {}

    def ref(engine: str, fact: str) -> list[int]:
        src = (q[engine].get("sources") or {}).get(fact)
        if not src:
            return []
        items = src if isinstance(src, list) else [src]
        nums = []
        for item in items:
            text = str(item).strip()
            if text not in ref_index:
                ref_index[text] = len(refs) + 1
                m = re.match(r"^(https?://\S+?)([.,;:]?(?:\s+.*)?)$", text)
                url, rest = (m.group(1), m.group(2).strip()) if m else (None, text)
                refs.append({"n": ref_index[text], "text": text, "url": url, "rest": rest, "where": []})
            refs[ref_index[text] - 1]["where"].append(f"{engine}: {METRIC_LABELS.get(fact, fact)}")
            nums.append(ref_index[text])
        return nums

    def numbers(engine: str, fact: str) -> list[int]:
        """The numbers ref() gave a fact's sources (each source counted once, where first met)."""
        src = (q[engine].get("sources") or {}).get(fact)
        items = (src if isinstance(src, list) else [src]) if src else []
        return [ref_index[str(item).strip()] for item in items]

    def fact_text(rec: Mapping[str, Any], key: str) -> str:
        if key not in rec:
            return "–"
        v = rec[key]
        if isinstance(v, bool):
            return "yes" if v else "no"
        if key == "ros":
            return ROS_TEXT.get(str(v), str(v))
        if key == "ui":
            return UI_TEXT.get(str(v), str(v))
        if isinstance(v, (list, tuple)):
            text = ", ".join(str(x) for x in v) if v else "none"
        else:
            text = str(v)
        if key == "model_formats" and rec.get("urdf_sdf_via_manual_plugin"):
            text += "; URDF/SDF via a plugin installed by hand"
        return text

    for key in FACT_ROWS:  # the sources' numbers first, row by row in the weight-free order
        for e in numbered:
            ref(e, key)
    extra_keys = sorted({k for e in numbered for k in (q[e].get("sources") or {}) if k not in FACT_ROWS})
    for e in numbered:
        for k in extra_keys:
            ref(e, k)
    rows = []
    for key in FACT_ROWS:
        cells = []
        for e in shown:
            rec = q[e]
            score = data.weighted.loc[e, key] if (e in data.weighted.index and key in data.weighted.columns) else None
            cells.append({"text": fact_text(rec, key), "score": score, "refs": numbers(e, key)})
        rows.append({"key": key, "label": METRIC_LABELS.get(key, key), "cells": cells})
    family = []
    for e in shown:
        sims = q[e].get("paper_simulators")
        family.append({"engine": e, "simulators": list(sims) if sims else [], "known": "paper_simulators" in q[e]})
    notes = []
    for e in numbered:
        for k, text in (q[e].get("notes") or {}).items():
            notes.append({"engine": e, "fact": METRIC_LABELS.get(k, k), "text": str(text)})
    return {"engines": shown, "rows": rows, "refs": refs, "family": family, "notes": notes}


def _runs(data: ReportData, tests: list[tuple[str, str]], engines: list[str]) -> dict[str, Any]:
    runs = data.runs.copy()
    runs["test"] = [test_label(t, m) for t, m in zip(runs["terrain"], runs["motion"])]
    order = {tm: i for i, tm in enumerate(tests)}
    runs["_e"] = [engines.index(e) if e in engines else len(engines) for e in runs["engine"]]
    runs["_t"] = [order.get((t, m), len(order)) for t, m in zip(runs["terrain"], runs["motion"])]
    runs = runs.sort_values(["_e", "_t"], kind="mergesort")
    records = runs.to_dict("records")
    failed = [r for r in records if str(r["status"]).strip().lower() != "ok"]
    pivot = []
    for t, m in tests:
        cells = []
        for e in engines:
            sel = runs[(runs["engine"] == e) & (runs["terrain"] == t) & (runs["motion"] == m)]
            if len(sel):
                r = sel.iloc[0]
                cells.append(
                    {
                        "steps_per_s": r["steps_per_s"],
                        "rtf": r["real_time_factor"],
                        "ok": str(r["status"]).strip().lower() == "ok",
                        "present": True,
                    }
                )
            else:
                cells.append({"present": False})
        pivot.append({"test": test_label(t, m), "cells": cells})
    versions = [
        {
            "engine": r["engine"],
            "test": r["test"],
            "version": r["engine_version"] or "–",
            "config_hash": r["config_hash"] or "–",
        }
        for r in records
    ]
    return {"records": records, "failed": failed, "n": len(records), "pivot": pivot, "versions": versions}


def _cpu(data: ReportData, engines: list[str]) -> dict[str, Any] | None:
    if not data.cpu:
        return None
    recs = sorted(data.cpu, key=lambda r: engines.index(r["engine"]) if r["engine"] in engines else len(engines))
    rows = []
    for r in recs:
        e = r["engine"]
        health = r.get("health") or {}
        row = {
            "engine": e,
            "status": health.get("status", "unchecked" if not health else "ok"),
            "reasons": list(health.get("reasons") or []),
        }
        for scen in ("average", "intense"):
            s = r.get(scen) or {}
            row[scen] = {
                "robots": s.get("robots"),
                "load": s.get("load_percent"),
                "repeats": list(s.get("repeats_percent") or []),
                "score": data.weighted.loc[e, f"cpu_{scen}"] if e in data.weighted.index else None,
            }
        rows.append(row)
    definitions = []
    for r in recs:
        d = str(r.get("definition", "")).strip()
        if d and d not in [x["text"] for x in definitions]:
            definitions.append({"text": d, "engines": [r["engine"]]})
        elif d:
            next(x for x in definitions if x["text"] == d)["engines"].append(r["engine"])
    return {"rows": rows, "definitions": definitions, "n_defs": len(definitions)}


def _imu(data: ReportData, engines: list[str], tests: list[tuple[str, str]]) -> dict[str, Any] | None:
    if data.imu_errors is None:
        return None
    ie = data.imu_errors.copy()
    ie["_e"] = [engines.index(e) if e in engines else len(engines) for e in ie["engine"]]
    ie = ie.sort_values(["quantity", "_e"], kind="mergesort")
    rows = []
    for r in ie.to_dict("records"):
        key = f"imu_{r['quantity']}"
        score = (
            data.weighted.loc[r["engine"], key]
            if (r["engine"] in data.weighted.index and key in data.weighted.columns)
            else None
        )
        rows.append(
            {
                **r,
                "score": score,
                "tests_list": [t for t in str(r["tests"]).split(";") if t.strip()],
                "excluded_list": [t for t in str(r["excluded"]).split(";") if t.strip()],
            }
        )
    coverage = {}
    for q, sel in ie.groupby("quantity"):
        n = sorted({int(x) for x in sel["n_tests"] if not _isnan(x)})
        coverage[q] = n
    uneven = {q: n for q, n in coverage.items() if len(n) > 1}
    breakdown = []
    pte = data.per_test_errors
    if pte is not None and len(pte):
        order = {tm: i for i, tm in enumerate(tests)}
        for q in ("angular", "linear"):
            sel = pte[pte["quantity"] == q]
            if not len(sel):
                continue
            trs = []
            for e in engines:
                es = sel[sel["engine"] == e]
                keys = sorted(
                    {(t, m) for t, m in zip(es["terrain"], es["motion"])}, key=lambda tm: order.get(tm, len(order))
                )
                for t, m in keys:
                    ts = es[(es["terrain"] == t) & (es["motion"] == m)].set_index("axis")
                    cells = {
                        a: (
                            {"range": ts.loc[a, "range_error"], "mean": ts.loc[a, "mean_error"]}
                            if a in ts.index
                            else None
                        )
                        for a in figures.AXES
                    }
                    trs.append(
                        {"engine": e, "test": test_label(t, m), "cells": cells, "total": float(ts["total_error"].sum())}
                    )
            breakdown.append({"quantity": q, "unit": QUANTITY_UNITS[q], "rows": trs})
    return {"rows": rows, "uneven": uneven, "breakdown": breakdown}


def _reference(data: ReportData, tests: list[tuple[str, str]]) -> dict[str, Any]:
    ref = data.reference_stats
    have: list[dict[str, Any]] = []
    if ref is not None and len(ref):
        for (t, m), sel in ref.groupby(["terrain", "motion"], sort=False):
            srcs = sorted({s for s in sel["source"] if s})
            have.append(
                {
                    "terrain": t,
                    "motion": m,
                    "test": test_label(t, m),
                    "sources": srcs,
                    "quantities": sorted(set(sel["quantity"])),
                }
            )
    keys = {(h["terrain"], h["motion"]) for h in have}
    without = [test_label(t, m) for t, m in tests if (t, m) not in keys]
    covered = None
    if data.imu_errors is not None:
        covered = sorted({t for ts in data.imu_errors["tests"] for t in str(ts).split(";") if t.strip()})
    return {"tests": have, "without": without, "covered": covered, "given": ref is not None}


def _status_map(data: ReportData) -> dict[tuple[str, str, str], str]:
    return {
        (r["engine"], r["terrain"], r["motion"]): str(r["status"]).strip().lower() for r in data.runs.to_dict("records")
    }


def _per_test(data: ReportData, engines: list[str], tests: list[tuple[str, str]]) -> list[dict[str, Any]]:
    """Per lab test: its figures (rules figure_imu_stats, figure_traces) and where each run ended
    (rule figure_paths' endpoints table)."""
    status = _status_map(data)
    ref = data.reference_stats
    ends = data.endpoints
    out = []
    for t, m in tests:
        item: dict[str, Any] = {"test": test_label(t, m), "terrain": t, "motion": m}
        failed = [e for e in engines if status.get((e, t, m), "ok") != "ok" and (e, t, m) in status]
        item["failed"] = failed
        if data.trace_stats is not None:
            rsel = None
            if ref is not None:
                rsel = ref[(ref["terrain"] == t) & (ref["motion"] == m)]
                if len(rsel):
                    item["reference_sources"] = sorted({s for s in rsel["source"] if s})
            item["has_reference"] = rsel is not None and len(rsel) > 0
            key = f"imu_stats/{t}/{m}"
            item["imu_uri"] = figures.data_uri(data.figures[key]) if key in data.figures else None
        if ends is not None:
            sel = ends[(ends["terrain"] == t) & (ends["motion"] == m)]
            rows = {r["engine"]: r for r in sel.to_dict("records")}
            item["trace_engines"] = [e for e in engines if e in rows]
            item["missing_traces"] = [e for e in engines if e not in rows and e not in failed and (e, t, m) in status]
            key = f"traces/{t}/{m}"
            item["ts_uri"] = figures.data_uri(data.figures[key]) if key in data.figures and rows else None
            item["endpoints"] = [rows.get(e) for e in engines]
        out.append(item)
    return out


def _published(data: ReportData) -> dict[str, Any] | None:
    if data.table11 is None:
        return None
    t11 = data.table11
    sims = list(t11.index)
    cmp_ = data.table11_comparison
    lookup = {}
    if cmp_ is not None:
        for r in cmp_.to_dict("records"):
            lookup[(r["simulator"], r["metric"])] = r
    rows = []
    for m in METRICS:
        cells = []
        for s in sims:
            c = lookup.get((s, m))
            cells.append(
                {
                    "published": c["published"] if c else None,
                    "recomputed": t11.loc[s, m] if m in t11.columns else None,
                    "matches": bool(c["matches"]) if c else None,
                }
            )
        rows.append({"label": METRIC_LABELS.get(m, m), "weight": DEFAULT_WEIGHTS[m], "cells": cells})
    totals = [
        {
            "simulator": s,
            "total": t11.loc[s, "total"],
            "from_published": t11.loc[s, "total_from_published_scores"],
            "printed": t11.loc[s, "published_total"],
            "diff": float(t11.loc[s, "published_total"]) - float(t11.loc[s, "total_from_published_scores"]),
            "diff_recomputed": float(t11.loc[s, "total"]) - float(t11.loc[s, "published_total"]),
        }
        for s in sims
    ]
    mismatches = [r for r in (cmp_.to_dict("records") if cmp_ is not None else []) if not r["matches"]]
    for r in mismatches:
        r["label"] = METRIC_LABELS.get(r["metric"], r["metric"])
    return {
        "sims": sims,
        "rows": rows,
        "totals": totals,
        "mismatches": mismatches,
        "n_compared": 0 if cmp_ is None else len(cmp_),
    }


def _worked(data: ReportData) -> dict[str, Any] | None:
    we = data.worked_example
    if not we:
        return None
    blocks = []
    for q in ("angular", "linear"):
        b = we.get(q)
        if not b:
            continue
        axes = []
        for a in figures.AXES:
            rec = (b.get("axes") or {}).get(a, {})
            pr = (b.get("printed_axes") or {}).get(a, {})
            axes.append(
                {
                    "axis": a,
                    "rec": rec,
                    "printed": pr,
                    "differs": any(
                        abs(float(rec.get(k, 0)) - float(pr.get(k, 0))) > 1e-9
                        for k in ("range_error", "mean_error", "total_error")
                        if k in rec and k in pr
                    ),
                }
            )
        figs = [b.get("total_from_inputs"), b.get("printed_rows_sum"), b.get("text_total")]
        agree = all(f is not None for f in figs) and max(figs) - min(figs) < 1e-9
        blocks.append(
            {
                "quantity": q,
                "unit": b.get("unit", QUANTITY_UNITS[q]),
                "axes": axes,
                "total_from_inputs": b.get("total_from_inputs"),
                "printed_rows_sum": b.get("printed_rows_sum"),
                "text_total": b.get("text_total"),
                "agree": agree,
            }
        )
    return {
        "source": we.get("source"),
        "test": we.get("test") or {},
        "frame": we.get("sensor_frame") or {},
        "blocks": blocks,
    }


def _verdict(data: ReportData, engines: list[str]) -> dict[str, Any]:
    """simpick's verdict tables beside the answer (results/verdict/): the outcomes of every engine
    against the best per metric, the headline paragraph, and the paper's total with its interval
    over real runs. Nothing here is computed: the tables are printed."""
    outcomes, rank = data.verdict.get("outcomes"), data.verdict.get("ranking")
    head = data.verdict_headline or {}
    if outcomes is None and not head:
        return {"given": False, "ranking": {}, "metrics": []}
    order = {e: i for i, e in enumerate(engines)}
    metrics = []
    if outcomes is not None:
        for metric, g in outcomes.groupby("metric", sort=False):
            rows = sorted(g.to_dict("records"), key=lambda r: order.get(r["engine"], len(order)))
            first = rows[0]
            metrics.append(
                {
                    "metric": metric,
                    "label": first["label"],
                    "unit": first["unit"] or "",
                    "margin": first["margin"],
                    "basis": first["margin_basis"],
                    "best": first["best"],
                    "unmeasured": all(r["outcome"] == "not measurable" for r in rows),
                    "rows": rows,
                }
            )
    ranking = {}
    if rank is not None:
        for r in rank.to_dict("records"):
            ranking[str(r["engine"])] = {
                "low": r["total_low"],
                "high": r["total_high"],
                "share_first": r["share_first"],
                "n_runs": r["n_runs"],
            }
    return {
        "given": True,
        "paragraph": head.get("paragraph"),
        "n_runs": head.get("n_runs"),
        "units": head.get("units") or "runs",
        "source": head.get("source_title") or head.get("source"),
        "metrics": metrics,
        "ranking": ranking,
    }


def _interactive(data: ReportData, weights: dict[str, float], simulators: str | None = None) -> str | None:
    """The decision tree in the browser: the simulators' (their leaves name simulators) where the study ran
    any, else the engines'."""
    from simpick.report.interactive import choose_fragment

    folder = Path(simulators) if simulators else None
    if folder is not None and (folder / "tree.json").is_file() and (folder / "weighted.csv").is_file():
        from simpick.score.tree import read_tree

        return choose_fragment(
            read_tree(str(folder / "tree.json")),
            __import__("pandas").read_csv(folder / "weighted.csv"),
            weights,
            noun="simulator",
            weighted_file="results/simulators/weighted.csv",
        )
    if data.tree is None:
        return None
    return choose_fragment(data.tree, data.weighted, weights)


def _opt_in(opt_in: Mapping[str, Any]) -> list[dict[str, Any]]:
    """The opt-in engines this study did not run, one entry per switch: the engines, the command, and
    what they would add (their jobs' measured wall seconds on one core, against the configured
    engines'), or that their cost is not measured yet."""
    by_switch: dict[str, list[str]] = {}
    for engine, entry in sorted(opt_in.items()):
        by_switch.setdefault(entry["switch"], []).append(engine)
    found = []
    for switch, engines in by_switch.items():
        seconds = [opt_in[e]["seconds"] for e in engines]
        study = opt_in[engines[0]]["study_seconds"]
        added = None if None in seconds or not study else sum(seconds)
        found.append(
            {
                "engines": engines,
                "switch": switch,
                "seconds": added,
                "study_seconds": study,
                "share": None if added is None else added / study,
            }
        )
    return found


def build_context(data: ReportData, params: Mapping[str, Any]) -> dict[str, Any]:
    import yaml

    from simpick.engines.simulators import is_profile
    from simpick.report import provenance, real
    from simpick.report.answer import answer_section
    from simpick.report.draw import colors as draw_colors
    from simpick.report.simulators import simulators_section

    config = dict(params.get("config") or {})
    weights = _weights(params)
    engines = _engine_order(data)
    # the figures' colours: params engines (rules/report.smk FIGURE_ENGINES), not the ranking
    colors = draw_colors(params.get("engines"), engines)
    tests = _test_order(data, config)
    ranking = _ranking(data, weights)
    per_test = _per_test(data, engines, tests)
    paths_uri = (
        figures.data_uri(data.figures["paths"])
        if "paths" in data.figures and data.endpoints is not None and len(data.endpoints)
        else None
    )
    runs = _runs(data, tests, engines)
    rtf_rows = []
    if data.rtf is not None:
        for r in data.rtf.to_dict("records"):
            e = r["engine"]
            r["score"] = data.weighted.loc[e, "real_time_factor"] if e in data.weighted.index else None
            rtf_rows.append(r)
        rtf_rows.sort(key=lambda r: engines.index(r["engine"]) if r["engine"] in engines else len(engines))
    rtf_excluded = sorted(
        {t for r in rtf_rows for t in str(r.get("excluded") or "").split(";") if t.strip() and t != "nan"}
    )
    rtf_tests = sorted({t for r in rtf_rows for t in str(r.get("tests") or "").split(";") if t.strip() and t != "nan"})
    config_text = yaml.safe_dump(config, sort_keys=False, allow_unicode=True, width=100) if config else None
    # name, label; real_data_robot: whose the real data are, when not the study's robot's
    robot = {"name": None, "label": None, "real_data_robot": None, **dict(config.get("robot") or {})}
    classes = real.class_order(data, params)
    accuracy = real.accuracy(data, params, engines, classes, [test_label(t, m) for t, m in tests])
    real_data = real.real_section(data, params, engines, colors, classes, accuracy)
    from simpick.report.calibration import calibration_section
    from simpick.report.sweep import sweep_section
    from simpick.report.validation import validation_section

    verdict = _verdict(data, engines)
    tree_uri = figures.data_uri(data.figures["tree"]) if "tree" in data.figures else None
    # the anchors a sentence of the answer may cite: only sections this report shows
    sections = {"answer-figure"} if "answer" in data.figures else set()
    sections |= {"quantitative", "validation"} | ({"calibration"} if data.calibration is not None else set())
    sections |= {"real"} if real_data["given"] else set()
    drive, turnmap_uri = None, None
    if params.get("drive"):
        from simpick.report.steps import drive_section

        drive = drive_section(
            params["drive"],
            robot.get("label") or robot.get("name") or "robot",
            calibration=params.get("drive_calibration") or None,
        )
        turnmap = Path(params["drive"]) / "turnmap.png"
        turnmap_uri = figures.data_uri(turnmap) if turnmap.is_file() else None
    return {
        # the DRIVE comparison (simpick.report.steps): the verdict against the real robot where its
        # steps were replayed, with the turn map (simpick.report.turnmap) beside it
        "drive": drive,
        "turnmap_uri": turnmap_uri,
        "answer": answer_section(
            data.verdict.get("answer"),
            data.verdict.get("outcomes"),
            data.verdict_sentences,
            engines,
            figures.data_uri(data.figures["answer"]) if "answer" in data.figures else None,
            sections,
            (data.verdict_headline or {}).get("basis"),
            (data.verdict_headline or {}).get("units") or "runs",
        ),
        "tree_uri": tree_uri,
        # the simulators as rows (simpick.report.simulators), when the study runs any
        "simulators": simulators_section(params["simulators"], weights) if params.get("simulators") else None,
        # the decision tree and the adjustable weights, answered in the browser (simpick.report.interactive):
        # one self-contained fragment, hidden in print where figures/tree.png stands for it
        "interactive": _interactive(data, weights, params.get("simulators")),
        "validation": validation_section(
            data.validation, engines, data.figures.get("validation_gain"), data.validation_gains
        ),
        "sweep": sweep_section(data.sweep, engines, data.figures.get("sweep")),
        "calibration": calibration_section(
            data.calibration,
            engines
            + [
                e
                for e in (data.calibration.engine.unique() if data.calibration is not None else [])
                if e not in engines
            ],
            colors,
            data.calibration_turning,
            data.calibration_target,
        ),
        "title": params.get("title")
        or (
            f"simpick: which physics engine reproduces the {robot['label']} best?"
            if robot.get("label")
            else DEFAULT_TITLE
        ),
        "robot": robot,
        "generated": _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        "engines": engines,
        # the header's list: engines and reference models, the simulators' profiles counted apart
        "header_engines": [e for e in engines if not is_profile(e)],
        "header_profiles": [e for e in engines if is_profile(e)],
        # configured engines the machine could not run (simpick.plan: Plan.unavailable): engine -> why
        "unavailable": dict(params.get("unavailable") or {}),
        # registered engines this study leaves out and an opt-in config adds (simpick.plan: Plan.opt_in):
        # engine -> the switch that runs them and their jobs' measured seconds
        "opt_in": _opt_in(params.get("opt_in") or {}),
        "colors": colors,
        "weights": weights,
        "metrics": list(METRICS),
        "metric_colors": {m: METRIC_PALETTE[i % len(METRIC_PALETTE)] for i, m in enumerate(METRICS)},
        "labels": METRIC_LABELS,
        "qualitative_metrics": list(QUALITATIVE_METRICS),
        "quantitative_metrics": list(QUANTITATIVE_METRICS),
        "accuracy_weight": weights["imu_angular"] + weights["imu_linear"],
        "tests": [test_label(t, m) for t, m in tests],
        "ranking": ranking,
        "verdict": verdict,
        "reference": _reference(data, tests),
        "qualitative": _qualitative(data, list(data.weighted.index), _engine_order(data, params.get("engines") or [])),
        "rtf_rows": rtf_rows,
        "rtf_given": data.rtf is not None,
        "runs": runs,
        "cpu": _cpu(data, engines),
        "rtf_excluded": rtf_excluded,
        "rtf_tests": rtf_tests,
        "imu": _imu(data, engines, tests),
        "accuracy": accuracy,
        "real": real_data,
        "per_test": per_test,
        "traces_given": data.endpoints is not None,
        "stats_given": data.trace_stats is not None,
        "paths_uri": paths_uri,
        "published": _published(data),
        "worked": _worked(data),
        "versions": provenance.package_versions(),
        "machine": provenance.machine(),
        "config_text": config_text,
        "sources": data.sources,
    }


def appendix_context(data: ReportData, params: Mapping[str, Any]) -> dict[str, Any]:
    """The appendices' context (appendices.html.j2): the raw tables, which no weight reaches. It reads
    no weighted table (``data.weighted`` is ignored: no score is shown there) and orders the engines
    by the study's engines (params ``engines``, the figures' order), not the ranking, so that a weight
    edit leaves the appendices' job and its files as they are."""
    import dataclasses

    import pandas as pd
    import yaml

    from simpick.report import provenance, real
    from simpick.report.draw import colors as draw_colors
    from simpick.report.validation import validation_section

    data = dataclasses.replace(data, weighted=pd.DataFrame(index=pd.Index([], name="engine")))
    config = dict(params.get("config") or {})
    engines = _engine_order(data, params.get("engines") or [])
    colors = draw_colors(params.get("engines"), engines)
    tests = _test_order(data, config)
    classes = real.class_order(data, params)
    accuracy = real.accuracy(data, params, engines, classes, [test_label(t, m) for t, m in tests])
    paths_uri = (
        figures.data_uri(data.figures["paths"])
        if "paths" in data.figures and data.endpoints is not None and len(data.endpoints)
        else None
    )
    return {
        "title": params.get("title") or DEFAULT_TITLE,
        "engines": engines,
        "colors": colors,
        "runs": _runs(data, tests, engines),
        "imu": _imu(data, engines, tests),
        "accuracy": accuracy,
        "real": real.real_section(data, params, engines, colors, classes, accuracy),
        "per_test": _per_test(data, engines, tests),
        "traces_given": data.endpoints is not None,
        "stats_given": data.trace_stats is not None,
        "paths_uri": paths_uri,
        "published": _published(data),
        "worked": _worked(data),
        "validation": validation_section(
            data.validation, engines, data.figures.get("validation_gain"), data.validation_gains
        ),
        "qualitative": _qualitative(data, engines),
        "versions": provenance.package_versions(),
        "machine": provenance.machine(),
        "config_text": yaml.safe_dump(config, sort_keys=False, allow_unicode=True, width=100) if config else None,
        "sources": data.sources,
    }


# --------------------------------------------------------------------------
# Rendering
# --------------------------------------------------------------------------

APPENDIX_TEMPLATE = "appendices.html.j2"
APPENDIX_PAGE = "appendix_page.html.j2"


def environment():
    import jinja2

    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(TEMPLATE_DIR)),
        autoescape=jinja2.select_autoescape(["html", "j2"]),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
    )
    env.filters.update(
        f3=fmt,
        f=fmt,
        num=fmt_num,
        int=fmt_int,
        signed=fmt_signed,
        yesno=fmt_yes_no,
        isnan=_isnan,
        soft_lower=soft_lower,
        sig3=fmt_sig,
    )
    env.tests["nan"] = _isnan
    return env


def render_html(data: ReportData, params: Mapping[str, Any], appendices: str | None = None) -> str:
    """The report's page; ``appendices``: the HTML placed after the body (the fragment of
    :func:`render_appendix`), rendered here from ``data`` when not given: the whole report."""
    from markupsafe import Markup

    if appendices is None:
        appendices = render_appendix(data, params)[0]
    ctx = build_context(data, params)
    return environment().get_template(TEMPLATE).render(**ctx, appendices=Markup(appendices))


def render_appendix(data: ReportData, params: Mapping[str, Any]) -> tuple[str, str]:
    """The appendices: the HTML fragment the report places after its body, and the same fragment as
    a document of its own (the report's style), for their PDF."""
    from markupsafe import Markup

    env = environment()
    ctx = appendix_context(data, params)
    fragment = env.get_template(APPENDIX_TEMPLATE).render(**ctx)
    page = env.get_template(APPENDIX_PAGE).render(title=ctx["title"], fragment=Markup(fragment))
    return fragment, page


def anchor_ids(html: str) -> list[str]:
    """Every ``id`` an HTML fragment defines, in order."""
    return list(dict.fromkeys(re.findall(r"""\bid=["']([^"']+)["']""", html)))


def write_pdf(html: str, pdf_path: str | Path, base_url: str | None = None, footers: bool = True) -> None:
    """The PDF of ``html``. ``footers`` False: without the page's footer (the report's name and
    "page n of N"), for a part that :func:`simpick.report.pdf.join` puts in one document and numbers."""
    import logging

    import weasyprint

    # WeasyPrint logs each CSS property it ignores; the report's CSS is written for it.
    logging.getLogger("weasyprint").setLevel(logging.ERROR)
    pdf_path = Path(pdf_path)
    pdf_path.parent.mkdir(parents=True, exist_ok=True)
    tmp = pdf_path.with_name(pdf_path.name + ".partial")
    sheets = [] if footers else [weasyprint.CSS(string=NO_FOOTERS)]
    weasyprint.HTML(string=html, base_url=base_url).write_pdf(str(tmp), stylesheets=sheets)
    tmp.replace(pdf_path)


# !important: a user stylesheet's declaration wins over the document's (author) own only so
NO_FOOTERS = "@page { @bottom-left { content: none !important } @bottom-right { content: none !important } }"
