"""The benchmark across robots: each engine's (and simulator profile's) outcomes on every robot side by
side, where the robots agree, where they differ and by how much, and a pooled outcome only where one
is honest.

It reads what each robot's study publishes, nothing of its internals: the answer
(``results/verdict/answer.csv``: per engine and real-data metric the outcome against the best engine,
the difference to the best with its interval and the practical margin; simpick.score.answer) and the
simulators' table (``results/simulators/table.csv``: per simulator profile its outcomes and errors;
simpick.score.simulators).

Outcomes fall in three classes: *as good as the best* (``best``, ``equivalent``: within the margin),
*worse*, and *open* (``undetermined``, ``too few runs``: the robot's data do not decide). ``not
measurable`` (the robot's logs cannot measure the metric) and a subject missing from a robot's study
leave that robot out of the comparison of that metric.

Pooling (:data:`POOLING_METHOD`): an intersection-union rule on the robots' own outcomes, never an
average of their errors. A pooled outcome is stated only where every robot of the benchmark measured
the metric and all of them give the same class; a mixed, open or missing outcome is said as the reason
there is none.
"""

from __future__ import annotations

import math

import pandas as pd

from simpick.errors import InputError
from simpick.score.verdict import METRICS

GOOD = ("best", "equivalent")
WORSE = ("worse",)
OPEN = ("undetermined", "too few runs")
UNMEASURED = ("not measurable", "not run", "")
SIMULATOR_METRICS = {"gain_error": "gain", "heading_error": "heading", "speed_error": "speed"}

POOLING_METHOD = (
    "intersection-union over the robots: a pooled outcome is stated only where every robot of the benchmark "
    "measured the metric and each robot's own test gives the same class (as good as the best on every robot, or "
    "worse on every robot); each robot's test holds at its study's level, so their conjunction does too. The "
    "errors are not averaged across robots: the robots' real data differ in kind, in their unit of pairing "
    "and in their margins, and a mean over them would weigh each robot by the size of its data set."
)

SIDE_COLUMNS = [
    "kind",
    "subject",
    "simulator",
    "variant",
    "engine",
    "metric",
    "robot",
    "outcome",
    "diff",
    "diff_low",
    "diff_high",
    "margin",
    "error",
    "error_low",
    "error_high",
    "mechanics",
]
AGREEMENT_COLUMNS = [
    "kind",
    "subject",
    "metric",
    "robots",
    "outcomes",
    "agreement",
    "gap",
    "pooled",
    "pooled_reason",
    "statement",
]
ANSWER_NEEDS = ("engine", "mechanics", *[f"{m}_{k}" for m in METRICS for k in ("outcome", "diff", "low", "high")])
SIMULATOR_NEEDS = ("simulator", "variant", "model", "engine", "mechanics", "gain_outcome", "heading_outcome")


def klass(outcome) -> str:
    """``good``, ``worse``, ``open`` or ``unmeasured`` for an outcome as the studies write it."""
    text = "" if outcome is None or (isinstance(outcome, float) and math.isnan(outcome)) else str(outcome).strip()
    if text in GOOD:
        return "good"
    if text in WORSE:
        return "worse"
    if text in OPEN:
        return "open"
    if text in UNMEASURED:
        return "unmeasured"
    raise ValueError(f"unknown outcome {text!r}: expected one of {GOOD + WORSE + OPEN + UNMEASURED[:2]}")


def _need(frame: pd.DataFrame, columns, where: str) -> None:
    missing = [c for c in columns if c not in frame.columns]
    if missing:
        raise InputError(where, f"lacks the column(s) {missing}", "rerun that robot's study (rule answer / simulators)")


def _num(value) -> float:
    try:
        out = float(value)
    except (TypeError, ValueError):
        return float("nan")
    return out


def side_by_side(
    answers: dict[str, pd.DataFrame],
    simulators: dict[str, pd.DataFrame] | None = None,
    where: dict[str, str] | None = None,
) -> pd.DataFrame:
    """One row per subject x metric x robot (``SIDE_COLUMNS``): the engines of each robot's answer
    (``answers``: robot -> its answer.csv) and the simulator profiles of its simulators' table
    (``simulators``: robot -> its table.csv; the profiles it ran, not those it lists as not run), in the
    robots' order. ``where``: robot -> the file each
    came from, for the error a table without the expected columns raises."""
    where = where or {}
    rows = []
    for robot, answer in answers.items():
        _need(answer, ANSWER_NEEDS, where.get(robot, f"{robot}: answer.csv"))
        for r in answer.to_dict("records"):
            for metric in METRICS:
                rows.append(
                    {
                        "kind": "engine",
                        "subject": str(r["engine"]),
                        "simulator": "",
                        "variant": "",
                        "engine": str(r["engine"]),
                        "metric": metric,
                        "robot": robot,
                        "outcome": str(r.get(f"{metric}_outcome") or "not measurable"),
                        "diff": _num(r.get(f"{metric}_diff")),
                        "diff_low": _num(r.get(f"{metric}_low")),
                        "diff_high": _num(r.get(f"{metric}_high")),
                        "margin": _num(r.get(f"{metric}_margin")),
                        "error": float("nan"),
                        "error_low": float("nan"),
                        "error_high": float("nan"),
                        "mechanics": str(r.get("mechanics", "")),
                    }
                )
    for robot, table in (simulators or {}).items():
        if table is None or table.empty:
            continue
        _need(table, SIMULATOR_NEEDS, where.get(f"{robot}:simulators", f"{robot}: simulators/table.csv"))
        for r in table.to_dict("records"):
            if str(r.get("status", "run")).startswith("not run"):  # listed by the catalog, not run in this study
                continue
            for metric, short in SIMULATOR_METRICS.items():
                outcome = r.get(f"{short}_outcome")
                outcome = "not measurable" if outcome is None or str(outcome) in ("", "nan") else str(outcome)
                gain = metric == "gain_error"
                rows.append(
                    {
                        "kind": "simulator",
                        "subject": f"{r['simulator']} ({r['variant']})",
                        "simulator": str(r["simulator"]),
                        "variant": str(r["variant"]),
                        "engine": str(r["engine"]),
                        "metric": metric,
                        "robot": robot,
                        "outcome": outcome,
                        "diff": _num(r.get("gain_diff_to_best")) if gain else float("nan"),
                        "diff_low": float("nan"),
                        "diff_high": float("nan"),
                        "margin": float("nan"),
                        "error": _num(r.get(metric)),
                        "error_low": _num(r.get("gain_error_low")) if gain else float("nan"),
                        "error_high": _num(r.get("gain_error_high")) if gain else float("nan"),
                        "mechanics": str(r.get("mechanics", "")),
                    }
                )
    return pd.DataFrame(rows, columns=SIDE_COLUMNS)


def _fmt(x: float) -> str:
    return "–" if not math.isfinite(x) else f"{x:.3g}"


def describe(row: dict) -> str:
    """One robot's outcome in words: the outcome, the difference to the best with its interval and the
    margin where the robot's answer gives them, else the error where the simulators' table does."""
    text = row["outcome"]
    reference = row["diff"] == 0 and not math.isfinite(row["diff_low"])  # the lowest mean, with too few runs
    if math.isfinite(row["diff"]) and row["outcome"] != "best" and not reference:
        text += f", {_fmt(row['diff'])}"
        if math.isfinite(row["diff_low"]) and math.isfinite(row["diff_high"]):
            text += f" [{_fmt(row['diff_low'])}, {_fmt(row['diff_high'])}]"
        text += " above the best"
        if math.isfinite(row["margin"]):
            text += f" (margin {_fmt(row['margin'])})"
    elif math.isfinite(row["error"]):
        text += f", error {_fmt(row['error'])}"
        if math.isfinite(row["error_low"]) and math.isfinite(row["error_high"]):
            text += f" [{_fmt(row['error_low'])}, {_fmt(row['error_high'])}]"
    return text


def agreement(side: pd.DataFrame, robots: list[str], labels: dict[str, str] | None = None, min_robots: int = 2):
    """One row per subject x metric (``AGREEMENT_COLUMNS``) over ``robots`` (every robot of the
    benchmark, in order; ``labels`` their names on the page):

    - ``agreement``: ``agree`` (every robot that measured it gives the same class), ``differ`` (as good
      as the best on one robot, worse on another), ``open`` (a robot's data do not decide and the others
      do not disagree), ``one robot`` / ``not measured`` (fewer than two robots measured it);
    - ``gap``: the largest minus the smallest difference to the best over the robots that give one, in
      the metric's unit (how far apart the robots put it);
    - ``pooled``: the class every robot gives, where all ``robots`` (at least ``min_robots``) measured it
      and agree (:data:`POOLING_METHOD`), else empty with ``pooled_reason``.
    """
    labels = labels or {}
    name = lambda r: labels.get(r, r)  # noqa: E731
    if len(robots) < 1:
        raise ValueError("agreement needs at least one robot")
    rows = []
    for (kind, subject, metric), group in side.groupby(["kind", "subject", "metric"], sort=False):
        by_robot = {r["robot"]: r for r in group.to_dict("records")}
        classes = {r: klass(by_robot[r]["outcome"]) if r in by_robot else "unmeasured" for r in robots}
        measured = [r for r in robots if classes[r] != "unmeasured"]
        decided = {classes[r] for r in measured if classes[r] != "open"}
        if not measured:
            verdict = "not measured"
        elif len(measured) == 1:
            verdict = "one robot"
        elif decided == {"good", "worse"}:
            verdict = "differ"
        elif any(classes[r] == "open" for r in measured):
            verdict = "open"
        else:
            verdict = "agree"
        diffs = [by_robot[r]["diff"] for r in measured if math.isfinite(by_robot[r]["diff"])]
        gap = max(diffs) - min(diffs) if len(diffs) >= 2 else float("nan")
        missing = [r for r in robots if classes[r] == "unmeasured"]
        open_ = [r for r in robots if classes[r] == "open"]
        pooled, reason = "", ""
        if len(robots) < min_robots:
            reason = f"the benchmark has {len(robots)} robot(s); pooling needs {min_robots}"
        elif missing:
            reason = "not measured on " + ", ".join(
                f"{name(r)} ({by_robot[r]['outcome']})" if r in by_robot else f"{name(r)} (not in its study)"
                for r in missing
            )
        elif verdict == "differ":
            reason = "the robots disagree"
        elif open_:
            reason = "undetermined on " + ", ".join(name(r) for r in open_)
        else:
            pooled = (
                "best on every robot"
                if all(by_robot[r]["outcome"] == "best" for r in robots)
                else ("as good as the best on every robot" if decided == {"good"} else "worse on every robot")
            )
        outcomes = "; ".join(f"{name(r)}: {describe(by_robot[r])}" for r in robots if r in by_robot)
        rows.append(
            {
                "kind": kind,
                "subject": subject,
                "metric": metric,
                "robots": len(measured),
                "outcomes": outcomes,
                "agreement": verdict,
                "gap": gap,
                "pooled": pooled,
                "pooled_reason": reason,
                "statement": _statement(verdict, subject, metric, robots, by_robot, classes, gap, name),
            }
        )
    return pd.DataFrame(rows, columns=AGREEMENT_COLUMNS)


def _statement(verdict, subject, metric, robots, by_robot, classes, gap, name) -> str:
    label = metric.replace("_", " ")
    if verdict == "not measured":
        return f"{subject}: {label} measured on no robot."
    if verdict == "one robot":
        only = next(r for r in robots if classes[r] != "unmeasured")
        return f"{subject}: {label} measured on {name(only)} only ({by_robot[only]['outcome']})."
    by = "" if not math.isfinite(gap) else f"; the robots' differences to the best lie {_fmt(gap)} apart"
    if verdict == "agree":
        first = next(r for r in robots if classes[r] != "unmeasured")
        what = "as good as the best" if classes[first] == "good" else "worse"
        return f"{subject}: the robots agree on {label}, {what} on each{by}."
    if verdict == "differ":
        good = [name(r) for r in robots if classes[r] == "good"]
        bad = [name(r) for r in robots if classes[r] == "worse"]
        return (
            f"{subject}: the robots differ on {label}: as good as the best on {', '.join(good)}, "
            f"worse on {', '.join(bad)}{by}."
        )
    open_ = [name(r) for r in robots if classes[r] == "open"]
    if len(open_) == sum(classes[r] != "unmeasured" for r in robots):
        return f"{subject}: {label} undetermined on every robot that measured it ({', '.join(open_)})."
    return f"{subject}: {label} undetermined on {', '.join(open_)}; the other robots do not disagree{by}."


def summary(agree: pd.DataFrame) -> dict:
    """Counts over the engines' and the simulators' rows (``kind`` -> ``agreement`` -> count)."""
    out: dict = {}
    for (kind, verdict), group in agree.groupby(["kind", "agreement"], sort=False):
        out.setdefault(kind, {})[verdict] = int(len(group))
    return out
