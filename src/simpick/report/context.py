"""The templates' contexts, in two parts that meet where the weights stop: the body's (the answer, the
ranking and weighted table, the verdict, the decision tree, the simulators, section 1 of the evidence),
which the weights reach, and the evidence's sections 2-5 and the appendices' (the tables of
:mod:`simpick.report.tables`), which no weight reaches, so that a job of its own renders them."""

from __future__ import annotations

import datetime as _dt
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from simpick.report import figures, tables
from simpick.report.draw import test_label
from simpick.report.draw import weights_of as _weights
from simpick.report.formats import isnan
from simpick.report.load import REAL_SETS, ReportData
from simpick.report.params import OptIn, ReportConfig, ReportParams, report_params
from simpick.score.scoring import METRIC_LABELS, METRICS, QUALITATIVE_METRICS, QUANTITATIVE_METRICS

DEFAULT_TITLE = "simpick: which physics engine reproduces the Husky best?"
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


def _ranking(data: ReportData, weights: dict[str, float]) -> dict[str, Any]:
    """The paper's ranking and weighted table as rule weighted wrote them: totals and ranks from
    weighted.csv, every weight x score cell from contributions.csv (simpick.score.contributions)."""
    w = data.weighted
    rows = []
    for e in w.index:
        excluded = [m for m in str(w.loc[e, "excluded"]).split(",") if m.strip()]
        rows.append(
            {
                "engine": e,
                "rank": int(w.loc[e, "rank"]) if not isnan(w.loc[e, "rank"]) else None,
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


def _opt_in(opt_in: Mapping[str, OptIn]) -> list[dict[str, Any]]:
    """The opt-in engines this study did not run, one entry per switch: the engines, the command, and
    what they would add (their jobs' measured wall seconds on one core, against the configured
    engines'), or that their cost is not measured yet."""
    by_switch: dict[str, list[str]] = {}
    for engine, entry in sorted(opt_in.items()):
        by_switch.setdefault(entry.switch, []).append(engine)
    found = []
    for switch, engines in by_switch.items():
        seconds = [opt_in[e].seconds for e in engines]
        study = opt_in[engines[0]].study_seconds
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


def _tree_leaves(data: ReportData) -> list[dict] | None:
    """Per leaf of the printed tree its letter and engines by the weighted total (weighted.csv)."""
    if data.tree is None or data.weighted is None:
        return None
    from simpick.report.tree_figure import leaf_rows

    return leaf_rows(data.tree, {e: float(t) for e, t in data.weighted["total"].items()})


def _title(config: ReportConfig, simulators: bool) -> str:
    """The question the page answers: which simulator, where the study runs simulators, else which engine."""
    robot = config.robot.label
    if simulators:
        name = robot or config.robot.name or "robot"
        return f"simpick: which simulator reproduces the {name} on its real runs, and with which settings?"
    return f"simpick: which physics engine reproduces the {robot} best?" if robot else DEFAULT_TITLE


def _simulator_answer(
    folder: str | None, answer: dict[str, Any], robot: str, units: str
) -> tuple[dict[str, Any] | None, list[dict]]:
    """The simulators' answer and its sentences from the simulators' table (results/simulators/table.csv, its
    settings folder beside it): (None, []) where the study runs no simulator. The robot's run-to-run spread
    of its gain, where the table has none, is the verdict's gain margin (the same figure)."""
    if not folder or not (Path(folder) / "table.csv").is_file():
        return None, []
    import pandas as pd

    from simpick.score.profiles import class_answer, simulator_answer
    from simpick.score.sentences import simulator_sentences

    gain = next((m for m in answer.get("metrics") or [] if m["key"] == "gain_error"), None)
    table = pd.read_csv(Path(folder) / "table.csv")
    found = simulator_answer(table, Path(folder) / "settings", spread=gain["margin"] if gain else None)
    per_class = Path(folder) / "per_class.csv"
    found["per_class"] = (
        class_answer(pd.read_csv(per_class), table, Path(folder) / "settings") if per_class.is_file() else []
    )
    return found, simulator_sentences(found, robot, f"real {units}")


def _robot(config: ReportConfig) -> dict[str, Any]:
    """name, label, track; real_data_robot: whose the real data are, when not the study's robot's."""
    return config.robot.model_dump(mode="json")


def _config_text(config: ReportConfig) -> str | None:
    """The report's slice of the study as the appendix shows it (None: none given)."""
    import yaml

    shown = config.model_dump(mode="json", exclude_defaults=True)
    return yaml.safe_dump(shown, sort_keys=False, allow_unicode=True, width=100) if shown else None


def build_context(data: ReportData, params: Mapping[str, Any] | ReportParams) -> dict[str, Any]:
    """The body's context (report.html.j2): the header, the answer, the DRIVE comparison, the decision
    tree, the ranking and weighted table, the simulators and section 1 of the evidence (what the answer
    rests on, with the verdict's outcomes), which the weights reach: the engines in the ranking's order,
    the weight points in the text. The evidence's sections 2-5 and the appendices are
    :func:`evidence_context`'s. ``params``: :class:`simpick.report.params.ReportParams`."""
    from simpick.engines.simulators import is_profile
    from simpick.report import real
    from simpick.report.answer import answer_section
    from simpick.report.draw import colors as draw_colors
    from simpick.report.simulators import simulators_section
    from simpick.report.validation import validation_headline

    p = report_params(params)
    weights = _weights(p.weights)
    engines = tables.engine_order(data)
    # the figures' colours: params engines (rules/report.smk FIGURE_ENGINES), not the ranking
    colors = draw_colors(p.engines, engines)
    tests = tables.test_order(data, p.config)
    robot = _robot(p.config)
    classes = real.class_order(data, p.real_data)
    accuracy = real.accuracy(data, p.statistics, engines, classes, [test_label(t, m) for t, m in tests])
    # whether section 5 has real data to show (real_section's "given"), without building the section
    real_given = any(data.real.get(s) for s in REAL_SETS) or data.segments is not None
    # the anchors a sentence of the answer may cite: only sections this report shows
    sections = {"answer-figure"} if "answer" in data.figures else set()
    sections |= {"quantitative", "validation"} | ({"calibration"} if data.calibration is not None else set())
    sections |= {"real"} if real_given else set()
    drive, turnmap_uri = None, None
    if p.drive:
        from simpick.report.steps import drive_section

        drive = drive_section(
            p.drive,
            p.config.robot.label or p.config.robot.name or "robot",
            calibration=p.drive_calibration or None,
        )
        turnmap = Path(p.drive) / "turnmap.png"
        turnmap_uri = figures.data_uri(turnmap) if turnmap.is_file() else None
    units = (data.verdict_headline or {}).get("units") or "runs"
    answer = answer_section(
        data.verdict.get("answer"),
        data.verdict.get("outcomes"),
        data.verdict_sentences,
        engines,
        figures.data_uri(data.figures["answer"]) if "answer" in data.figures else None,
        sections,
        (data.verdict_headline or {}).get("basis"),
        units,
    ) | {"cpu_robots": _cpu_robots(data)}
    label = p.config.robot.label or p.config.robot.name or "robot"
    simulator_answer, simulator_sentences = _simulator_answer(p.simulators, answer, label, units)
    return {
        # the first page's answer on the simulators (simpick.score.profiles.simulator_answer): None where the
        # study runs none, and the engines' answer is the page's
        "simulator_answer": simulator_answer,
        "simulator_sentences": simulator_sentences,
        "simulator_units": units,
        # the DRIVE comparison (simpick.report.steps): the verdict against the real robot where its
        # steps were replayed, with the turn map (simpick.report.turnmap) beside it
        "drive": drive,
        "turnmap_uri": turnmap_uri,
        "answer": answer,
        "tree_uri": figures.data_uri(data.figures["tree"]) if "tree" in data.figures else None,
        # the printed tree's leaves by the weighted total (the figure reads no weight: a weight edit
        # changes this table, not the figure; simpick.report.tree_figure)
        "tree_leaves": _tree_leaves(data) if "tree" in data.figures else None,
        # the simulators as rows (simpick.report.simulators), when the study runs any
        "simulators": simulators_section(p.simulators, weights) if p.simulators else None,
        # the decision tree and the adjustable weights, answered in the browser (simpick.report.interactive):
        # one self-contained fragment, hidden in print where figures/tree.png stands for it
        "interactive": _interactive(data, weights, p.simulators or None),
        "validation": validation_headline(data.validation, engines),
        "title": p.title or _title(p.config, simulator_answer is not None),
        "robot": robot,
        "generated": _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        "engines": engines,
        # the header's list: engines and reference models, the simulators' profiles counted apart
        "header_engines": [e for e in engines if not is_profile(e)],
        "header_profiles": [e for e in engines if is_profile(e)],
        # configured engines the machine could not run (simpick.plan: Plan.unavailable): engine -> why
        "unavailable": dict(p.unavailable),
        # registered engines this study leaves out and an opt-in config adds (simpick.plan: Plan.opt_in):
        # engine -> the switch that runs them and their jobs' measured seconds
        "opt_in": _opt_in(p.opt_in),
        "colors": colors,
        "weights": weights,
        "metrics": list(METRICS),
        "metric_colors": {m: METRIC_PALETTE[i % len(METRIC_PALETTE)] for i, m in enumerate(METRICS)},
        "labels": METRIC_LABELS,
        "qualitative_metrics": list(QUALITATIVE_METRICS),
        "quantitative_metrics": list(QUANTITATIVE_METRICS),
        "accuracy_weight": weights["imu_angular"] + weights["imu_linear"],
        "tests": [test_label(t, m) for t, m in tests],
        "ranking": _ranking(data, weights),
        "verdict": _verdict(data, engines),
        "reference": tables.reference(data, tests),
        "runs": tables.run_health(data, tests, engines),
        "accuracy": accuracy,
        "real": {"given": real_given},
    }


def evidence_context(data: ReportData, params: Mapping[str, Any] | ReportParams) -> dict[str, Any]:
    """The context of the evidence's sections 2-5 and the appendices (evidence.html.j2), which no weight
    reaches: the engines in the study's order (params ``engines``, the figures' order), not the
    ranking's, and beside the figures the per-metric scores of ``data.weighted``, which the workflow
    gives as the scores job's table (results/scores/scores.csv: no weight, no total, no rank), so that a
    weight edit leaves the evidence's job and its files as they are. ``params``:
    :class:`simpick.report.params.EvidenceParams` (rule report_evidence's), or the report's, of which the
    evidence reads the same fields (a report job rendering the evidence itself: :func:`report_params`)."""
    from simpick.report import provenance, real
    from simpick.report.calibration import calibration_section
    from simpick.report.draw import colors as draw_colors
    from simpick.report.sweep import sweep_section
    from simpick.report.validation import validation_section

    p = report_params(params)
    engines = tables.engine_order(data, list(p.engines))
    colors = draw_colors(p.engines, engines)
    tests = tables.test_order(data, p.config)
    classes = real.class_order(data, p.real_data)
    accuracy = real.accuracy(data, p.statistics, engines, classes, [test_label(t, m) for t, m in tests])
    paths_uri = (
        figures.data_uri(data.figures["paths"])
        if "paths" in data.figures and data.endpoints is not None and len(data.endpoints)
        else None
    )
    rtf_rows = []
    if data.rtf is not None:
        for r in data.rtf.to_dict("records"):
            e = r["engine"]
            r["score"] = data.weighted.loc[e, "real_time_factor"] if e in data.weighted.index else None
            rtf_rows.append(r)
        rtf_rows.sort(key=lambda r: engines.index(r["engine"]) if r["engine"] in engines else len(engines))
    return {
        "title": p.title or DEFAULT_TITLE,
        "robot": _robot(p.config),
        "engines": engines,
        "colors": colors,
        "runs": tables.runs(data, tests, engines),
        "rtf_rows": rtf_rows,
        "rtf_given": data.rtf is not None,
        "rtf_excluded": sorted(
            {t for r in rtf_rows for t in str(r.get("excluded") or "").split(";") if t.strip() and t != "nan"}
        ),
        "rtf_tests": sorted(
            {t for r in rtf_rows for t in str(r.get("tests") or "").split(";") if t.strip() and t != "nan"}
        ),
        "cpu": tables.cpu(data, engines),
        "imu": tables.imu(data, engines, tests),
        "accuracy": accuracy,
        "real": real.real_section(data, p, engines, colors, classes, accuracy),
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
        "per_test": tables.per_test(data, engines, tests),
        "traces_given": data.endpoints is not None,
        "stats_given": data.trace_stats is not None,
        "paths_uri": paths_uri,
        "published": tables.published(data),
        "worked": tables.worked(data),
        "validation": validation_section(
            data.validation, engines, data.figures.get("validation_gain"), data.validation_gains
        ),
        "qualitative": tables.qualitative(data, engines),
        "versions": provenance.package_versions(),
        "machine": provenance.machine(),
        "config_text": _config_text(p.config),
        "sources": data.sources,
    }


def _cpu_robots(data: ReportData) -> str:
    """The answer's CPU column's heading: the robots of the average and intense scenarios as measured
    (the CPU-load records' own counts, so a config with another count is labelled by it)."""
    counts = {
        scenario: sorted({(r.get(scenario) or {}).get("robots") for r in data.cpu or []} - {None})
        for scenario in ("average", "intense")
    }
    if not counts["average"] or not counts["intense"]:
        return "average / intense"
    return " / ".join("-".join(str(n) for n in counts[s]) for s in ("average", "intense")) + " robots"
