"""The page of the benchmark across robots (rule robots, rules/robots.smk): per real-data metric, each
engine's and each simulator profile's outcome on every robot side by side, where the robots agree or
differ and by how much, and a pooled outcome where every robot gives the same one
(simpick.score.robots); each robot's data, its answer and the command that reruns its study alone.

It reads each robot's public outputs only (answer.csv, headline.yaml, simulators/table.csv) and writes
``benchmark.csv`` (the side-by-side rows), ``agreement.csv`` (one row per subject and metric), the HTML
page and its PDF (WeasyPrint, as the study report).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Any

import pandas as pd
import yaml
from pydantic import Field

from simpick.errors import InputError
from simpick.params import JobParams
from simpick.score.robots import POOLING_METHOD, agreement, describe, side_by_side, summary
from simpick.score.verdict import METRICS
from simpick.tables import write_csv

TEMPLATE = "robots.html.j2"
KINDS = {"engine": "Engines", "simulator": "Simulator profiles (as shipped, tuned and calibrated)"}


def _read_csv(path: str, what: str) -> pd.DataFrame:
    if not Path(path).is_file():
        raise InputError(path, f"{what} does not exist", "run that robot's study first (rules/robots.smk does)")
    return pd.read_csv(path)


def _read_headline(path: str) -> dict:
    if not Path(path).is_file():
        raise InputError(path, "the robot's headline does not exist", "run that robot's study first")
    data = yaml.safe_load(Path(path).read_text()) or {}
    if not isinstance(data, dict):
        raise InputError(path, "is not a mapping", "rerun that robot's rule answer")
    return data


def _cells(side: pd.DataFrame, agree: pd.DataFrame, kind: str, metric: str, robots: list[str]) -> list[dict]:
    """The rows of one metric's table: per subject, each robot's cell, the agreement and the pooled outcome."""
    rows = []
    part = agree[(agree.kind == kind) & (agree.metric == metric)]
    mine = side[(side.kind == kind) & (side.metric == metric)]
    for a in part.to_dict("records"):
        cells = []
        for robot in robots:
            found = mine[(mine.subject == a["subject"]) & (mine.robot == robot)]
            if found.empty:
                cells.append({"outcome": "not in its study", "detail": "", "mechanics": ""})
                continue
            r = found.iloc[0].to_dict()
            text = describe(r)
            head, _, rest = text.partition(", ")
            cells.append({"outcome": head, "detail": rest, "mechanics": r["mechanics"]})
        rows.append(
            {
                "subject": a["subject"],
                "cells": cells,
                "agreement": a["agreement"],
                "gap": a["gap"] if isinstance(a["gap"], float) and math.isfinite(a["gap"]) else None,
                "pooled": a["pooled"],
                "reason": a["pooled_reason"],
            }
        )
    return rows


def _findings(agree: pd.DataFrame, kind: str) -> list[str]:
    """The summary's lines for one kind: per metric, the subjects the robots agree on, differ on, and
    the pooled outcomes."""
    lines = []
    for metric in METRICS:
        part = agree[(agree.kind == kind) & (agree.metric == metric)]
        if part.empty:
            continue
        label = metric.replace("_", " ")
        compared = part[part.agreement.isin(["agree", "differ", "open"])]
        if compared.empty:
            only = sorted({r for r in part.statement if " only (" in r})
            robots = sorted({s.split(" measured on ", 1)[1].split(" only (", 1)[0] for s in only})
            lines.append(
                f"{label}: measured on {' and '.join(robots)} only (one robot each): nothing to compare"
                if robots
                else f"{label}: measured on no robot"
            )
            continue
        agree_on = compared[compared.agreement == "agree"].subject.tolist()
        differ_on = compared[compared.agreement == "differ"].subject.tolist()
        open_on = compared[compared.agreement == "open"].subject.tolist()
        parts = []
        if agree_on:
            parts.append(f"the robots agree on {', '.join(agree_on)}")
        if differ_on:
            parts.append(f"they differ on {', '.join(differ_on)}")
        if open_on:
            parts.append(f"undetermined on at least one robot for {', '.join(open_on)}")
        text = f"{label}: " + "; ".join(parts)
        pooled = part[part.pooled != ""]
        if len(pooled):
            groups: dict[str, list[str]] = {}
            for r in pooled.itertuples():
                groups.setdefault(r.pooled, []).append(r.subject)
            text += ". Pooled: " + "; ".join(f"{k}: {', '.join(v)}" for k, v in groups.items())
        else:
            text += ". Nothing pooled"
        lines.append(text + ".")
    return lines


class RobotShown(JobParams):
    """One robot of the benchmark as the page shows it (simpick.config.robots.RobotStudy)."""

    name: str = Field(description="the robot's name in config/robots.yaml (its rules' prefix)")
    label: str = Field("", description="its name on the page ('': the name)")
    command: str = Field(description="the command that runs its study alone")
    settings: dict[str, Any] = Field({}, description="the settings given on top of its files, by dotted key")
    configfiles: list[str] = Field([], description="the config files its study runs with, in order")


class Pooling(JobParams):
    """How the page puts one engine's outcomes on the robots together (config/robots.yaml, pooling)."""

    # strict: a whole number, not True nor "2" (a YAML typo)
    min_robots: Annotated[int, Field(ge=2, strict=True)] = Field(
        2, description="a pooled outcome needs an outcome on at least this many robots, and none undetermined"
    )


class RobotsParams(JobParams):
    """What rule robots' job reads: the robots in order, and the pooling."""

    robots: list[RobotShown]
    pooling: Pooling = Field(Pooling(), description="how outcomes are pooled over the robots")


def simulators_per_robot(
    frames: dict[str, pd.DataFrame],
    labels: dict[str, str],
    units: dict[str, str],
    settings: dict[str, tuple[str, str]] | None = None,
) -> dict[str, Any]:
    """Which simulator reproduces each robot, side by side: per robot its simulators' answer (the closest
    profile, shipped, tuned or calibrated, on its held-out runs, with its settings file:
    simpick.score.profiles.simulator_answer) and its sentence; per simulator a row with each robot's pick.
    ``frames``: robot -> its simulators' table; ``units``: what its real data's units are called; ``settings``:
    robot -> (its settings folder, the link to it from the page)."""
    from simpick.score.profiles import simulator_answer
    from simpick.score.sentences import simulator_sentences

    robots = list(frames)
    answers = {}
    for robot, frame in frames.items():
        folder, link = (settings or {}).get(robot, (None, ""))
        answers[robot] = simulator_answer(frame, folder, link=link)
    leads = []
    for robot in robots:
        said = simulator_sentences(answers[robot], labels[robot], f"real {units.get(robot) or 'runs'}")
        a = answers[robot]
        leads.append(
            {
                "robot": labels[robot],
                "text": said[0]["text"] if said else f"No simulator can be named: {a['why_none']}.",
                "files": said[0]["files"] if said else [],
                "no_calibrated": a.get("no_calibrated", ""),
            }
        )
    names: dict[str, str] = {}
    for a in answers.values():
        for s in a["simulators"]:
            names.setdefault(s["simulator"], s["label"])
    rows = []
    for simulator, label in names.items():
        cells = []
        for robot in robots:
            s = next((s for s in answers[robot]["simulators"] if s["simulator"] == simulator), None)
            if s is None:
                cells.append({"text": "not in its study"})
            elif not s["ran"]:
                cells.append({"text": "not run: " + (s["not_run"][0]["why"] if s["not_run"] else "–")})
            elif s["best"] is None:
                cells.append({"text": "not measured on its real data"})
            else:
                cells.append({"pick": s["best"], "spread": answers[robot]["spread"]})
        rows.append({"simulator": simulator, "label": label, "cells": cells})

    # the simulators by their best pick over the robots that keeps its mechanics, then those whose picks all break
    # them (a pick marked ✗ is never the answer), those measured on no robot last
    def order(row: dict) -> tuple[int, float]:
        picks = [c["pick"] for c in row["cells"] if "pick" in c]
        passing = [p["error"] for p in picks if p["passes"]]
        return (0, min(passing)) if passing else (1, min((p["error"] for p in picks), default=math.inf))

    rows.sort(key=order)
    return {
        "given": any(a["given"] for a in answers.values()),
        "robots": [labels[r] for r in robots],
        "leads": leads,
        "rows": rows,
        "heldout": {labels[r]: answers[r].get("heldout", False) for r in robots},
    }


def build_page(
    robots: list[RobotShown],
    answers: list[str],
    headlines: list[str],
    simulators: list[str],
    min_robots: int = 2,
    settings: list[tuple[str, str]] | None = None,
) -> tuple[pd.DataFrame, pd.DataFrame, dict]:
    """(the side-by-side rows, the agreement rows, the page's context) from each robot's files, in the
    order of ``robots`` (the rule's params); ``settings``: per robot its simulators' settings folder and the
    link to it from the page, where the rule gives them."""
    if not (len(robots) == len(answers) == len(headlines) == len(simulators)):
        raise ValueError("one answer, headline and simulators' table per robot")
    names = [r.name for r in robots]
    labels = {r.name: r.label or r.name for r in robots}
    answer_frames = {n: _read_csv(p, "the robot's answer") for n, p in zip(names, answers, strict=True)}
    simulator_frames = {
        n: _read_csv(p, "the robot's simulators' table") for n, p in zip(names, simulators, strict=True)
    }
    where = {n: p for n, p in zip(names, answers, strict=True)}
    where.update({f"{n}:simulators": p for n, p in zip(names, simulators, strict=True)})
    side = side_by_side(answer_frames, simulator_frames, where=where)
    agree = agreement(side, names, labels, min_robots=min_robots)
    heads = {n: _read_headline(p) for n, p in zip(names, headlines, strict=True)}
    sections = []
    for kind, title in KINDS.items():
        if not (side.kind == kind).any():
            continue
        tables = []
        for metric in METRICS:
            rows = _cells(side, agree, kind, metric, names)
            if any(r["agreement"] != "not measured" for r in rows):  # a metric no robot measured: no table
                tables.append({"metric": metric, "label": METRICS[metric]["label"], "rows": rows})
        sections.append({"kind": kind, "title": title, "tables": tables, "findings": _findings(agree, kind)})
    no_simulators = [labels[n] for n in names if not (side[side.robot == n].kind == "simulator").any()]
    context = {
        # the question first: which simulator, per robot, with which settings file
        "simulator_answers": simulators_per_robot(
            simulator_frames,
            labels,
            {n: str(heads[n].get("units") or "runs") for n in names},
            dict(zip(names, settings, strict=True)) if settings else None,
        ),
        "no_simulators": no_simulators,
        "robots": [
            {
                **r.model_dump(mode="json"),
                "label": labels[r.name],
                "headline": heads[r.name],
            }
            for r in robots
        ],
        "sections": sections,
        "metrics": [{"label": v["label"], "unit": v["unit"] or "no unit", "what": v["what"]} for v in METRICS.values()],
        "method": POOLING_METHOD,
        "min_robots": min_robots,
        "counts": summary(agree),
    }
    return side, agree, context


def render(context: dict) -> str:
    from simpick.report.render import environment

    return environment().get_template(TEMPLATE).render(**context)


def robots_job(inputs: dict, params: dict, outputs: dict) -> None:
    """Rule robots: the tables, the page and its PDF."""
    import os

    from simpick.report.render import write_pdf

    p = RobotsParams.model_validate(params)
    page = Path(outputs["html"]).parent
    settings = [(str(f), os.path.relpath(f, page)) for f in inputs.get("settings") or []] or None
    side, agree, context = build_page(
        list(p.robots),
        list(inputs["answers"]),
        list(inputs["headlines"]),
        list(inputs["simulators"]),
        p.pooling.min_robots,
        settings,
    )
    write_csv(side, outputs["table"])
    write_csv(agree, outputs["agreement"])
    html = render(context)
    Path(outputs["html"]).write_text(html)
    write_pdf(html, outputs["pdf"])
