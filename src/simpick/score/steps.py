"""The verdict over replayed step units (DRIVE's steps, or any reader's): every engine against the best per
metric, over the per-step errors of :mod:`simpick.compare.steps`.

The verdict is BorealTC's (:func:`simpick.score.equivalence.outcomes_table`: each engine against the best,
Holm-adjusted one-sided tests and TOST equivalence against the practical margins). Its unit of pairing is
the step (``drive_replay.unit``): every engine replays the same step from the same measured wheels, so the
paired difference of two engines on one step cancels the step's command and the real values; DRIVE draws
each step's command at random, independently of the others, so steps are the experiment's replicates. The
five shared sessions (two on grass) are too few for a paired test by session (a sign-flip test needs six),
and a session's steps share its conditions (ground, weather, tyre pressure): the per-session rows show
whether a result holds in each session. ``unit: session`` pairs by session instead (means of its steps).
The gain error's margin, where the config bases it on the real robot's spread (``real_spread``), is the
real robot's own step-to-step repeatability (the single-step standard deviation of the gain between steps
of similar command within a terrain, :func:`simpick.compare.steps.gain_repeatability`), the floor no model
can beat.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Annotated, Any, Literal

import pandas as pd
from pydantic import Field

from simpick.compare.steps import ALL, gain_repeatability, step_errors, summary_table
from simpick.params import JobParams
from simpick.score.equivalence import outcomes_table
from simpick.score.mechanics import mechanics_table
from simpick.score.settings import Margin, Statistics, Verdict
from simpick.score.verdict import METRICS, metric_table, per_run_long, per_run_values
from simpick.tables import write_csv


def per_test(errors: pd.DataFrame, unit: str = "step") -> pd.DataFrame:
    """The errors in the verdict's per-test form: one test per step, its ``run`` the unit of pairing (the
    step itself, or its session)."""
    if unit not in ("step", "session"):
        raise ValueError(f"drive_replay.unit is 'step' or 'session', not {unit!r}")
    run = errors.session if unit == "session" else errors.session + "/" + errors.step.map("{:03d}".format)
    return errors.assign(
        run=run, test=errors.case, yaw_rate_gain_real=errors.gain_real, yaw_rate_gain_sim=errors.gain_sim
    )


def gain_margin_spec(spec: Margin, steps: pd.DataFrame, tolerance: float) -> tuple[dict, str | None]:
    """The gain error's margin spec for DRIVE, as simpick.score.equivalence reads it: where the config bases
    it on the real robot's spread, the real robot's step-to-step repeatability (absolute) and the sentence
    saying so; else the config's spec."""
    if spec.basis != "real_spread":
        return spec.model_dump(mode="json"), None
    sd, pairs = gain_repeatability(steps, tolerance)
    value = spec.value * sd
    factor = "" if spec.value == 1 else f"{spec.value:g} x "
    return {"basis": "absolute", "value": value}, (
        f"{factor}the real robot's own step-to-step repeatability of its yaw-rate gain: the single-step "
        f"standard deviation between the {pairs} pairs of steps of similar command (within a terrain), {sd:.3g}"
    )


def mechanics_gate(validation: pd.DataFrame | None, engines: list[str]) -> pd.DataFrame:
    """The verdict's mechanics gate (simpick.score.mechanics.mechanics_table) from the validation summary;
    None: no engine validated."""
    summary = (
        validation if validation is not None else pd.DataFrame(columns=["engine", "status", "case", "kind", "passed"])
    )
    return mechanics_table(summary, engines)


def outcomes(
    errors: pd.DataFrame,
    steps: pd.DataFrame,
    engines: list[str],
    verdict: Verdict | Mapping[str, Any],
    tolerance: float,
    validation: pd.DataFrame | None = None,
    unit: str = "step",
    statistics: dict | None = None,
    seed: int = 0,
) -> pd.DataFrame:
    """Every engine against the best per metric (:func:`simpick.score.equivalence.outcomes_table`), over
    all terrains (``scope`` all) and per terrain, paired by ``unit``. ``validation``: the validation
    summary (the mechanics gate: an engine failing the cases a metric rests on is never the best); None:
    no engine validated, the lowest mean is the reference and is named so. ``verdict``: the margins and
    mechanics (a mapping is validated as :class:`simpick.score.settings.Verdict`)."""
    typed = verdict if isinstance(verdict, Verdict) else Verdict.model_validate(verdict)
    # simpick.score.equivalence reads the margins and mechanics as mappings
    margins, gate = typed.margins.model_dump(mode="json"), typed.mechanics.model_dump(mode="json")
    mechanics = mechanics_gate(validation, engines)
    frames = []
    for scope, e in [(ALL, errors)] + list(errors.groupby("terrain_class", sort=True)):
        real = steps if scope == ALL else steps[steps.terrain_class == scope]
        tests = per_test(e, unit)
        spec, basis = gain_margin_spec(typed.margins.gain_error, real, tolerance)
        settings = {"margins": {**margins, "gain_error": spec}, "mechanics": gate}
        walls = {metric: per_run_values(tests, metric) for metric in METRICS}
        table = outcomes_table(walls, tests, engines, METRICS, mechanics, settings, statistics, seed)
        if basis:
            table.loc[table.metric == "gain_error", "margin_basis"] = basis
        # paired_by: the verdict's unit of pairing (step or session); "unit" stays the metric's own unit
        frames.append(table.assign(scope=scope, paired_by=unit))
    out = pd.concat(frames, ignore_index=True)
    return out[["scope", "paired_by"] + [c for c in out.columns if c not in ("scope", "paired_by")]]


def verdict_tables(
    errors: pd.DataFrame,
    engines: list[str],
    validation: pd.DataFrame | None = None,
    unit: str = "step",
    statistics: dict | None = None,
    seed: int = 0,
) -> dict[str, pd.DataFrame]:
    """The tables rule answer reads beside the outcomes, as the verdict writes them for BorealTC
    (simpick.score.verdict), over every terrain: ``per_test`` (one test per step, its run the unit of
    pairing), ``metrics`` (per-run values, the answer's figure), ``table`` (each engine against the next)
    and ``mechanics`` (the gate the outcomes rest on)."""
    tests = per_test(errors, unit)
    return {
        "per_test": tests,
        "metrics": per_run_long({m: per_run_values(tests, m) for m in METRICS}),
        "table": metric_table(tests, engines, statistics, seed),
        "mechanics": mechanics_gate(validation, engines),
    }


class CompareParams(JobParams):
    """What rule drive_compare's job reads: the engines it judges, the verdict's margins and mechanics, the
    statistics, the unit of pairing (``drive_replay.unit``), the similar-command tolerance and the seed."""

    engines: list[str] = Field(description="the study's engines the replay ran (drive_replay.models)")
    verdict: Verdict
    statistics: Statistics
    unit: Literal["step", "session"] = Field(description="the verdict's unit of pairing")
    tolerance: float = Field(
        description="rad/s, two steps are of similar command when both wheels' commands differ by at most this "
        "(simpick.real.steps.SIMILAR): the gain's repeatability pairs them"
    )
    seed: Annotated[int, Field(ge=0, lt=2**32)]


def compare_job(inputs: dict, params: dict, outputs: dict) -> None:
    """The replayed steps of every engine against the real robot, into ``errors``,
    ``summary`` and ``outcomes`` (CSV), and, where the study's first page rests on DRIVE (rule answer), the
    tables beside them that the verdict writes for BorealTC (results/verdict/), in the same form and over
    all terrains: ``per_test`` (one test per step, the verdict's per-test form), ``metrics`` (the per-run
    values the answer's figure draws), ``table`` (each engine against the next) and ``mechanics`` (the
    gate)."""
    p = CompareParams.model_validate(params)
    cases = pd.read_csv(inputs["cases"])
    steps = pd.read_csv(inputs["steps"])
    replayed = pd.concat([pd.read_csv(p) for p in inputs["replayed"]], ignore_index=True)
    validation = pd.read_csv(inputs["validation"]) if inputs.get("validation") else None
    errors = step_errors(cases, steps, replayed)
    # simpick.compare.steps and simpick.score.verdict read the statistics as a mapping
    statistics, verdict = p.statistics.model_dump(mode="json"), p.verdict
    engines = list(p.engines)
    write_csv(errors, outputs["errors"])
    write_csv(summary_table(errors, steps, p.tolerance, statistics, p.seed), outputs["summary"])
    write_csv(
        outcomes(errors, steps, engines, verdict, p.tolerance, validation, p.unit, statistics, p.seed),
        outputs["outcomes"],
    )
    tables = verdict_tables(errors, engines, validation, p.unit, statistics, p.seed)
    for name, frame in tables.items():
        if outputs.get(name):
            write_csv(frame, outputs[name])
