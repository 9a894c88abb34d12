"""The answer's sentences: one per need a roboticist has (closest, the runs an engine failed, fastest, settings,
avoid; ``answer.yaml``), the report's first paragraph (the headline) and the sentence that names the data the
answer rests on, each with the figures it rests on. An engine that failed runs the others completed is never
named closest without that said in the same sentence. simpick.score.answer builds the table they read and
writes them.
"""

from __future__ import annotations

import re

import numpy as np
import pandas as pd
from pydantic import Field

from simpick.params import JobParams
from simpick.score.equivalence import FAILED_SEPARATOR

RUNS = "real runs"  # what the sentences call the real data's units where the basis names none


PRIMARY = ("gain_error", "heading_error", "speed_error")  # the metric a "closest" sentence rests on first


def _f(x, digits: int = 3) -> str:
    return "–" if x is None or not np.isfinite(float(x)) else f"{float(x):.{digits}g}"


def failed_runs(outcomes: pd.DataFrame, engine: str) -> list[tuple[str, str]]:
    """(run, why) for every real run ``engine`` failed that another engine completed, over the
    metrics (outcomes.csv's ``failed_runs``), each run once."""
    seen: dict[str, str] = {}
    if "failed_runs" not in outcomes:
        return []
    for cell in outcomes.loc[outcomes.engine == engine, "failed_runs"]:
        if not isinstance(cell, str) or not cell:
            continue
        for item in cell.split(FAILED_SEPARATOR):
            run, _, why = item.partition(": ")
            seen.setdefault(run, why)
    return sorted(seen.items())


def _kinds(failures: list[tuple[str, str]]) -> str:
    """The kinds of failure behind ``failures``: each health reason's first clause, once."""
    kinds: list[str] = []
    for _, why in failures:
        for reason in why.split("; "):
            kind = reason.split(":", 1)[0].strip()
            if kind and kind not in kinds:
                kinds.append(kind)
    return "; ".join(kinds)


def _runs(failures: list[tuple[str, str]]) -> str:
    runs = [r for r, _ in failures]
    return runs[0] if len(runs) == 1 else ", ".join(runs[:-1]) + " and " + runs[-1]


def failure_clause(o: pd.Series | dict, failures: list[tuple[str, str]], noun: str = RUNS) -> str:
    """``o``'s engine failed ``failures``, runs another engine completed: how many, which and why."""
    total = int(o["runs_all"]) if "runs_all" in o and np.isfinite(float(o["runs_all"])) else len(failures)
    return f"{o['engine']} failed {len(failures)} of the {total} {noun} ({_runs(failures)}: {_kinds(failures)})"


def _cite(o: pd.Series) -> str:
    """A row of outcomes.csv as the figure a sentence rests on."""
    text = f"outcomes.csv: {o.metric} {o.engine} {o.outcome}, mean {_f(o['mean'])}"
    if not o.is_best and np.isfinite(o.diff_to_best):
        text += (
            f", difference to {o.best} {_f(o.diff_to_best)} [{_f(o.diff_low)}, {_f(o.diff_high)}], margin "
            f"{_f(o.margin)}, p_worse {_f(o.p_worse, 2)}, p_equivalent {_f(o.p_equivalent, 2)}"
        )
    return text


def units(noun: str) -> str:
    """The units without the dataset's name ("DRIVE steps" -> "steps")."""
    return noun.split()[-1]


def _names(frame: pd.DataFrame) -> str:
    names = list(frame.engine)
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def closest_sentence(outcomes: pd.DataFrame, robot: str, noun: str = RUNS) -> dict:
    for metric in PRIMARY:
        g = outcomes[outcomes.metric == metric]
        best = g[g.is_best.astype(bool)]
        if best.empty or best.outcome.iloc[0] == "not measurable":
            continue
        b = best.iloc[0]
        label, unit = b.label, f" {b.unit}" if isinstance(b.unit, str) and b.unit else ""
        if b.outcome == "too few runs":
            lost = failed_runs(g, b.engine)
            return {
                "need": "closest",
                "text": f"Too few {noun} to name the engine closest to the {robot} on "
                f"{label}: {b.engine} has the lowest mean ({_f(b['mean'])}{unit}) over {int(b.n_runs)} {noun}"
                + (f", though {failure_clause(b, lost, noun)}" if lost else "")
                + ".",
                "rests_on": [_cite(b)],
            }
        text = (
            f"Closest to the {robot} on {label}: {b.engine} ({_f(b['mean'])}{unit} [{_f(b.low)}, {_f(b.high)}] "
            f"over {int(b.n_runs)} {noun})"
        )
        # an engine that failed runs the others completed is named with that, in this sentence
        lost = failed_runs(g, b.engine)
        others_lost = {e: failed_runs(g, e) for e in g.engine if e != b.engine and failed_runs(g, e)}
        if lost:
            text = (
                f"Closest to the {robot} on {label}, over the {int(b.n_runs)} {noun} every compared engine "
                f"completed: {b.engine} ({_f(b['mean'])}{unit} [{_f(b.low)}, {_f(b.high)}]), though "
                f"{failure_clause(b, lost, noun)}, which the others completed and no comparison counts"
            )
        elif others_lost:
            text += f", every engine judged on the {noun} all of them completed"
        if not b.recommendable:
            text += ", though no engine passes the mechanics this metric rests on"
        others = g[~g.is_best.astype(bool)]
        eq, worse, open_ = (others[others.outcome == k] for k in ("equivalent", "worse", "undetermined"))
        if len(eq):
            text += (
                f"; equivalent to it within the margin {_f(b.margin)}{unit} ({b.margin_basis}): {_names(eq)}, "
                "any of them serves as well"
            )
        if len(worse):
            text += f"; worse: {_names(worse)}"
        if len(open_):
            text += "; undetermined: " + ", ".join(
                f"{r.engine} (about {int(r.runs_needed)} {units(noun)} would decide)"
                if np.isfinite(r.runs_needed)
                else r.engine
                for r in open_.itertuples()
            )
        shown = others[~others.recommendable.astype(bool) & (others.outcome != "not measurable")]
        if len(shown):
            text += (
                f". {_names(shown)} fail{'s' if len(shown) == 1 else ''} the mechanics this metric rests on and "
                "cannot be the pick, whatever their figure"
            )
        return {
            "need": "closest",
            "text": text + ".",
            "rests_on": [_cite(b)] + [_cite(r) for _, r in others.iterrows() if r.outcome != "not measurable"],
        }
    return {
        "need": "closest",
        "text": f"No real-data metric could be measured: no engine can be named closest to the {robot}.",
        "rests_on": [],
    }


def failed_sentence(outcomes: pd.DataFrame, engines: list[str], noun: str = RUNS) -> dict | None:
    """Which engine failed which real runs that another completed, and why; None where no real-data
    metric was measured."""
    measured = outcomes[outcomes.outcome != "not measurable"] if len(outcomes) else outcomes
    if measured.empty:
        return None
    parts, rests = [], []
    for engine in engines:
        lost = failed_runs(measured, engine)
        if not lost:
            continue
        o = measured[measured.engine == engine].sort_values("runs_failed").iloc[-1]
        parts.append(failure_clause(o, lost, noun))
        rests += [f"outcomes.csv: {engine} failed_runs {run}: {why}" for run, why in lost]
    if not parts:
        n = int(pd.to_numeric(measured.runs_all, errors="coerce").max()) if "runs_all" in measured else 0
        return {
            "need": "failed",
            "text": f"Every engine completed every one of the {n} {noun}: all are compared on the same {units(noun)}.",
            "rests_on": [f"outcomes.csv: runs_failed 0 for every engine, runs_all {n}"],
        }
    common = pd.to_numeric(measured[measured.is_best.astype(bool)].n_runs, errors="coerce")
    text = "; ".join(parts)
    if len(common) and np.isfinite(common.min()):
        text += f". Each engine is compared on the {units(noun)} every compared engine completed ({int(common.min())})"
    return {"need": "failed", "text": text + ".", "rests_on": rests}


def fastest_sentence(answer: pd.DataFrame) -> dict:
    timed = answer[np.isfinite(answer.rtf.astype(float))]
    passing = timed[timed.mechanics == "pass"]
    if passing.empty:
        return {
            "need": "fastest",
            "text": "No engine that passes the mechanics has a measured real-time factor.",
            "rests_on": [],
        }
    f = passing.sort_values("rtf", ascending=False).iloc[0]
    text = (
        f"Fastest among the engines that pass the mechanics: {f.engine}, real-time factor {_f(f.rtf)} on the lab "
        f"runs (CPU load {_f(f.cpu_average)} % with one robot, {_f(f.cpu_intense)} % with several)"
    )
    quicker = timed[(timed.mechanics != "pass") & (timed.rtf > f.rtf)]
    if len(quicker):
        text += (
            f"; {_names(quicker)} run{'s' if len(quicker) == 1 else ''} faster but fail"
            f"{'s' if len(quicker) == 1 else ''} the mechanics"
        )
    rests = [
        f"answer.csv: {r.engine} rtf {_f(r.rtf)}, cpu_average {_f(r.cpu_average)}, mechanics {r.mechanics}"
        for r in timed.itertuples()
    ]
    return {"need": "fastest", "text": text + ".", "rests_on": rests}


def settings_sentence(outcomes: pd.DataFrame, answer: pd.DataFrame, calibration: pd.DataFrame, robot: str) -> dict:
    g = outcomes[(outcomes.metric == "gain_error") & outcomes.is_best.astype(bool)]
    if g.empty or g.outcome.iloc[0] == "not measurable":
        return {
            "need": "settings",
            "text": f"The real {robot}'s turning is not measured here (no real turning run): "
            "no setting can be derived from it.",
            "rests_on": [],
        }
    engine = g.engine.iloc[0]
    row = answer.set_index("engine").loc[engine]
    ratio = float(row.gain_ratio)
    if not np.isfinite(ratio) or ratio <= 0:
        return {
            "need": "settings",
            "text": f"{engine}'s turning against the real {robot} is not measured.",
            "rests_on": [],
        }
    text = (
        f"To turn like the real {robot}: {engine} as configured turns at {_f(ratio)} of the real robot's yaw "
        f"rate for the same wheel commands, so a simulated ROS diff_drive_controller needs the real robot's "
        f"wheel_separation_multiplier times {_f(1 / ratio)} (the yaw rate scales with it)"
    )
    rests = [f"answer.csv: {engine} gain_ratio {_f(ratio)}"]
    cal = calibration[calibration.engine == engine] if len(calibration) else calibration
    if len(cal) and np.isfinite(cal.gain_ratio.iloc[0]):
        c = cal.iloc[0]
        text += (
            f"; calibrated on training runs ({c.parameters}), it turns at {_f(c.gain_ratio)} of the real robot's "
            f"yaw rate on the held-out runs"
        )
        rests.append(f"calibration turning.csv: {engine} calibrated gain_ratio {_f(c.gain_ratio)} ({c.parameters})")
    return {"need": "settings", "text": text + ".", "rests_on": rests}


def avoid_sentence(outcomes: pd.DataFrame, answer: pd.DataFrame) -> dict:
    parts, rests = [], []
    for row in answer.itertuples():
        why = []
        if row.mechanics == "fail":
            why.append(row.mechanics_note)
            rests.append(f"answer.csv: {row.engine} mechanics fail, {row.mechanics_note}")
        worse = outcomes[(outcomes.engine == row.engine) & (outcomes.outcome == "worse")]
        for _, o in worse.iterrows():
            unit = f" {o.unit}" if isinstance(o.unit, str) and o.unit else ""
            why.append(
                f"{o.label} worse than {o.best} by {_f(o.diff_to_best)}{unit} [{_f(o.diff_low)}, "
                f"{_f(o.diff_high)}] (Holm p {_f(o.p_worse, 2)})"
            )
            rests.append(_cite(o))
        if why:
            parts.append(f"{row.engine}: {'; '.join(why)}")
    text = (
        ("Avoid " + "; ".join(parts) + ".")
        if parts
        else "No engine fails the mechanics or is worse than the best on a real-data metric."
    )
    return {"need": "avoid", "text": text, "rests_on": rests}


def sentences(
    outcomes: pd.DataFrame, answer: pd.DataFrame, calibration: pd.DataFrame, robot: str, noun: str = RUNS
) -> list[dict]:
    """One sentence per need: closest, the runs an engine failed, fastest, settings, avoid (answer.yaml's
    ``sentences``). ``noun``: what the real data's units are called ("real runs", "DRIVE steps")."""
    failed = failed_sentence(outcomes, list(answer.engine), noun)
    return [
        closest_sentence(outcomes, robot, noun),
        *([failed] if failed else []),
        fastest_sentence(answer),
        settings_sentence(outcomes, answer, calibration, robot),
        avoid_sentence(outcomes, answer),
    ]


def headline(said: list[dict], separation: list[dict], rank: pd.DataFrame) -> str:
    """The report's first paragraph, from the answer's sentences and the paper's rows."""
    parts = [s["text"] for s in said if s["need"] in ("closest", "failed", "avoid")]
    paper = [s for s in separation if s["method"] == "paper"]
    total = next((s for s in paper if s["metric"] == "total"), None)
    scores = [s for s in paper if s["metric"] != "total"]
    if total:
        parts.append(
            "The paper's method (Eq. 7/8 and its weighted table, shown as the paper defines it) ranks "
            f"{total['best']} first: {total['totals']} (intervals over the real runs)."
        )
        r = rank.sort_values("total", ascending=False)
        imu_spread = float(r.imu_points.max() - r.imu_points.min())
        gap = float(r.total.iloc[0] - r.total.iloc[1]) if len(r) > 1 else float("nan")
        if scores and np.isfinite(gap) and imu_spread < gap:
            ranges = " and ".join(f"{_f(s['low'])}–{_f(s['high'])} ({s['quantity']})" for s in scores)
            parts.append(
                f"That order is decided by qualitative facts, real-time factor and CPU load, not by how the "
                f"engines move the robot: the IMU accuracy scores are {ranges} for every engine, so they "
                f"move the totals by at most {imu_spread:.2f} points, less than the {gap:.2f} between the "
                f"first two."
            )
    return " ".join(parts)


def _and(names: list[str]) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


class AnswerBasis(JobParams):
    """The real data the answer rests on, as its sentences name them (simpick.plan's answer_basis)."""

    dataset: str = Field(description="the dataset's label ('' : none, no sentence)")
    unit: str = Field("run", description="the unit of pairing: a real run, a DRIVE step or its session")
    noun: str | None = Field(None, description="what the sentences call the units (None: 'real runs')")
    title: str = Field("", description="how the units were compared, in brackets after them")
    others: list[str] = Field([], description="the study's other real data, compared in their own section")


def basis_sentence(basis: AnswerBasis | dict | None, n: int, left_out: list[str] | None = None) -> str:
    """Which real data the answer rests on, named with its units ("345 DRIVE steps", "12 BorealTC runs"),
    the study's engines the comparison did not judge, and the study's other real data, reported apart."""
    if not basis:
        return ""
    b = basis if isinstance(basis, AnswerBasis) else AnswerBasis.model_validate(basis)
    if not b.dataset:
        return ""
    unit = b.unit or "run"
    text = f"The answer rests on {n} {b.dataset} {unit}{'' if n == 1 else 's'}"
    if b.title:
        text += f" ({b.title})"
    if left_out:
        text += f"; {_and(left_out)} {'was' if len(left_out) == 1 else 'were'} not replayed on these data and "
        text += f"{'is' if len(left_out) == 1 else 'are'} not in the table"
    others = list(b.others)
    if others:
        text += f"; the study's other real data ({_and(others)}) are compared in their own section, not here"
    return text + "."


# --------------------------------------------------------------------------
# The simulators' answer: which simulator, as shipped, tuned or calibrated, and with which settings
# --------------------------------------------------------------------------


def _e(x) -> str:
    """A gain error as the simulators' table prints it (three decimals)."""
    return "–" if x is None or not np.isfinite(float(x)) else f"{float(x):.3f}"


def _profile(p: dict) -> str:
    """A simulator's profile as a sentence names it: ``Gazebo Classic, calibrated (friction_ratio 0.62)``."""
    text = f"{p['label']}, {p['variant']}"
    return text + (f" ({p['settings']})" if p.get("settings") else "")


def _against_spread(p: dict, spread: float | None) -> str:
    """A profile's gain error against the robot's own run-to-run spread of its gain."""
    interval = f" [{_e(p['low'])}, {_e(p['high'])}]" if p.get("low") is not None else ""
    text = f"{_e(p['error'])}{interval}"
    if spread is None or p.get("spread_ratio") is None:
        return text
    if p.get("within"):
        return f"{text}, within the robot's own spread of {_e(spread)}"
    return f"{text}, {p['spread_ratio']:.1f} times the robot's own spread of {_e(spread)}"


def _reason(text: str) -> str:
    """A reason's first clause, for the first page: what it says before its source (a parenthesis or a colon)."""
    return re.split(r" \(|: |; ", text, maxsplit=1)[0].strip().rstrip(".,")


def simulator_sentences(answer: dict, robot: str, noun: str = RUNS) -> list[dict]:
    """The first page's sentences on the simulators (simpick.score.profiles.simulator_answer
    of the simulators' table): the closest profile and its settings, the closest per variant, where a simulator
    cannot move its turning within its own settings, a profile that fits the runs by breaking its mechanics,
    and why no calibrated profile is there. Each names the table's figures it rests on."""
    if not answer.get("given"):
        return []
    spread, lead = answer.get("spread"), answer["lead"]
    runs = lead.get("runs")
    # held-out: the real runs no profile was fitted on; else every real run (no profile saw any)
    counted = f"{int(runs)} " if runs else ""
    over = f"{counted}held-out {units(noun)}" if answer["heldout"] else f"{counted}{noun}"
    metric = "yaw-rate gain error"
    text = f"Closest to the real {robot} on {over}: {_profile(lead)}, {metric} {_against_spread(lead, spread)}"
    if not lead["passes"]:
        text += f"; it {lead['mechanics']}, so no simulator reproduced here passes mechanics"
    said = [
        {
            "need": "closest",
            "title": "Which simulator",
            "text": text + ".",
            "files": lead["files"],
            "rests_on": [f"simulators/table.csv: {lead['simulator']} {lead['variant']} {answer['metric']}"],
        }
    ]
    per_variant = [
        f"{p['words']}, {p['label']} ({_e(p['error'])}"
        + (f", {p['spread_ratio']:.1f}x the spread" if p.get("spread_ratio") is not None else "")
        + ("" if p["passes"] else f"; {p['mechanics']}")
        + ")"
        for v, p in answer["by_variant"].items()
    ]
    if len(per_variant) > 1:
        said.append(
            {
                "need": "variants",
                "title": ", ".join(answer["by_variant"]).capitalize(),
                "text": "The closest simulator " + "; ".join(per_variant) + ".",
                "files": [],
                "rests_on": [f"simulators/table.csv: {answer['metric']} per variant"],
            }
        )
    fixed = [
        (s, p)
        for s in answer["simulators"]
        for p in s["profiles"]
        if p["variant"] == "calibrated" and p["not_settable"]
    ]
    if fixed:
        said.append(
            {
                "need": "not_settable",
                "title": "Where the settings cannot move the turning",
                "text": "; ".join(
                    f"{s['label']} cannot move its turning within its own settings ({_reason(p['not_settable'])}): "
                    f"the best it reaches is {_e(s['best']['error'])} ({s['best']['variant']})"
                    for s, p in fixed
                )
                + " (the sources: the simulators' section).",
                "files": [],
                "rests_on": ["simulators/table.csv: turning_settable"],
            }
        )
    broken = [
        (s, p)
        for s in answer["simulators"]
        for p in s["profiles"]
        if not p["passes"] and p["error"] is not None and s["best"] is not None and p["error"] < s["best"]["error"]
    ]
    if broken:
        said.append(
            {
                "need": "broken",
                "title": "Fits by breaking mechanics",
                "text": "; ".join(
                    f"{_profile({**p, 'label': s['label']})} comes closer ({_e(p['error'])}), but {p['mechanics']}: "
                    "never the pick"
                    for s, p in broken
                )
                + ".",
                "files": [],
                "rests_on": ["simulators/table.csv: mechanics, mechanics_own"],
            }
        )
    if answer.get("no_calibrated"):
        said.append(
            {
                "need": "no_calibrated",
                "title": "No calibrated profile",
                "text": answer["no_calibrated"][0].upper() + answer["no_calibrated"][1:] + "; the answer rests on the "
                "shipped and tuned profiles.",
                "files": [],
                "rests_on": ["simulators/table.csv: variant, status"],
            }
        )
    return said
