"""simpick's verdict (simpick.score.verdict): per-run metrics, intervals and separation over runs, the
paper's accuracy scores' discrimination and its weighted total with an interval over runs."""

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from simpick.score.verdict import (
    METRICS,
    metric_table,
    ranking,
    runs_needed,
    score_discrimination,
    separation_rows,
    verdict_job,
)

STATS = {"min_runs": 6, "level": 0.95}


def _tests(values: dict[str, list[float]], metric: str = "heading_error", per_run: int = 1) -> pd.DataFrame:
    """One test per value; ``per_run`` consecutive values share a run (classes a and b alternate)."""
    rows = []
    for engine, vals in values.items():
        for i, v in enumerate(vals):
            run = i // per_run
            rows.append(
                {
                    "engine": engine,
                    "terrain_class": "ice" if run % 2 else "snow",
                    "run": f"{run:02d}",
                    "test": f"t{i}",
                    "status": "ok",
                    metric: v,
                }
            )
    return pd.DataFrame(rows)


def test_a_metric_is_averaged_within_a_run_and_pooled_over_runs():
    # two tests per run: run means 1.5, 3.5, 5.5, 7.5, 9.5, 11.5 -> mean 6.5
    frame = _tests({"a": list(range(1, 13)), "b": [x + 1 for x in range(1, 13)]}, per_run=2)
    table = metric_table(frame, ["a", "b"], STATS).set_index(["metric", "model"])
    a = table.loc[("heading_error", "a")]
    assert a.n_runs == 6 and a["mean"] == pytest.approx(6.5) and a.low < 6.5 < a.high
    # b is worse by exactly 1 in every run: the sign-flip test's smallest p over 6 runs, 2 / 64
    assert a["rank"] == 1 and a.next == "b" and a.diff_to_next == pytest.approx(-1.0)
    assert a.p_to_next == pytest.approx(2 / 64) and bool(a.separates_from_next) is True
    # the speed error: BorealTC has no measured speed, and the table says so for every model
    speed = table.loc["speed_error"]
    assert (speed.n_runs == 0).all() and speed.note.str.startswith("not measurable on this data").all()


def test_engines_that_cannot_be_told_apart_are_named_with_the_runs_that_would_change_it():
    # differences b - a per run: +1, -0.5, +1, -0.5, +1, -0.5: mean 0.25, sd 0.822
    a = [10.0, 11.0, 12.0, 13.0, 14.0, 15.0]
    b = [x + d for x, d in zip(a, (1, -0.5, 1, -0.5, 1, -0.5))]
    table = metric_table(_tests({"a": a, "b": b, "kinematic": a}), ["a", "b"], STATS)
    row = table[(table.metric == "heading_error") & (table.model == "a")].iloc[0]
    assert bool(row.separates_from_next) is False and row.p_to_next > 0.05
    d = np.array([1, -0.5, 1, -0.5, 1, -0.5]) * -1  # a - b
    # n = ((1.96 + 0.8416) * sd / |mean|)^2 = (2.8016 * 0.8216 / 0.25)^2 = 84.8 -> 85
    assert runs_needed(d, 0.95) == 85 == row.runs_needed
    ref = table[(table.metric == "heading_error") & (table.model == "kinematic")].iloc[0]
    assert not ref.is_engine and np.isnan(ref["rank"])  # a reference model is shown, never ranked
    (sep,) = [s for s in separation_rows(table, 6) if s["metric"] == "heading_error"]
    assert sep["separates"] is False and "a, b cannot be told apart" in sep["statement"]
    assert "about 85 runs" in sep["statement"]


def test_below_min_runs_nothing_is_separated_or_ranked_as_closest():
    table = metric_table(_tests({"a": [1.0] * 5, "b": [2.0] * 5}), ["a", "b"], STATS)
    row = table[(table.metric == "heading_error") & (table.model == "a")].iloc[0]
    assert pd.isna(row.separates_from_next) and row.note == "too few runs (5 < 6)" and np.isnan(row.low)
    (sep,) = [s for s in separation_rows(table, 6) if s["metric"] == "heading_error"]
    assert sep["separates"] is None and "too few runs (5 < 6)" in sep["statement"]


def _unit_errors(errors: dict[str, list[float]]) -> pd.DataFrame:
    rows = [
        {
            "engine": e,
            "terrain_class": "ice",
            "run": f"{i:02d}",
            "test": f"ice-{i:02d}",
            "status": "ok",
            "error_angular": v,
            "error_linear": v,
        }
        for e, vals in errors.items()
        for i, v in enumerate(vals)
    ]
    return pd.DataFrame(rows)


def test_score_discrimination_splits_the_error_into_floor_and_engine():
    a = [10.0, 20.0, 5.0, 30.0, 8.0, 12.0]
    per_test = _unit_errors({"a": a, "b": [x + 1 for x in a], "k": a, "c": [x + 5 for x in a]})
    d = score_discrimination(per_test, ["a", "b"], ["k", "c"])
    rows = d[d.quantity == "angular"].set_index("engine")
    assert (rows.floor == 85.0).all() and (rows.n_runs == 6).all()  # the smaller reference total
    assert rows.loc["b", "error"] == 91.0 and rows.loc["b", "engine_part"] == 6.0
    assert rows.loc["b", "floor_share"] == pytest.approx(85 / 91) and rows.loc["a", "floor_share"] == 1.0
    assert rows.loc["b", "score"] == pytest.approx(85 / 91) and rows.spread.iloc[0] == pytest.approx(6 / 91)
    assert rows.separates.iloc[0] is True or rows.separates.iloc[0] == True  # noqa: E712

    noisy = _unit_errors({"a": a, "b": [x + s for x, s in zip(a, (6, -5, 4, -6, 5, -3))], "k": a})
    d = score_discrimination(noisy, ["a", "b"], ["k"])
    assert d.spread.iloc[0] == pytest.approx(1 - 85 / 86) and not d.separates.iloc[0]

    d = score_discrimination(_unit_errors({"a": a[:3], "b": a[:3], "k": a[:3]}), ["a", "b"], ["k"])
    assert d.separates.isna().all() and d.half_width.isna().all()


def _weighted() -> pd.DataFrame:
    # totals: a = 30 + 10 x 1 + 10 x 1 = 50; b = 32 + 10 x 0.9 + 10 x 0.8 = 49
    return pd.DataFrame(
        {"imu_angular": [1.0, 0.9], "imu_linear": [1.0, 0.8], "total": [50.0, 49.0], "rank": [1, 2]},
        index=pd.Index(["a", "b"], name="engine"),
    )


WEIGHTS = {"imu_angular": 10, "imu_linear": 10}


def test_the_papers_total_gets_an_interval_over_runs_with_the_rest_held_as_measured():
    a = [10.0, 20.0, 5.0, 30.0, 8.0, 12.0]
    per_test = _unit_errors({"a": a, "b": [x + s for x, s in zip(a, (6, -5, 4, -6, 5, -3))]})
    rank = ranking(_weighted(), per_test, None, WEIGHTS, STATS).set_index("engine")
    assert rank.loc["a", "other_points"] == pytest.approx(30.0) and rank.loc["b", "other_points"] == pytest.approx(32.0)
    assert rank.loc["a", "imu_points"] == pytest.approx(20.0) and rank.n_runs.eq(6).all()
    # every draw's accuracy scores are at most 1: a total never exceeds its rest + 20
    assert rank.loc["b", "total_high"] <= 52.0 + 1e-9 and rank.loc["b", "total_low"] >= 32.0
    assert rank.share_first.sum() == pytest.approx(1.0)
    # below min_runs, or on the lab (no per-test runs): no interval
    few = ranking(_weighted(), per_test[per_test.run < "03"], None, WEIGHTS, STATS)
    assert few.total_low.isna().all() and (few.n_runs == 3).all()
    assert ranking(_weighted(), None, None, WEIGHTS, STATS).total_low.isna().all()


VERDICT_SETTINGS = {
    "margins": {
        "gain_error": {"basis": "absolute", "value": 0.05},
        "heading_error": {"basis": "absolute", "value": 0.05},
        "speed_error": {"basis": "absolute", "value": 0.05},
    },
    "mechanics": {
        "gain_error": ["yaw_gain", "invariance"],
        "heading_error": ["yaw_gain", "invariance", "straight"],
        "speed_error": ["straight"],
    },
}


def _validation(failing: dict[str, list[str]] | None = None, engines=("a", "b")) -> pd.DataFrame:
    """A validation summary: each engine runs a yaw-gain, a straight and an incline case; ``failing``
    names the kinds an engine fails."""
    rows = []
    for e in engines:
        for case, kind in (("gain", "yaw_gain"), ("straight", "straight"), ("incline", "incline")):
            rows.append(
                {
                    "engine": e,
                    "case": case,
                    "kind": kind,
                    "passed": kind not in (failing or {}).get(e, []),
                    "status": "ok",
                }
            )
    return pd.DataFrame(rows)


def test_the_verdict_and_answer_jobs_write_every_table_and_the_headline(tmp_path):
    from simpick.score.answer import answer_job

    a = [0.1, 0.2, 0.15, 0.3, 0.12, 0.22]
    frame = _tests({"a": a, "b": [x + 0.2 for x in a], "k": a})
    frame["error_angular"], frame["error_linear"] = 1.0, 2.0
    frame["gain_error"] = [x / 10 for x in frame.heading_error]
    frame["yaw_rate_gain_real"], frame["yaw_rate_gain_sim"] = 0.6, 0.5
    frame.loc[frame.engine == "b", "yaw_rate_gain_sim"] = 0.3
    per_test = tmp_path / "per_test.csv"
    frame.to_csv(per_test, index=False)
    errors = tmp_path / "imu_errors.csv"
    pd.DataFrame(
        {"engine": ["a", "b"], "quantity": "angular", "error": 1.0, "tests": ";".join(sorted(frame.test.unique()))}
    ).to_csv(errors, index=False)
    validation = tmp_path / "validation.csv"
    _validation({"b": ["incline"]}).to_csv(validation, index=False)
    verdict_out = {
        k: str(tmp_path / "verdict" / f"{k}.csv")
        for k in ("metrics", "table", "discrimination", "headings", "outcomes", "mechanics")
    }
    params = {
        "engines": ["a", "b"],
        "baselines": ["k"],
        "statistics": STATS,
        "seed": 1,
        "accuracy_set": "segments",
        "verdict": VERDICT_SETTINGS,
    }
    verdict_job(
        {
            "per_test": str(per_test),
            "accuracy_tests": str(per_test),
            "accuracy_errors": str(errors),
            "validation": str(validation),
        },
        params,
        verdict_out,
    )
    outcomes = pd.read_csv(verdict_out["outcomes"]).set_index(["metric", "engine"])
    assert outcomes.loc[("heading_error", "a"), "outcome"] == "best"
    assert outcomes.loc[("heading_error", "b"), "outcome"] == "worse"  # 0.2 rad worse in every run
    assert (outcomes.loc["speed_error"].outcome == "not measurable").all()
    assert not pd.read_csv(verdict_out["discrimination"]).empty

    weighted = tmp_path / "weighted.csv"
    _weighted().to_csv(weighted)
    provenance = tmp_path / "provenance.yaml"
    provenance.write_text(yaml.safe_dump({"accuracy": {"set": "segments", "tests": sorted(frame.test.unique())}}))
    rtf = tmp_path / "rtf.csv"
    pd.DataFrame({"engine": ["a", "b"], "real_time_factor": [2.0, 5.0]}).to_csv(rtf, index=False)
    cpu = []
    for e, load in (("a", 10.0), ("b", 5.0)):
        cpu.append(tmp_path / f"{e}.json")
        cpu[-1].write_text(
            json.dumps({"engine": e, "average": {"load_percent": load}, "intense": {"load_percent": 3 * load}})
        )
    answer_out = {k: str(tmp_path / "verdict" / f"{k}.csv") for k in ("ranking", "separation", "answer")}
    answer_out |= {
        "answer_yaml": str(tmp_path / "verdict" / "answer.yaml"),
        "headline": str(tmp_path / "verdict" / "headline.yaml"),
    }
    answer_job(
        {
            "per_test": str(per_test),
            "accuracy_tests": str(per_test),
            "weighted": str(weighted),
            "provenance": str(provenance),
            "table": verdict_out["table"],
            "discrimination": verdict_out["discrimination"],
            "outcomes": verdict_out["outcomes"],
            "mechanics": verdict_out["mechanics"],
            "rtf": str(rtf),
            "cpu": [str(c) for c in cpu],
        },
        {
            "engines": ["a", "b"],
            "statistics": STATS,
            "weights": WEIGHTS,
            "seed": 1,
            "source": "segments",
            "source_title": "test segments",
            "robot": "test robot",
        },
        answer_out,
    )
    separation = pd.read_csv(answer_out["separation"]).set_index("metric")
    assert set(METRICS) <= set(separation.index) and {"imu_angular", "imu_linear", "total"} <= set(separation.index)
    assert separation.loc["total", "method"] == "paper"
    metrics = pd.read_csv(verdict_out["metrics"])
    assert len(metrics[(metrics.metric == "heading_error")]) == 18  # 6 runs x 3 models
    answer = pd.read_csv(answer_out["answer"], keep_default_na=False).set_index("engine")
    assert answer.loc["b", "mechanics"] == "fail" and answer.loc["b", "paper_flag"] == "fails mechanics (1 of 3 cases)"
    assert answer.loc["a", "paper_flag"] == "" and float(answer.loc["a", "paper_total"]) == 50.0
    assert float(answer.loc["a", "gain_ratio"]) == pytest.approx(0.5 / 0.6)
    assert float(answer.loc["b", "rtf"]) == 5.0 and float(answer.loc["a", "cpu_intense"]) == 30.0
    said = {s["need"]: s for s in yaml.safe_load(Path(answer_out["answer_yaml"]).read_text())["sentences"]}
    assert list(said) == ["closest", "failed", "fastest", "settings", "avoid"] and all(
        s["rests_on"] for s in said.values()
    )
    assert said["failed"]["text"].startswith("Every engine completed every one of the 6 real runs")
    # b is faster but fails the mechanics: a is the fastest that passes
    assert (
        said["fastest"]["text"].startswith("Fastest among the engines that pass the mechanics: a, real-time factor 2")
        and "b runs faster but fails the mechanics" in said["fastest"]["text"]
    )
    assert "times 1.2 " in said["settings"]["text"]  # the real robot's multiplier x 0.6 / 0.5
    assert said["avoid"]["text"].startswith("Avoid b: fails 1 of 3 analytic cases: incline (1)")
    head = yaml.safe_load(Path(answer_out["headline"]).read_text())
    assert head["n_runs"] == 6 and head["paragraph"].startswith("Closest to the test robot on yaw-rate gain error: a")
    assert "The paper's method" in head["paragraph"]


def test_the_heading_spread_is_each_gain_over_the_coulomb_gain_on_the_same_test():
    rows = []
    for test, heading, gains in (
        ("t0", 0.0, {"p": 0.1, "coulomb": 0.5}),
        ("t1", 45.0, {"p": 0.5, "coulomb": 0.5}),
        ("t2", 90.0, {"p": 0.12, "coulomb": 0.4}),
    ):
        for model, g in gains.items():
            rows.append(
                {
                    "engine": model,
                    "test": test,
                    "terrain_class": "asphalt",
                    "run": test,
                    "status": "ok",
                    "start_heading_deg": heading,
                    "yaw_rate_gain_sim": g,
                }
            )
    from simpick.score.verdict import heading_spread

    out = heading_spread(pd.DataFrame(rows)).set_index("test")
    assert list(out.model) == ["p"] * 3
    np.testing.assert_allclose(out.gain_ratio, [0.2, 1.0, 0.3])
    assert heading_spread(pd.DataFrame(rows)[lambda f: f.engine != "coulomb"]).empty


def test_the_headline_says_plainly_when_the_papers_order_is_not_decided_by_the_imu_scores():
    from simpick.score.sentences import headline
    from simpick.score.verdict import paper_rows

    weighted = _weighted().assign(total=[60.0, 49.0])  # the rest: 40 and 32; IMU 20 and 17 points
    rank = ranking(weighted, None, None, WEIGHTS, STATS)
    disc = pd.DataFrame(
        [
            {"quantity": q, "engine": e, "score": s, "spread": 0.2, "half_width": 0.3, "separates": False, "n_runs": 6}
            for q in ("angular", "linear")
            for e, s in (("a", 1.0), ("b", 0.85))
        ]
    )
    text = headline([], paper_rows(rank, disc, WEIGHTS), rank)
    # IMU points differ by 3, the totals by 11: the order comes from the rest
    assert "ranks a first: a 60.000, b 49.000" in text
    assert (
        "decided by qualitative facts, real-time factor and CPU load" in text
        and "0.85–1 (angular) and 0.85–1 (linear)" in text
        and "at most 3.00 points, less than the 11.00" in text
    )
    close = ranking(_weighted(), None, None, WEIGHTS, STATS)  # totals 50 and 49: the IMU scores could swap them
    assert "decided by" not in headline([], paper_rows(close, disc, WEIGHTS), close)


# --- every engine against the best: outcomes on data whose answer is known -------------------------------


def _gain_tests(values: dict[str, list[float]]) -> pd.DataFrame:
    """One turning test per run and engine with the gain error given (runs alternate two classes)."""
    frame = _tests(values, metric="gain_error")
    frame["kind"] = "turning"
    return frame


def _outcomes(
    values: dict[str, list[float]], failing: dict[str, list[str]] | None = None, settings: dict | None = None
) -> pd.DataFrame:
    from simpick.score.equivalence import outcomes_table
    from simpick.score.mechanics import mechanics_table
    from simpick.score.verdict import per_run_values

    frame = _gain_tests(values)
    engines = [e for e in values if e != "k"]
    walls = {m: per_run_values(frame, m) for m in METRICS}
    mechanics = mechanics_table(_validation(failing, engines), engines)
    table = outcomes_table(walls, frame, engines, METRICS, mechanics, settings or VERDICT_SETTINGS, STATS, seed=3)
    return table[table.metric == "gain_error"].set_index("engine")


BEST = [0.20, 0.25, 0.18, 0.30, 0.22, 0.27, 0.24, 0.21]


def test_each_engine_against_the_best_is_equivalent_worse_or_undetermined():
    rng = np.random.default_rng(7)
    values = {
        "best": BEST,
        "near": [x + d for x, d in zip(BEST, rng.normal(0.004, 0.004, 8))],  # within 0.05, tightly
        "far": [x + d for x, d in zip(BEST, rng.normal(0.15, 0.01, 8))],  # 0.15 worse in every run
        "noisy": [x + d for x, d in zip(BEST, (0.09, -0.08, 0.1, -0.07, 0.12, -0.05, 0.08, -0.06))],
    }
    out = _outcomes(values)
    assert out.loc["best", "outcome"] == "best" and out.loc["best", "is_best"] and (out.best == "best").all()
    assert out.loc["near", "outcome"] == "equivalent"
    assert -0.05 < out.loc["near", "diff_low"] < out.loc["near", "diff_high"] < 0.05
    assert out.loc["near", "p_equivalent"] < 0.05
    assert out.loc["far", "outcome"] == "worse" and out.loc["far", "p_worse"] < 0.05
    assert out.loc["far", "diff_to_best"] == pytest.approx(np.mean(np.array(values["far"]) - BEST))
    # a mean difference of 0.016 inside the margin but an interval far wider than it: undetermined, with the
    # runs a TOST at this spread would need: ((z_0.95 + z_0.8) sd / (0.05 - 0.01625))^2
    noisy = out.loc["noisy"]
    assert noisy.outcome == "undetermined" and np.isnan(out.loc["near", "runs_needed"])
    d = np.array(values["noisy"]) - BEST
    z = 1.6448536 + 0.8416212
    assert noisy.runs_needed == np.ceil((z * d.std(ddof=1) / (0.05 - abs(d.mean()))) ** 2)
    assert (out.margin == 0.05).all() and (out.margin_basis == "declared in the config: 0.05").all()
    assert out.recommendable.all() and (out.mechanics == "pass").all()


def test_an_engine_failing_the_mechanics_is_never_the_best_however_low_its_error():
    values = {"artefact": [x - 0.1 for x in BEST], "ok": BEST, "other": [x + 0.001 for x in BEST]}
    out = _outcomes(values, failing={"artefact": ["yaw_gain"]})
    assert (out.best == "ok").all() and out.loc["ok", "outcome"] == "best"
    art = out.loc["artefact"]
    assert art.outcome != "best" and not art.is_best and not art.recommendable and art.mechanics == "fail"
    assert art["mean"] == pytest.approx(np.mean(BEST) - 0.1)  # its figure is shown
    assert "never recommended" in art.note and art.mechanics_note == "fails 1 of 3 analytic cases: yaw gain (1)"
    assert out.loc["other", "outcome"] == "equivalent"
    # failing a case the metric does not rest on (an incline) leaves an engine recommendable on it
    out = _outcomes(values, failing={"artefact": ["incline"]})
    assert out.loc["artefact", "is_best"] and out.loc["artefact", "mechanics"] == "fail"
    # no engine passes: the lowest mean is the reference of the comparison, flagged, not recommended
    out = _outcomes(values, failing={e: ["yaw_gain"] for e in values})
    assert out.loc["artefact", "is_best"] and not out.loc["artefact", "recommendable"]
    assert "not as a recommendation" in out.loc["artefact", "note"]


def test_too_few_runs_and_a_metric_the_data_cannot_measure():
    out = _outcomes({"a": BEST[:5], "b": [x + 0.2 for x in BEST[:5]]})
    assert (out.outcome == "too few runs").all() and out.p_worse.isna().all()
    from simpick.score.equivalence import outcomes_table
    from simpick.score.mechanics import mechanics_table

    frame = _gain_tests({"a": BEST})
    table = outcomes_table(
        {},
        frame,
        ["a"],
        METRICS,
        mechanics_table(_validation(engines=["a"]), ["a"]),
        VERDICT_SETTINGS,
        STATS,
        absent={"speed_error": "no measured speed"},
    )
    speed = table[table.metric == "speed_error"].iloc[0]
    assert speed.outcome == "not measurable" and speed.note == "no measured speed" and speed.n_runs == 0


def test_holm_tost_and_the_interval_are_the_libraries():
    """The outcome table's p-values and intervals are scipy's and statsmodels' on the same per-run pairs."""
    from scipy.stats import ttest_rel
    from statsmodels.stats.multitest import multipletests
    from statsmodels.stats.weightstats import ttost_paired

    rng = np.random.default_rng(11)
    best = np.array(BEST)
    values = {"best": list(best)} | {
        e: list(best + rng.normal(mu, 0.02, 8)) for e, mu in (("b", 0.01), ("c", 0.03), ("d", 0.06))
    }
    out = _outcomes(values)
    raw = [ttest_rel(values[e], best, alternative="greater").pvalue for e in ("b", "c", "d")]
    np.testing.assert_allclose(out.loc[["b", "c", "d"], "p_worse"], multipletests(raw, method="holm")[1], rtol=1e-12)
    for e in ("b", "c", "d"):
        assert out.loc[e, "p_equivalent"] == pytest.approx(
            ttost_paired(np.array(values[e]), best, -0.05, 0.05)[0], rel=1e-12
        )
        ci = ttest_rel(values[e], best).confidence_interval(0.95)
        assert (out.loc[e, "diff_low"], out.loc[e, "diff_high"]) == pytest.approx((ci.low, ci.high), rel=1e-12)


def test_a_margin_from_the_real_robots_own_run_to_run_spread():
    from simpick.score.equivalence import margin

    # class x: runs at 0.5 and 0.7 (variance 0.02, 1 dof); class y: 0.3, 0.3, 0.6 (0.03, 2 dof); class z one run
    rows = [("x", "1", 0.5), ("x", "2", 0.7), ("y", "1", 0.3), ("y", "2", 0.3), ("y", "3", 0.6), ("z", "1", 0.9)]
    frame = pd.DataFrame(
        [
            {"engine": e, "terrain_class": c, "run": r, "test": f"{c}{r}", "status": "ok", "yaw_rate_gain_real": g}
            for c, r, g in rows
            for e in ("a", "b")
        ]
    )
    value, basis = margin(frame, "gain_error", {"basis": "real_spread", "value": 1.0})
    assert value == pytest.approx(np.sqrt((0.02 * 1 + 0.03 * 2) / 3))
    assert "over 5 runs in 2 terrain classes" in basis
    assert margin(frame, "gain_error", {"basis": "real_spread", "value": 0.5})[0] == pytest.approx(value / 2)
    assert margin(frame, "gain_error", {"basis": "real_fraction", "value": 0.1})[0] == pytest.approx(0.1 * 3.3 / 6)
    lone = margin(frame[frame.terrain_class == "z"], "gain_error", {"basis": "real_spread", "value": 1.0})
    assert np.isnan(lone[0]) and "cannot be measured" in lone[1]


def test_the_mechanics_gate_counts_failed_cases_by_kind_and_ignores_skipped_ones():
    from simpick.score.mechanics import mechanics_table, recommendable

    summary = pd.DataFrame(
        [
            {"engine": "p", "case": "g1", "kind": "yaw_gain", "passed": False, "status": "ok"},
            {"engine": "p", "case": "g1", "kind": "yaw_gain", "passed": False, "status": "ok"},  # a second quantity
            {"engine": "p", "case": "g2", "kind": "yaw_gain", "passed": False, "status": "ok"},
            {"engine": "p", "case": "i1", "kind": "incline", "passed": False, "status": "ok"},
            {"engine": "p", "case": "s1", "kind": "straight", "passed": True, "status": "ok"},
            {"engine": "p", "case": "r1", "kind": "yaw_gain", "passed": False, "status": "skipped"},
            {"engine": "p", "case": "left_right", "kind": "invariance", "passed": False, "status": "ok"},
            {"engine": "q", "case": "g1", "kind": "yaw_gain", "passed": True, "status": "ok"},
        ]
    )
    table = mechanics_table(summary, ["p", "q", "r"]).set_index("engine")
    assert table.loc["p", "mechanics_note"] == (
        "fails 3 of 4 analytic cases: yaw gain (2), incline (1); fails 1 turn symmetry and heading check"
    )
    assert table.loc["p", "mechanics_failed"] == 3 and table.loc["q", "mechanics"] == "pass"
    assert table.loc["r", "mechanics"] == "fail" and "not validated" in table.loc["r", "mechanics_note"]
    assert recommendable(table.reset_index(), ["straight"]) == {"p": True, "q": True, "r": False}
    assert recommendable(table.reset_index(), ["invariance"])["p"] is False


def test_per_class_verdicts_are_typed_columns_a_reader_takes_as_they_are():
    from simpick.compare.real import CLASS_OUTCOMES, class_verdicts, pairwise_table, summary_table

    rows = []
    for cls, runs in (("x", 6), ("y", 3)):
        for r in range(runs):
            for engine, err in (("a", 1.0 + r), ("b", 2.0 + r)):
                rows.append(
                    {
                        "engine": engine,
                        "terrain_class": cls,
                        "run": f"{r}",
                        "test": f"{cls}{r}",
                        "status": "ok",
                        "error_angular": err,
                        "error_linear": 5.0 - err / 10,
                    }
                )
    tests = pd.DataFrame(rows)
    pairwise = pairwise_table(tests, "terrain_class", STATS)
    x = pairwise[(pairwise.terrain_class == "x") & (pairwise.figure == "error_angular")].iloc[0]
    assert (x.outcome, x.closer, x.verdict, x.min_runs) == ("closer", "a", "a closer", 6)
    y = pairwise[pairwise.terrain_class == "y"]
    assert (y.outcome == "too few runs").all() and (y.closer.fillna("") == "").all()
    summary = class_verdicts(summary_table(tests, "terrain_class", STATS), pairwise, "terrain_class")
    s = summary.set_index(["terrain_class", "engine"])
    assert s.loc[("x", "a"), "error_angular_closest"] and not s.loc[("x", "b"), "error_angular_closest"]
    assert s.loc[("x", "a"), "error_angular_outcome"] == s.loc[("x", "b"), "error_angular_outcome"] == "clear"
    assert s.loc[("y", "a"), "error_angular_outcome"] == "too few runs"
    # error_linear: b has the smaller error in every run of x, and the test says so
    assert s.loc[("x", "b"), "error_linear_closest"] and s.loc[("x", "b"), "error_linear_outcome"] == "clear"
    assert set(summary.filter(like="_outcome").stack()) <= set(CLASS_OUTCOMES) | {""}


def test_the_answer_takes_the_calibrated_gain_ratio_from_the_calibrations_turning_table(tmp_path):
    from simpick.score.answer import answer_table, calibrated
    from simpick.score.mechanics import mechanics_table
    from simpick.score.sentences import settings_sentence

    turning = tmp_path / "turning.csv"
    pd.DataFrame(
        [
            {
                "terrain_class": "target classes",
                "engine": "a",
                "variant": "calibrated",
                "n_runs": 6,
                "gain_ratio": 0.97,
                "parameters": "friction_ratio=0.62",
            },
            {
                "terrain_class": "target classes",
                "engine": "a",
                "variant": "configured",
                "n_runs": 6,
                "gain_ratio": 0.7,
                "parameters": "",
            },
            {
                "terrain_class": "ice",
                "engine": "a",
                "variant": "calibrated",
                "n_runs": 2,
                "gain_ratio": 0.5,
                "parameters": "friction_ratio=0.62",
            },
        ]
    ).to_csv(turning, index=False)
    cal = calibrated(str(turning))
    assert list(cal.engine) == ["a"] and cal.gain_ratio.iloc[0] == 0.97
    assert calibrated(None).empty and calibrated(str(tmp_path / "none.csv")).empty
    outcomes = _outcomes({"a": BEST, "b": [x + 0.2 for x in BEST]})
    outcomes = outcomes.reset_index()
    weighted = pd.DataFrame({"total": [40.0, 30.0], "rank": [1, 2]}, index=pd.Index(["b", "a"], name="engine"))
    mechanics = mechanics_table(_validation(engines=["a", "b"]), ["a", "b"])
    answer = answer_table(outcomes, mechanics, weighted, ["a", "b"], {"a": 0.8, "b": 0.5}, cal, {"a": 1.0}, {})
    row = answer.set_index("engine").loc["a"]
    assert (row.gain_ratio, row.gain_ratio_calibrated, row.paper_rank, row.gain_error_outcome) == (0.8, 0.97, 2, "best")
    assert np.isnan(answer.set_index("engine").loc["b", "gain_ratio_calibrated"])
    said = settings_sentence(outcomes, answer, cal, "robot")
    assert "times 1.25" in said["text"] and "(friction_ratio=0.62), it turns at 0.97" in said["text"]


STUCK = "wheels do not track their command: mean speed error 0.62 rad/s beyond a 0.05 s servo lag around t = 2.5 s"


def _with_failures(values: dict[str, list[float]], failed: dict[str, list[int]]) -> pd.DataFrame:
    """``_gain_tests`` where each engine of ``failed`` failed the runs (by index) its health check named."""
    frame = _gain_tests(values)
    for engine, runs in failed.items():
        hit = (frame.engine == engine) & frame.run.isin([f"{r:02d}" for r in runs])
        frame.loc[hit, "gain_error"] = np.nan
        frame.loc[hit, "status"] = "failed"
        frame.loc[hit, "reasons"] = STUCK
    return frame


def _failure_case():
    # 11 runs; "lagger" failed 3 of them (runs 1, 4 and 7), where "steady" is far lower than on the
    # rest: over its own runs steady's mean is the lowest, over the 8 runs both completed lagger's is
    from simpick.score.equivalence import outcomes_table
    from simpick.score.mechanics import mechanics_table
    from simpick.score.verdict import per_run_values

    lost = [1, 4, 7]
    steady = [0.02 if i in lost else 0.30 for i in range(11)]
    values = {"lagger": [0.25 + 0.01 * (i % 3) for i in range(11)], "steady": steady, "far": [0.6] * 11}
    frame = _with_failures(values, {"lagger": lost})
    engines = list(values)
    walls = {m: per_run_values(frame, m) for m in METRICS}
    mechanics = mechanics_table(_validation(engines=engines), engines)
    table = outcomes_table(walls, frame, engines, METRICS, mechanics, VERDICT_SETTINGS, STATS, seed=3)
    return frame, values, lost, mechanics, table


def test_engines_are_compared_on_the_runs_every_compared_engine_completed():
    frame, values, lost, _, table = _failure_case()
    out = table[table.metric == "gain_error"].set_index("engine")
    common = [i for i in range(11) if i not in lost]
    # every engine's figure is over the 8 common runs, not the steady engine's own 11
    assert (out.n_runs == 8).all() and (out.runs_all == 11).all()
    assert out.loc["steady", "mean"] == pytest.approx(np.mean([values["steady"][i] for i in common]))
    assert np.mean(values["steady"]) < out.loc["lagger", "mean"] < out.loc["steady", "mean"]
    assert out.loc["lagger", "is_best"] and out.loc["lagger", "outcome"] == "best"
    # which runs it failed and why
    assert out.loc["lagger", "runs_completed"] == 8 and out.loc["lagger", "runs_failed"] == 3
    named = out.loc["lagger", "failed_runs"].split(" | ")
    runs = frame.drop_duplicates("run").set_index("run").terrain_class
    assert sorted(named) == sorted(f"{runs[f'{i:02d}']}/{i:02d}: {STUCK}" for i in lost)
    assert out.loc["steady", "runs_failed"] == 0 and out.loc["steady", "runs_completed"] == 11


def test_an_engine_that_failed_runs_is_named_closest_only_with_its_failures_in_the_same_sentence():
    from simpick.score.answer import answer_table
    from simpick.score.sentences import closest_sentence, failed_sentence

    frame, values, lost, mechanics, table = _failure_case()
    closest = closest_sentence(table, "Husky")["text"]
    named = closest.index("lagger (")
    said = closest[named:].split(". ")[0]  # the sentence that names it
    assert "lagger failed 3 of the 11 real runs" in said and "wheels do not track their command" in said
    runs = frame.drop_duplicates("run").set_index("run").terrain_class
    assert all(f"{runs[f'{i:02d}']}/{i:02d}" in said for i in lost)
    assert "over the 8 real runs every compared engine completed" in closest[:named]
    failed = failed_sentence(table, list(values))
    assert failed["text"].startswith("lagger failed 3 of the 11 real runs") and "steady" not in failed["text"]
    assert len(failed["rests_on"]) == 3 and all(STUCK in r for r in failed["rests_on"])
    weighted = pd.DataFrame({"total": [1.0, 2.0, 3.0], "rank": [3, 2, 1]}, index=list(values))
    answer = answer_table(table, mechanics, weighted, list(values), {}, pd.DataFrame(), {}, {}).set_index("engine")
    assert answer.loc["lagger", "runs_failed"] == 3 and answer.loc["steady", "runs_failed"] == 0
    assert answer.loc["lagger", "failed_runs"].count(STUCK) == 3


def test_the_first_page_lists_the_runs_an_engine_failed_and_why():
    from simpick.report.answer import answer_section
    from simpick.score.answer import answer_table
    from simpick.score.sentences import sentences

    _, values, _, mechanics, table = _failure_case()
    answer = answer_table(
        table, mechanics, pd.DataFrame({"total": [], "rank": []}), list(values), {}, pd.DataFrame(), {}, {}
    )
    said = sentences(table, answer, pd.DataFrame(), "Husky")
    assert [s["need"] for s in said][:2] == ["closest", "failed"]
    page = answer_section(answer, table, {"sentences": said}, list(values), None, {"health"})
    failed = [s for s in page["sentences"] if s["need"] == "failed"]
    assert len(failed) == 1 and failed[0]["title"] == "Runs an engine failed"
    assert failed[0]["figure"] == {"anchor": "health", "name": "Health of the runs"}
    assert "lagger failed 3 of the 11 real runs" in failed[0]["text"] and STUCK.split(":")[0] in failed[0]["text"]
