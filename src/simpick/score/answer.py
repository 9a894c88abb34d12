"""The answer a roboticist acts on: one row per engine and one sentence per need.

``answer.csv`` (one row per engine): whether it passes the analytic mechanics (the failed cases
counted by kind), each real-data metric's outcome against the best with the interval of the
difference and the margin (simpick.score.equivalence), how it turns as configured against the
real robot (simulated / real yaw-rate gain; after calibration where it ran), real-time factor, CPU
load, and the paper's weighted total and rank, flagged for every engine that fails mechanics (the
paper's table itself stays exactly the paper's), and the real runs it failed that another engine
completed, with the health reasons. ``answer.yaml``: a sentence per need (closest, the runs an engine
failed, fastest, settings, avoid), each with the figures it rests on. Every engine is compared on the
runs every compared engine completed (simpick.score.equivalence), and an engine that failed runs the
others completed is never named closest without that said in the same sentence.

This is rule ``answer``'s job, beside the paper's weighted ranking with its interval over runs,
the separation table and the headline: the work a weight edit reruns, kept small (no test of
the verdict is redone; those are rule ``verdict``'s, which reads no weight).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import numpy as np
import pandas as pd
import yaml
from pydantic import Field

from simpick.errors import InputError
from simpick.params import JobParams, NonNegative
from simpick.score.equivalence import FAILED_SEPARATOR, pooled
from simpick.score.settings import Statistics
from simpick.score.verdict import (
    DISCRIMINATION_COLUMNS,
    METRICS,
    SEPARATION_COLUMNS,
    paper_rows,
    ranking,
    read_per_test,
    run_key,
    separation_rows,
)
from simpick.tables import write_csv

ANSWER_COLUMNS = [
    "engine",
    "mechanics",
    "mechanics_failed",
    "mechanics_cases",
    "mechanics_note",
    *[f"{m}_{k}" for m in METRICS for k in ("outcome", "diff", "low", "high", "margin")],
    "gain_ratio",
    "gain_ratio_calibrated",
    "rtf",
    "cpu_average",
    "cpu_intense",
    "paper_total",
    "paper_rank",
    "paper_flag",
    "runs_failed",
    "failed_runs",
]
RUNS = "real runs"  # what the sentences call the real data's units where the basis names none
PRIMARY = ("gain_error", "heading_error", "speed_error")  # the metric a "closest" sentence rests on first
CALIBRATED_POOL = "target classes"  # simpick.studies.calibration.turning.TARGET_POOL: the held-out runs judged together


def _f(x, digits: int = 3) -> str:
    return "–" if x is None or not np.isfinite(float(x)) else f"{float(x):.{digits}g}"


def gain_ratios(per_test: pd.DataFrame, engines: list[str]) -> dict[str, float]:
    """engine -> simulated / real yaw-rate gain as configured: each over the engine's healthy
    turning tests, averaged within a run, then over runs (the same runs for both)."""
    need = {"yaw_rate_gain_sim", "yaw_rate_gain_real"}
    if not need <= set(per_test.columns) or per_test.empty:
        return {}
    frame = per_test[per_test.status == "ok"].assign(
        sim=lambda f: pd.to_numeric(f.yaw_rate_gain_sim, errors="coerce"),
        real=lambda f: pd.to_numeric(f.yaw_rate_gain_real, errors="coerce"),
    )
    frame = frame[np.isfinite(frame.sim) & np.isfinite(frame.real)]
    out = {}
    for engine in engines:
        g = frame[frame.engine == engine]
        if g.empty:
            continue
        runs = g.assign(_run=run_key(g)).groupby("_run")[["sim", "real"]].mean()
        real = float(runs.real.mean())
        out[engine] = float(runs.sim.mean()) / real if real else float("nan")
    return out


def calibrated(turning: str | None) -> pd.DataFrame:
    """The calibration's held-out turning rows as calibrated, per engine (empty where it did not run)."""
    if not turning or not Path(turning).is_file():
        return pd.DataFrame(columns=["engine", "gain_ratio", "parameters", "n_runs"])
    frame = pd.read_csv(turning, dtype={"parameters": str}, keep_default_na=False, na_values=[""])
    frame = frame[(frame.terrain_class == CALIBRATED_POOL) & (frame.variant == "calibrated")]
    return frame[["engine", "gain_ratio", "parameters", "n_runs"]].reset_index(drop=True)


def machine_figures(rtf: str, cpu_files: list[str]) -> tuple[dict, dict]:
    """engine -> real-time factor (the lab runs, one robot), and engine -> (CPU load % with one
    robot, with several), from a CPU run that passed its health check (NaN otherwise)."""
    rtf_frame = pd.read_csv(rtf)
    rtfs = dict(zip(rtf_frame.engine, rtf_frame.real_time_factor.astype(float)))
    cpu = {}
    for path in cpu_files:
        c = json.loads(Path(path).read_text())
        ok = (c.get("health") or {}).get("status", "ok") == "ok"
        cpu[c["engine"]] = (
            (float(c["average"]["load_percent"]), float(c["intense"]["load_percent"]))
            if ok
            else (float("nan"), float("nan"))
        )
    return rtfs, cpu


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


def answer_table(
    outcomes: pd.DataFrame,
    mechanics: pd.DataFrame,
    weighted: pd.DataFrame,
    engines: list[str],
    ratios: dict,
    calibration: pd.DataFrame,
    rtfs: dict,
    cpu: dict,
) -> pd.DataFrame:
    """One row per engine (``ANSWER_COLUMNS``), in the order of the study's engines."""
    mech = mechanics.set_index("engine")
    cal = calibration.set_index("engine").gain_ratio.to_dict() if len(calibration) else {}
    rows = []
    for engine in engines:
        m = mech.loc[engine]
        row = {
            "engine": engine,
            "mechanics": m.mechanics,
            "mechanics_failed": int(m.mechanics_failed),
            "mechanics_cases": int(m.mechanics_cases),
            "mechanics_note": m.mechanics_note,
        }
        for metric in METRICS:
            o = outcomes[(outcomes.metric == metric) & (outcomes.engine == engine)]
            o = o.iloc[0] if len(o) else {}
            row.update(
                {
                    f"{metric}_outcome": o.get("outcome", "not measurable"),
                    f"{metric}_diff": o.get("diff_to_best", float("nan")),
                    f"{metric}_low": o.get("diff_low", float("nan")),
                    f"{metric}_high": o.get("diff_high", float("nan")),
                    f"{metric}_margin": o.get("margin", float("nan")),
                }
            )
        flag = ""
        if m.mechanics == "fail":
            flag = (
                f"fails mechanics ({int(m.mechanics_failed)} of {int(m.mechanics_cases)} cases)"
                if int(m.mechanics_failed)
                else f"fails mechanics ({m.mechanics_note})"
            )
        average, intense = cpu.get(engine, (float("nan"), float("nan")))
        in_table = engine in weighted.index
        row.update(
            {
                "gain_ratio": ratios.get(engine, float("nan")),
                "gain_ratio_calibrated": cal.get(engine, float("nan")),
                "rtf": rtfs.get(engine, float("nan")),
                "cpu_average": average,
                "cpu_intense": intense,
                "paper_total": float(weighted.loc[engine, "total"]) if in_table else float("nan"),
                "paper_rank": int(weighted.loc[engine, "rank"]) if in_table else None,
                "paper_flag": flag,
            }
        )
        lost = failed_runs(outcomes, engine)
        row.update(
            {
                "runs_failed": len(lost),
                "failed_runs": FAILED_SEPARATOR.join(f"{r}: {why}" for r, why in lost),
            }
        )
        rows.append(row)
    return pd.DataFrame(rows, columns=ANSWER_COLUMNS)


def _cite(o: pd.Series) -> str:
    """A row of outcomes.csv as the figure a sentence rests on."""
    text = f"outcomes.csv: {o.metric} {o.engine} {o.outcome}, mean {_f(o['mean'])}"
    if not o.is_best and np.isfinite(o.diff_to_best):
        text += (
            f", difference to {o.best} {_f(o.diff_to_best)} [{_f(o.diff_low)}, {_f(o.diff_high)}], margin "
            f"{_f(o.margin)}, p_worse {_f(o.p_worse, 2)}, p_equivalent {_f(o.p_equivalent, 2)}"
        )
    return text


def _plain(noun: str) -> str:
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
                f"{r.engine} (about {int(r.runs_needed)} {_plain(noun)} would decide)"
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
            "text": f"Every engine completed every one of the {n} {noun}: all are compared on the same {_plain(noun)}.",
            "rests_on": [f"outcomes.csv: runs_failed 0 for every engine, runs_all {n}"],
        }
    common = pd.to_numeric(measured[measured.is_best.astype(bool)].n_runs, errors="coerce")
    text = "; ".join(parts)
    if len(common) and np.isfinite(common.min()):
        text += f". Each engine is compared on the {_plain(noun)} every compared engine completed ({int(common.min())})"
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


def read_outcomes(path: str) -> pd.DataFrame:
    """Every engine against the best per real-data metric, from the comparison the answer rests on: the
    verdict's outcomes.csv or the DRIVE comparison's (its rows over every terrain:
    simpick.score.equivalence.pooled). A table that is neither stops here, naming what it lacks."""
    frame = pooled(pd.read_csv(path))
    missing = [c for c in ("metric", "engine", "outcome", "is_best", "mean", "n_runs") if c not in frame]
    if missing:
        raise InputError(path, f"not an outcomes table: columns {missing} are missing", "rerun the rule that writes it")
    if frame.duplicated(["metric", "engine"]).any():
        raise InputError(path, "more than one row per metric and engine", "rerun the rule that writes it")
    return frame


def _and(names: list[str]) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


class AnswerBasis(JobParams):
    """The real data the answer rests on, as its sentences name them (simpick.plan's answer_basis)."""

    dataset: str = Field(description="the dataset's label ('' : none, no sentence)")
    unit: str = Field("run", description="the unit of pairing: a real run, a DRIVE step or its session")
    noun: str | None = Field(None, description="what the sentences call the units (None: 'real runs')")
    title: str = Field("", description="how the units were compared, in brackets after them")
    others: list[str] = Field([], description="the study's other real data, compared in their own section")


class AnswerParams(JobParams):
    """What rule answer's job reads: the study's engines, the statistics, the weights (the answer is what a
    weight edit reruns), the seed, the real data's source and title, the robot's name and the basis."""

    engines: list[str]
    statistics: Statistics
    weights: dict[str, NonNegative]
    seed: Annotated[int, Field(ge=0, lt=2**32)]
    source: str = Field(description="the real data's source (a source's name, or the DRIVE dataset)")
    source_title: str = Field(description="how the headline names the real data")
    robot: str = Field(description="the robot's name in the sentences")
    basis: AnswerBasis | None = Field(None, description="the real data the answer rests on; None: not named")


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


def answer_job(inputs: dict, params: dict, outputs: dict) -> None:
    """Rule ``answer``: the paper's weighted ranking with its interval over real runs (ranking.csv),
    the separation table, answer.csv, answer.yaml and the headline, from the scores (weighted.csv, or
    with ``inputs["scores"]`` the per-metric scores, weighed here at the params' weights into
    ``outputs["weighted"]``, ``["contributions"]`` and ``["drivers"]``; provenance.yaml), the real-data
    comparison's tables (outcomes, mechanics, table, per_test: the verdict's,
    with its discrimination table, where the study has one, else the DRIVE comparison's, which writes the
    same tables beside its outcomes; simpick.plan answer_tables), the lab's real-time factor, the CPU runs
    and, where it ran, the calibration's turning table. ``params.basis``: the dataset the comparison rests
    on, its unit ("step", "run") and the study's other real data, for the sentence that names them
    (``params``: :class:`AnswerParams`)."""
    p = AnswerParams.model_validate(params)
    # simpick.score.verdict's ranking reads the statistics as a mapping
    statistics, weights = p.statistics.model_dump(mode="json"), dict(p.weights)
    engines, seed = list(p.engines), p.seed
    if inputs.get("scores"):
        # the workflow weighs the scores here (rule answer writes weighted.csv, contributions.csv and
        # drivers.csv): one job less before the answer on a weight edit
        from simpick.score.jobs import weigh

        weigh(pd.read_csv(inputs["scores"], index_col="engine"), weights, outputs)
    weighted = pd.read_csv(outputs["weighted"] if inputs.get("scores") else inputs["weighted"], index_col=0)
    prov = yaml.safe_load(Path(inputs["provenance"]).read_text()) or {}
    acc = prov.get("accuracy") or {}
    acc_per_test = None
    if acc.get("set") not in (None, "lab") and Path(inputs["accuracy_tests"]).is_file():
        acc_per_test = read_per_test(inputs["accuracy_tests"])
    scored = [e for e in engines if e in weighted.index]
    rank = ranking(weighted.loc[scored], acc_per_test, acc.get("tests") or None, weights, statistics, seed=seed)
    write_csv(rank, outputs["ranking"])
    table = pd.read_csv(inputs["table"])
    # what the paper's accuracy scores separate: the verdict's, where the scores rest on its real runs; none
    # beside DRIVE's outcomes (the scores never rest on DRIVE's steps)
    disc = (
        pd.read_csv(inputs["discrimination"])
        if inputs.get("discrimination")
        else pd.DataFrame(columns=DISCRIMINATION_COLUMNS)
    )
    separation = separation_rows(table, p.statistics.min_runs) + paper_rows(rank, disc, weights)
    write_csv(pd.DataFrame(separation, columns=SEPARATION_COLUMNS), outputs["separation"])

    outcomes = read_outcomes(inputs["outcomes"])
    # the engines the comparison judged: a DRIVE replay may leave some of the study's out (drive_replay.models);
    # the answer names them rather than giving them a row without real data
    judged = set(outcomes.engine)
    left_out = [e for e in engines if e not in judged]
    engines = [e for e in engines if e in judged]
    mechanics = pd.read_csv(inputs["mechanics"])
    tests = read_per_test(inputs["per_test"])
    rtfs, cpu = machine_figures(inputs["rtf"], list(inputs["cpu"]))
    cal = calibrated(inputs.get("calibration_turning"))
    answer = answer_table(outcomes, mechanics, weighted, engines, gain_ratios(tests, engines), cal, rtfs, cpu)
    write_csv(answer, outputs["answer"])
    robot = p.robot or "real robot"
    noun = (p.basis.noun if p.basis else None) or RUNS
    said = sentences(outcomes, answer, cal, robot, noun)
    Path(outputs["answer_yaml"]).write_text(
        yaml.safe_dump({"robot": robot, "sentences": said}, sort_keys=False, allow_unicode=True, width=10_000)
    )
    n_runs = int(run_key(tests[tests.status == "ok"]).nunique()) if len(tests) else 0
    source = p.source_title or p.source or "real data"
    Path(outputs["headline"]).write_text(
        yaml.safe_dump(
            {
                "source": p.source,
                "source_title": source,
                "n_runs": n_runs,
                "min_runs": p.statistics.min_runs,
                "units": _plain(noun),
                "basis": basis_sentence(p.basis, n_runs, left_out),
                "level": p.statistics.level,
                "paragraph": headline(said, separation, rank),
            },
            sort_keys=False,
            allow_unicode=True,
        )
    )
