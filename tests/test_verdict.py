"""simpick's verdict (simpick.score.verdict): per-run metrics, intervals and separation over runs, the
paper's accuracy scores' discrimination and its weighted total with an interval over runs."""

import numpy as np
import pandas as pd
import pytest
import yaml

from simpick.score.verdict import (METRICS, metric_table, ranking, runs_needed, score_discrimination, separation_rows,
                             verdict_job)

STATS = {"min_runs": 6, "level": 0.95}


def _tests(values: dict[str, list[float]], metric: str = "heading_error", per_run: int = 1) -> pd.DataFrame:
    """One test per value; ``per_run`` consecutive values share a run (classes a and b alternate)."""
    rows = []
    for engine, vals in values.items():
        for i, v in enumerate(vals):
            run = i // per_run
            rows.append({"engine": engine, "terrain_class": "ice" if run % 2 else "snow", "run": f"{run:02d}",
                         "test": f"t{i}", "status": "ok", metric: v})
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
    rows = [{"engine": e, "terrain_class": "ice", "run": f"{i:02d}", "test": f"ice-{i:02d}", "status": "ok",
             "error_angular": v, "error_linear": v} for e, vals in errors.items() for i, v in enumerate(vals)]
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
    return pd.DataFrame({"imu_angular": [1.0, 0.9], "imu_linear": [1.0, 0.8], "total": [50.0, 49.0],
                         "rank": [1, 2]}, index=pd.Index(["a", "b"], name="engine"))


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


def test_the_verdict_job_writes_every_table_and_the_headline(tmp_path):
    a = [0.1, 0.2, 0.15, 0.3, 0.12, 0.22]
    frame = _tests({"a": a, "b": [x + 0.2 for x in a], "k": a})
    frame["error_angular"], frame["error_linear"] = 1.0, 2.0
    frame["gain_error"] = [x / 10 for x in frame.heading_error]
    per_test = tmp_path / "per_test.csv"
    frame.to_csv(per_test, index=False)
    weighted = tmp_path / "weighted.csv"
    _weighted().to_csv(weighted)
    provenance = tmp_path / "provenance.yaml"
    provenance.write_text(yaml.safe_dump({"accuracy": {"set": "segments", "per_test_file": str(per_test),
                                                       "tests": sorted(frame.test.unique())}}))
    outputs = {k: str(tmp_path / "verdict" / f"{k}.csv") for k in ("metrics", "table", "separation", "ranking",
                                                                     "discrimination", "headings")}
    outputs["headline"] = str(tmp_path / "verdict" / "headline.yaml")
    params = {"engines": ["a", "b"], "baselines": ["k"], "statistics": STATS, "weights": WEIGHTS, "seed": 1,
              "source": "segments", "source_title": "test segments"}
    verdict_job(str(per_test), str(weighted), str(provenance), params, outputs)
    separation = pd.read_csv(outputs["separation"]).set_index("metric")
    assert set(METRICS) <= set(separation.index) and {"imu_angular", "imu_linear", "total"} <= set(separation.index)
    assert bool(separation.loc["heading_error", "separates"]) and separation.loc["heading_error", "best"] == "a"
    assert separation.loc["total", "method"] == "paper"
    metrics = pd.read_csv(outputs["metrics"])
    assert len(metrics[(metrics.metric == "heading_error")]) == 18  # 6 runs x 3 models
    head = yaml.safe_load((tmp_path / "verdict" / "headline.yaml").read_text())
    assert head["n_runs"] == 6 and head["paragraph"].startswith("Closest to the real Husky")
    assert "heading error: a is closest" in head["paragraph"] and "The paper's method" in head["paragraph"]
    assert "speed error: not measurable on this data" in head["paragraph"].lower()


def test_the_heading_spread_is_each_gain_over_the_coulomb_gain_on_the_same_test():
    rows = []
    for test, heading, gains in (("t0", 0.0, {"p": 0.1, "coulomb": 0.5}), ("t1", 45.0, {"p": 0.5, "coulomb": 0.5}),
                                 ("t2", 90.0, {"p": 0.12, "coulomb": 0.4})):
        for model, g in gains.items():
            rows.append({"engine": model, "test": test, "terrain_class": "asphalt", "run": test, "status": "ok",
                         "start_heading_deg": heading, "yaw_rate_gain_sim": g})
    from simpick.score.verdict import heading_spread

    out = heading_spread(pd.DataFrame(rows)).set_index("test")
    assert list(out.model) == ["p"] * 3
    np.testing.assert_allclose(out.gain_ratio, [0.2, 1.0, 0.3])
    assert heading_spread(pd.DataFrame(rows)[lambda f: f.engine != "coulomb"]).empty


def test_the_headline_says_plainly_when_the_papers_order_is_not_decided_by_the_imu_scores():
    from simpick.score.verdict import headline, paper_rows

    weighted = _weighted().assign(total=[60.0, 49.0])  # the rest: 40 and 32; IMU 20 and 17 points
    rank = ranking(weighted, None, None, WEIGHTS, STATS)
    disc = pd.DataFrame([{"quantity": q, "engine": e, "score": s, "spread": 0.2, "half_width": 0.3,
                          "separates": False, "n_runs": 6} for q in ("angular", "linear")
                         for e, s in (("a", 1.0), ("b", 0.85))])
    text = headline(pd.DataFrame(), paper_rows(rank, disc, WEIGHTS), rank, "test data", 6)
    # IMU points differ by 3, the totals by 11: the order comes from the rest
    assert "ranks a first: a 60.000, b 49.000" in text
    assert ("decided by qualitative facts, real-time factor and CPU load" in text
            and "0.85–1 (angular) and 0.85–1 (linear)" in text and "at most 3.00 points, less than the 11.00" in text)
    close = ranking(_weighted(), None, None, WEIGHTS, STATS)  # totals 50 and 49: the IMU scores could swap them
    assert "decided by" not in headline(pd.DataFrame(), paper_rows(close, disc, WEIGHTS), close, "test data", 6)
