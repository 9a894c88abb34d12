"""The decision tree of Farley, Wang & Marshall (2022, Figure 9), built from simpick's own tables.

The paper closes with a tree of questions ("do you need ROS?", ...) whose leaves are simulators,
drawn from the authors' experience. Here every answer rests on a fact a rule wrote or a sourced
record: the qualitative facts (resources/engines/qualitative.yaml, each with its source), the
analytic mechanics checks (the verdict's gate, results/verdict/mechanics.csv, or without real data
results/validation/summary.csv), the real-data verdict (results/verdict/outcomes.csv: best,
equivalent to the best, worse, undetermined), the lab's real-time factor
(results/metrics/lab/rtf.csv) and the CPU load (results/cpu/<engine>.json).

The questions are requirements, asked in a fixed order (licence, ROS, closeness to the real robot
on the verdict's metrics, mechanics, speed, CPU): each answer keeps the engines that meet it. A
question is asked at a node only where some answer would change the engines left there, so
another robot, other data or another set of engines gives another tree; a leaf is the engines
that every answer on its path kept (none, one, or a group no remaining question separates).

The weights do not change the tree: they only order the engines within a leaf (the paper's
weighted total, :func:`leaf_order`), which the report and the figure do from
results/scores/weighted.csv, and the interactive page again in the browser. So a weight edit
does not rerun this job.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from simpick.errors import InputError
from simpick.score.equivalence import pooled
from simpick.score.mechanics import failures

SCHEMA = "simpick.tree/1"

# what a verdict outcome means for "as close to the real robot as the best engine"
CLOSE_OUTCOMES = ("best", "equivalent")

ROS_TEXT = {
    "out_of_the_box": "ROS 2 out of the box",
    "official_plugin": "an official ROS 2 plugin, built by hand",
    "none": "no ROS interface of its own",
}


@dataclass(frozen=True)
class Fact:
    """One engine's answer to one question: the value the answers test, what a reader sees, and
    where it comes from (a results file and row, or the record's source)."""

    value: Any
    text: str
    source: str


@dataclass(frozen=True)
class Option:
    label: str
    keeps: tuple[str, ...]
    short: str = ""  # the label as the printed figure's edges show it (the label itself if empty)


@dataclass(eq=False)
class Question:
    """A requirement. ``options(candidates)`` gives the answers and the engines each keeps, from
    the most demanding answer to "no need"."""

    key: str
    text: str
    rests_on: str
    facts: dict[str, Fact]
    options: Callable[[Sequence[str]], list[Option]] = field(repr=False)


def _binary(key: str, text: str, rests_on: str, facts: dict[str, Fact], yes: str = "Yes", no: str = "No") -> Question:
    def options(candidates: Sequence[str]) -> list[Option]:
        return [
            Option(yes, tuple(e for e in candidates if facts[e].value is True), "Yes"),
            Option(no, tuple(candidates), "No"),
        ]

    return Question(key, text, rests_on, facts, options)


def _read_yaml(path: str) -> dict:
    import yaml

    try:
        data = yaml.safe_load(Path(path).read_text())
    except (OSError, yaml.YAMLError) as exc:
        raise InputError(path, f"cannot read it: {exc}") from None
    if not isinstance(data, dict):
        raise InputError(path, "expected a mapping of engine -> facts")
    return data


def _read_csv(path: str, columns: Sequence[str], what: str):
    import pandas as pd

    try:
        frame = pd.read_csv(path)
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise InputError(path, f"cannot read {what}: {exc}") from None
    missing = [c for c in columns if c not in frame.columns]
    if missing:
        raise InputError(
            path,
            f"{what} lacks the column(s) {', '.join(missing)}",
            "rerun the rule that writes it (snakemake --forcerun) with this simpick",
        )
    return frame


# --------------------------------------------------------------------------
# The questions, each from one table
# --------------------------------------------------------------------------


def qualitative_questions(facts: Mapping[str, Mapping], engines: Sequence[str], path: str) -> list[Question]:
    """Free to use, open source, ROS: the sourced facts of qualitative.yaml."""
    for engine in engines:
        record = facts.get(engine)
        if not isinstance(record, Mapping):
            raise InputError(path, f"no facts for engine {engine!r}", "add a record for it")
        for key in ("free", "open_source", "ros"):
            if key not in record:
                raise InputError(f"{path}: {engine}.{key}", "missing", "add the fact and its source")
        if record["ros"] not in ROS_TEXT:
            raise InputError(f"{path}: {engine}.ros", f"{record['ros']!r} is not one of {sorted(ROS_TEXT)}")

    def fact(engine: str, key: str, value: Any, text: str) -> Fact:
        sources = facts[engine].get("sources") or {}
        notes = facts[engine].get("notes") or {}
        note = f" ({notes[key]})" if key in notes else ""
        return Fact(value, text + note, f"{path}: {engine}.{key}; {sources.get(key, 'no source given')}")

    free = {
        e: fact(e, "free", bool(facts[e]["free"]), "free to use" if facts[e]["free"] else "not free") for e in engines
    }
    open_source = {
        e: fact(
            e,
            "open_source",
            bool(facts[e]["open_source"]),
            "open source" if facts[e]["open_source"] else "closed source",
        )
        for e in engines
    }
    ros = {e: fact(e, "ros", facts[e]["ros"], ROS_TEXT[facts[e]["ros"]]) for e in engines}

    def ros_options(candidates: Sequence[str]) -> list[Option]:
        return [
            Option(
                "Yes, out of the box",
                tuple(e for e in candidates if ros[e].value == "out_of_the_box"),
                "out of the box",
            ),
            Option(
                "Yes; an official plugin built by hand will do",
                tuple(e for e in candidates if ros[e].value in ("out_of_the_box", "official_plugin")),
                "a plugin will do",
            ),
            Option("No", tuple(candidates), "No"),
        ]

    return [
        _binary("free", "Must it be free to use?", path, free),
        _binary("open_source", "Must it be open source?", path, open_source),
        Question("ros", "Do you need ROS 2?", path, ros, ros_options),
    ]


KIND_TEXT = {
    "yaw_gain": "turning",
    "straight": "driving straight",
    "slide": "sliding to rest",
    "incline": "slopes",
    "rest": "standing at rest",
    "invariance": "left/right and heading invariance",
    "rest_pose": "resting level on its suspension",
    "articulation": "the suspension's articulation over blocks",
}


def mechanics_question(summary_path: str, engines: Sequence[str]) -> Question:
    """Must it pass the analytic mechanics cases (results/validation/summary.csv)? An engine passes
    when it fails none of its cases; a skipped case (not applicable) is no failure."""
    summary = _read_csv(summary_path, ("engine", "case", "kind", "passed", "status"), "the validation summary")
    summary = summary[summary.engine.isin(engines)]
    failed = failures(summary)
    kinds = [k for k in dict.fromkeys(summary.kind) if isinstance(k, str)]
    facts = {}
    for engine in engines:
        rows = summary[(summary.engine == engine) & (summary.status != "skipped")]
        cases = rows.case.nunique()
        if not cases:
            facts[engine] = Fact(False, "not checked against mechanics", summary_path)
            continue
        bad = failed.get(engine, [])
        if not bad:
            facts[engine] = Fact(True, f"passes all {cases} analytic cases", f"{summary_path}: {engine}")
            continue
        by_kind: dict[str, int] = {}
        for case in bad:
            kind = rows[rows.case == case].kind.iloc[0]
            by_kind[kind] = by_kind.get(kind, 0) + 1
        named = ", ".join(f"{KIND_TEXT.get(k, k)} ({n})" for k, n in by_kind.items())
        facts[engine] = Fact(
            False,
            f"fails {len(bad)} of {cases} analytic cases: {named}",
            f"{summary_path}: {engine} ({', '.join(bad)})",
        )
    checked = ", ".join(KIND_TEXT.get(k, k) for k in kinds)
    return _binary("mechanics", "Must it follow analytic mechanics?", f"{summary_path} (cases: {checked})", facts)


def verdict_mechanics_question(mechanics_path: str, engines: Sequence[str], cases: str) -> Question:
    """The mechanics question from the verdict's gate (results/verdict/mechanics.csv: one row per
    engine, ``mechanics`` pass or fail and the note the answer table shows), so the tree and the
    report's first table say the same; ``cases`` names what the validation checks."""
    frame = _read_csv(mechanics_path, ("engine", "mechanics", "mechanics_note"), "the verdict's mechanics gate")
    frame = frame.set_index("engine")
    facts = {}
    for engine in engines:
        if engine not in frame.index:
            facts[engine] = Fact(False, "not checked against mechanics", mechanics_path)
            continue
        row = frame.loc[engine]
        facts[engine] = Fact(str(row.mechanics) == "pass", str(row.mechanics_note), f"{mechanics_path}: {engine}")
    return _binary("mechanics", "Must it follow analytic mechanics?", f"{mechanics_path} ({cases})", facts)


def _fmt(x: float, digits: int = 3) -> str:
    return "nan" if x is None or not math.isfinite(float(x)) else f"{float(x):.{digits}g}"


def closeness_question(outcomes_path: str, engines: Sequence[str]) -> Question | None:
    """Must it be as close to the real robot as the best engine (results/verdict/outcomes.csv)? On
    a metric, an engine is close when it is the verdict's best or equivalent to it and passes the
    mechanics the metric depends on (the verdict vouches for no other). The answers: close on every
    metric, close on one named metric (each that some engine is close on), or no need; answers
    that keep the same engines lead to the same place. None where no engine is close on any."""
    columns = (
        "metric",
        "label",
        "unit",
        "engine",
        "n_runs",
        "mean",
        "best",
        "outcome",
        "diff_to_best",
        "diff_low",
        "diff_high",
        "margin",
        "runs_needed",
        "recommendable",
    )
    outcomes = _read_csv(outcomes_path, columns, "the verdict's outcomes")
    outcomes = pooled(outcomes)  # the DRIVE comparison's: its rows over every terrain
    close: dict[str, dict[str, bool]] = {e: {} for e in engines}
    texts: dict[str, list[str]] = {e: [] for e in engines}
    labels: dict[str, str] = {}
    for metric, rows in outcomes.groupby("metric", sort=False):
        rows = rows.set_index("engine")
        label, unit = str(rows.label.iloc[0]), rows.unit.iloc[0]
        unit = "" if not isinstance(unit, str) or not unit or unit == "1" else f" {unit}"
        verdicts = {}
        for engine in engines:
            if engine not in rows.index:
                verdicts[engine] = (False, f"{label}: not in the verdict")
                continue
            r = rows.loc[engine]
            recommendable = str(r.recommendable).strip().lower() in ("true", "1")
            outcome = str(r.outcome)
            text = f"{label} {_fmt(r['mean'])}{unit}: {outcome}"
            if outcome in ("equivalent", "worse", "undetermined"):
                text += (
                    f" (difference to the best, {r.best}: {_fmt(r.diff_to_best, 2)} "
                    f"[{_fmt(r.diff_low, 2)}, {_fmt(r.diff_high, 2)}], margin {_fmt(r.margin, 2)})"
                )
            if outcome == "undetermined" and not (isinstance(r.runs_needed, float) and math.isnan(r.runs_needed)):
                text += f", about {_fmt(r.runs_needed)} runs would decide"
            if not recommendable:
                text += ", fails the mechanics this metric depends on"
            verdicts[engine] = (outcome in CLOSE_OUTCOMES and recommendable, f"{text}, {int(r.n_runs)} runs")
        for engine, (_, text) in verdicts.items():
            texts[engine].append(text)
        if any(is_close for is_close, _ in verdicts.values()):  # a metric nobody is close on is no answer
            labels[metric] = label
            for engine, (is_close, _) in verdicts.items():
                close[engine][metric] = is_close
    if not labels:
        return None
    facts = {
        e: Fact(
            {m: close[e][m] for m in labels},
            "; ".join(texts[e]),
            f"{outcomes_path}: {', '.join(outcomes.metric.unique())} {e}",
        )
        for e in engines
    }

    def options(candidates: Sequence[str]) -> list[Option]:
        out = []
        if len(labels) > 1:
            out.append(
                Option(
                    "Yes, on every measure",
                    tuple(e for e in candidates if all(facts[e].value.values())),
                    "on every measure",
                )
            )
        for metric, label in labels.items():
            out.append(
                Option(
                    f"Yes, on its {label.lower()}",
                    tuple(e for e in candidates if facts[e].value[metric]),
                    label.lower(),
                )
            )
        return [*out, Option("No", tuple(candidates), "No")]

    return Question(
        "closeness", "Must it be as close to the real robot as the best engine?", outcomes_path, facts, options
    )


# Real-time factors measured on a shared machine scatter by tens of percent between runs; two
# engines closer than this ratio are one speed class to a user choosing by speed.
SPEED_CLASS_RATIO = 1.5
# at most this many speed classes at a node: the few answers a reader can take in at once
SPEED_CLASSES = 3


def _round_down(x: float, above: float) -> float:
    """A round threshold in (above, x]: the largest 1, 2 or 5 x 10^k that is, else x to two
    significant figures."""
    k = math.floor(math.log10(x))
    for step in (5, 2, 1):
        for scale in (10.0**k, 10.0 ** (k - 1)):
            if above < step * scale <= x:
                return step * scale
    scale = 10.0 ** (k - 1)
    return math.floor(x / scale + 1e-9) * scale


def speed_question(rtf_path: str, engines: Sequence[str]) -> Question:
    """The real-time factor needed on one core (results/metrics/lab/rtf.csv: simulated over wall
    time over the lab tests, one robot, one process). The answers at a node split its candidates
    into speed classes at the largest gaps between their factors (at least SPEED_CLASS_RATIO),
    with a round threshold in each gap; an engine without a measured factor meets none."""
    frame = _read_csv(rtf_path, ("engine", "real_time_factor"), "the real-time factors").set_index("engine")
    facts = {}
    for engine in engines:
        value = float(frame.real_time_factor.get(engine, math.nan))
        measured = math.isfinite(value)
        text = f"real-time factor {_fmt(value)} on one core" if measured else "real-time factor not measured"
        facts[engine] = Fact(value if math.isfinite(value) and value > 0 else None, text, f"{rtf_path}: {engine}")

    def options(candidates: Sequence[str]) -> list[Option]:
        measured = sorted({facts[e].value for e in candidates if facts[e].value is not None}, reverse=True)
        gaps = sorted(
            (
                (measured[i] / measured[i + 1], i)
                for i in range(len(measured) - 1)
                if measured[i] / measured[i + 1] >= SPEED_CLASS_RATIO
            ),
            reverse=True,
        )[: SPEED_CLASSES - 1]
        thresholds = [_round_down(measured[i], measured[i + 1]) for _, i in gaps]
        if measured and measured[0] >= 1.0 > measured[-1]:
            thresholds.append(1.0)  # keeping pace with the clock (hardware in the loop, ROS time) is a need of its own
        thresholds = sorted(set(thresholds), reverse=True)
        if measured and any(facts[e].value is None for e in candidates):
            thresholds.append(_round_down(measured[-1], 0.0))  # measured at all: those without a factor go
        out = []
        for threshold in thresholds:
            keeps = tuple(e for e in candidates if facts[e].value is not None and facts[e].value >= threshold)
            if out and out[-1].keeps == keeps:  # the same engines: the lower threshold, the one more needs meet
                out.pop()
            if threshold == 1.0:
                out.append(Option("At least real time", keeps, "\u2265 real time"))
            else:
                out.append(Option(f"At least {threshold:g} x real time", keeps, f"\u2265 {threshold:g}\u00d7"))
        return [*out, Option("No need", tuple(candidates), "no need")]

    return Question("real_time_factor", "Which real-time factor do you need on one core?", rtf_path, facts, options)


def cpu_question(cpu_paths: Sequence[str], engines: Sequence[str]) -> Question | None:
    """Must it run the intense test's robots at once in real time on one core: CPU load (CPU time
    spent stepping over simulated time, % of one core; results/cpu/<engine>.json) at most 100 %?
    A measurement that failed its health check counts as not measured."""
    records = {}
    for path in cpu_paths:
        try:
            record = json.loads(Path(path).read_text())
            records[record["engine"]] = (path, record)
        except (OSError, json.JSONDecodeError, KeyError, TypeError) as exc:
            raise InputError(path, f"cannot read the CPU load record: {exc}") from None
    robots = sorted({r["intense"]["robots"] for _, r in records.values() if r.get("intense")})
    if not robots:
        return None
    facts = {}
    for engine in engines:
        path, record = records.get(engine, ("results/cpu", {}))
        intense = record.get("intense") or {}
        load = intense.get("load_percent")
        healthy = (record.get("health") or {}).get("status", "ok") == "ok"
        if load is None or not healthy:
            facts[engine] = Fact(False, "CPU load not measured (or its run failed the health check)", path)
            continue
        n = intense.get("robots")
        facts[engine] = Fact(
            load <= 100.0, f"{n} robots at once: {_fmt(load)} % of one core", f"{path}: intense.load_percent"
        )
    n = robots[-1]
    return _binary("cpu", f"Must it run {n} robots at once in real time on one core?", ", ".join(cpu_paths), facts)


# --------------------------------------------------------------------------
# The tree
# --------------------------------------------------------------------------


def build_tree(questions: Sequence[Question], engines: Sequence[str]) -> dict:
    """The tree as a JSON-ready dict: ``nodes`` (id -> a question node or a leaf), ``root``,
    ``questions`` (every question with each engine's fact), ``not_asked`` (the questions no
    answer would change at the root, and why)."""
    engines = tuple(engines)
    asked, not_asked = [], []
    for q in questions:
        options = q.options(engines)
        if not any(o.keeps for o in options[:-1]):  # the last answer is always "no need"
            not_asked.append({"key": q.key, "question": q.text, "why": "no engine meets it"})
        elif all(o.keeps == engines for o in options):
            not_asked.append({"key": q.key, "question": q.text, "why": "every engine meets it"})
        else:
            asked.append(q)

    nodes: dict[str, dict] = {}

    def node(candidates: tuple[str, ...], remaining: list[Question], path: list[dict]) -> str:
        nid = f"n{len(nodes)}"
        nodes[nid] = {}
        for i, q in enumerate(remaining):
            options = q.options(candidates)
            if any(o.keeps != candidates for o in options):
                children: dict[tuple[str, ...], str] = {}
                answers = []
                for o in options:
                    if o.keeps not in children:
                        step = {"question": q.key, "answer": o.label}
                        children[o.keeps] = node(o.keeps, remaining[i + 1 :], [*path, step])
                    dropped = [e for e in candidates if e not in o.keeps]
                    answers.append(
                        {
                            "label": o.label,
                            "short": o.short or o.label,
                            "next": children[o.keeps],
                            "keeps": list(o.keeps),
                            "drops": [{"engine": e, "why": q.facts[e].text} for e in dropped],
                        }
                    )
                nodes[nid] = {
                    "id": nid,
                    "kind": "question",
                    "question": q.key,
                    "text": q.text,
                    "candidates": list(candidates),
                    "answers": answers,
                }
                return nid
        nodes[nid] = {"id": nid, "kind": "leaf", "engines": list(candidates), "path": path}
        return nid

    root = node(engines, asked, [])
    return {
        "schema": SCHEMA,
        "engines": list(engines),
        "root": root,
        "nodes": nodes,
        "questions": [
            {
                "key": q.key,
                "text": q.text,
                "rests_on": q.rests_on,
                "asked": any(q is a for a in asked),
                "facts": {
                    e: {"value": q.facts[e].value, "text": q.facts[e].text, "source": q.facts[e].source}
                    for e in engines
                },
            }
            for q in questions
        ],
        "not_asked": not_asked,
    }


def study_questions(engines: Sequence[str], inputs: Mapping[str, Any]) -> list[Question]:
    """Every question from the study's tables, in the order they are asked. ``inputs``:
    ``qualitative``, ``validation`` (summary.csv), ``rtf``, ``cpu`` (a list of JSON files) and,
    where the study has real data, the verdict's ``outcomes`` and ``mechanics``."""
    questions = qualitative_questions(_read_yaml(inputs["qualitative"]), engines, inputs["qualitative"])
    # closeness before mechanics: its "yes" keeps only engines that pass the mechanics its metric
    # depends on, so the mechanics question is left to the branches where it still says something
    closeness = closeness_question(inputs["outcomes"], engines) if inputs.get("outcomes") else None
    if closeness is not None:
        questions.append(closeness)
    mechanics = mechanics_question(inputs["validation"], engines)
    if inputs.get("mechanics"):  # the verdict's gate, where the study has one: the words of the answer table
        mechanics = verdict_mechanics_question(inputs["mechanics"], engines, mechanics.rests_on)
    questions.append(mechanics)
    questions.append(speed_question(inputs["rtf"], engines))
    cpu = cpu_question(list(inputs.get("cpu") or []), engines)
    if cpu is not None:
        questions.append(cpu)
    return questions


def decision_tree_job(engines: Sequence[str], inputs: Mapping[str, Any], output: str) -> None:
    """Rule decision_tree: results/verdict/tree.json from the study's tables."""
    tree = build_tree(study_questions(engines, inputs), engines)
    tree["inputs"] = {k: (list(v) if isinstance(v, (list, tuple)) else v) for k, v in inputs.items()}
    Path(output).parent.mkdir(parents=True, exist_ok=True)
    Path(output).write_text(json.dumps(tree, indent=1, allow_nan=False) + "\n")


# --------------------------------------------------------------------------
# What the weights change: the order within a leaf
# --------------------------------------------------------------------------


def leaf_order(engines: Sequence[str], totals: Mapping[str, float]) -> list[str]:
    """A leaf's engines by weighted total, highest first (ties keep the tree's order); the first is
    the pick. An engine without a total comes last."""
    order = {e: i for i, e in enumerate(engines)}

    def key(engine: str) -> tuple:
        total = totals.get(engine)
        missing = total is None or not math.isfinite(float(total))
        return (missing, 0.0 if missing else -float(total), order[engine])

    return sorted(engines, key=key)


def read_tree(path: str) -> dict:
    try:
        tree = json.loads(Path(path).read_text())
    except (OSError, json.JSONDecodeError) as exc:
        raise InputError(path, f"cannot read the decision tree: {exc}", "rerun rule decision_tree") from None
    if tree.get("schema") != SCHEMA:
        raise InputError(
            f"{path}: schema",
            f"expected {SCHEMA!r}, got {tree.get('schema')!r}",
            "rerun rule decision_tree with this simpick",
        )
    return tree


def walk(tree: dict, answers: Mapping[str, str]) -> dict:
    """The node the answers (question key -> answer label) lead to from the root: a leaf, or the
    first question they leave unanswered."""
    node = tree["nodes"][tree["root"]]
    while node["kind"] == "question" and node["question"] in answers:
        label = answers[node["question"]]
        chosen = [a for a in node["answers"] if a["label"] == label]
        if not chosen:
            known = [a["label"] for a in node["answers"]]
            raise KeyError(f"{node['question']}: no answer {label!r} (answers: {known})")
        node = tree["nodes"][chosen[0]["next"]]
    return node
