"""Scoring rules of Farley et al. (2022) section 3.2-4, on hand-computed cases."""

from __future__ import annotations

import math
from pathlib import Path

import pandas as pd
import pytest

from simpick.score import scoring as sc


def test_metric_tables_are_consistent() -> None:
    assert len(sc.METRICS) == 12 and len(set(sc.METRICS)) == 12
    assert set(sc.METRIC_LABELS) == set(sc.METRICS)
    assert set(sc.DEFAULT_WEIGHTS) == set(sc.METRICS)
    assert sum(sc.DEFAULT_WEIGHTS.values()) == 56
    assert sc.DEFAULT_WEIGHTS["imu_angular"] == 10 and sc.DEFAULT_WEIGHTS["ros"] == 6
    assert sc.METRIC_LABELS["imu_angular"] == "IMU angular velocity accuracy"


# ----------------------------------------------------------------- qualitative


def test_bool_scores() -> None:
    assert sc.score_bool(True) == 1.0
    assert sc.score_bool(False) == 0.0
    with pytest.raises(ValueError):
        sc.score_bool("yes")  # type: ignore[arg-type]


@pytest.mark.parametrize(("support", "expected"), [("out_of_the_box", 1.0), ("official_plugin", 0.8), ("none", 0.0)])
def test_ros(support: str, expected: float) -> None:
    assert sc.score_ros(support) == expected


def test_ros_rejects_unknown_level() -> None:
    with pytest.raises(ValueError, match="ROS support"):
        sc.score_ros("plugin")


@pytest.mark.parametrize(
    ("languages", "expected"),
    [
        (["C/C++", "Python", "MATLAB", "Java"], 1.0),
        (["c++", "python", "matlab", "lua"], 1.0),  # case-insensitive, C++ counts as C/C++
        (["C", "Python", "MATLAB", "Octave"], 1.0),
        (["C/C++", "Python", "MATLAB"], 0.667),  # "and more" is a condition
        (["C/C++", "Python"], 0.667),
        (["C/C++", "Python", "Java"], 0.667),
        (["Python", "MATLAB", "Java"], 0.333),  # no C/C++
        (["C/C++"], 0.333),
        (["Python"], 0.333),
        (["Lua", "MATLAB"], 0.0),
        ([], 0.0),
    ],
)
def test_languages(languages: list[str], expected: float) -> None:
    assert sc.score_languages(languages) == expected


def test_languages_rejects_a_bare_string() -> None:
    with pytest.raises(ValueError):
        sc.score_languages("Python")


@pytest.mark.parametrize(
    ("level", "expected"), [("full", 1.0), ("partial", 0.667), ("visualization", 0.333), ("none", 0.0)]
)
def test_ui(level: str, expected: float) -> None:
    assert sc.score_ui(level) == expected


def test_ui_rejects_unknown_level() -> None:
    with pytest.raises(ValueError, match="UI level"):
        sc.score_ui("good")


@pytest.mark.parametrize(
    ("formats", "plugin", "expected"),
    [
        (["URDF", "SDF", "STL"], False, 1.0),
        (["urdf", "sdf", "collada"], True, 1.0),
        (["URDF", "SDF"], False, 0.5),  # no "more"
        (["URDF", "STL"], False, 0.5),
        (["SDF"], True, 0.5),  # native beats the plugin
        (["Proto Nodes"], True, 0.25),
        (["Proto Nodes"], False, 0.0),
        ([], False, 0.0),
    ],
)
def test_model_formats(formats: list[str], plugin: bool, expected: float) -> None:
    assert sc.score_model_formats(formats, plugin) == expected


@pytest.mark.parametrize(
    ("engines", "expected"),
    [(["Bullet", "ODE"], 1.0), (["ODE"], 0.0), (["ODE", "ode"], 0.0), ([], 0.0)],
)
def test_physics_engines(engines: list[str], expected: float) -> None:
    assert sc.score_physics_engines(engines) == expected


def test_qualitative_scores_record() -> None:
    facts = {
        "free": True,
        "open_source": False,
        "ros": "official_plugin",
        "languages": ["C/C++", "Python"],
        "ui": "partial",
        "model_formats": ["URDF"],
        "urdf_sdf_via_manual_plugin": False,
        "physics_engines": ["ODE", "Bullet"],
        "note": "ignored",
    }
    assert sc.qualitative_scores(facts) == {
        "free": 1.0,
        "open_source": 0.0,
        "ros": 0.8,
        "languages": 0.667,
        "ui": 0.667,
        "model_formats": 0.5,
        "physics_engines": 1.0,
    }
    del facts["ui"]
    with pytest.raises(ValueError, match="ui"):
        sc.qualitative_scores(facts)


# ---------------------------------------------------------------- quantitative


def test_real_time_factor_is_r_over_max() -> None:
    s = sc.real_time_factor_scores({"a": 0.5, "b": 1.0, "c": 2.0})
    assert s == pytest.approx({"a": 0.25, "b": 0.5, "c": 1.0})


def test_efficiency_and_accuracy_are_min_over_value() -> None:
    assert sc.efficiency_scores({"a": 10, "b": 20, "c": 40}) == pytest.approx({"a": 1.0, "b": 0.5, "c": 0.25})
    assert sc.accuracy_scores({"a": 3.0, "b": 1.5}) == pytest.approx({"a": 0.5, "b": 1.0})


def test_accuracy_zero_errors() -> None:
    assert sc.accuracy_scores({"a": 0.0, "b": 0.0}) == {"a": 1.0, "b": 1.0}
    assert sc.accuracy_scores({"a": 0.0, "b": 2.0, "c": 5.0}) == {"a": 1.0, "b": 0.0, "c": 0.0}
    assert sc.efficiency_scores({"a": 0, "b": 3}) == {"a": 1.0, "b": 0.0}


def test_real_time_factor_zeros() -> None:
    assert sc.real_time_factor_scores({"a": 0.0, "b": 0.0}) == {"a": 1.0, "b": 1.0}
    assert sc.real_time_factor_scores({"a": 0.0, "b": 2.0}) == {"a": 0.0, "b": 1.0}


def test_missing_values_are_excluded() -> None:
    s = sc.accuracy_scores({"a": 2.0, "b": float("nan"), "c": None, "d": 4.0})
    assert s["a"] == 1.0 and s["d"] == 0.5
    assert math.isnan(s["b"]) and math.isnan(s["c"])
    r = sc.real_time_factor_scores({"a": float("nan"), "b": 0.5})
    assert math.isnan(r["a"]) and r["b"] == 1.0
    all_nan = sc.efficiency_scores({"a": None, "b": float("nan")})
    assert all(math.isnan(v) for v in all_nan.values())


@pytest.mark.parametrize("fn", [sc.real_time_factor_scores, sc.efficiency_scores, sc.accuracy_scores])
def test_negative_and_infinite_inputs_raise(fn) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ValueError, match="negative"):
        fn({"a": 1.0, "b": -0.1})
    with pytest.raises(ValueError, match="infinite"):
        fn({"a": 1.0, "b": float("inf")})


def test_empty_input_gives_empty_scores() -> None:
    assert sc.accuracy_scores({}) == {}


# ---------------------------------------------------------------- weighted table


def _scores(**rows: dict[str, float]) -> pd.DataFrame:
    df = pd.DataFrame.from_dict(rows, orient="index")[list(sc.METRICS)]
    df.index.name = "subject"
    return df


def test_weighted_table_totals_and_order() -> None:
    ones = {m: 1.0 for m in sc.METRICS}
    half = {m: 0.5 for m in sc.METRICS}
    out = sc.weighted_table(_scores(low=half, high=ones), sc.DEFAULT_WEIGHTS)
    assert list(out.index) == ["high", "low"]
    assert out.loc["high", "total"] == pytest.approx(56.0)
    assert out.loc["low", "total"] == pytest.approx(28.0)
    assert list(out["rank"]) == [1, 2]
    assert list(out["excluded"]) == ["", ""]
    assert out.index.name == "subject"
    assert all(m in out.columns for m in sc.METRICS)


def test_weighted_table_nan_counts_zero_and_is_listed() -> None:
    row = {m: 1.0 for m in sc.METRICS}
    row["imu_angular"] = float("nan")
    row["cpu_average"] = float("nan")
    out = sc.weighted_table(_scores(a=row), sc.DEFAULT_WEIGHTS)
    assert out.loc["a", "total"] == pytest.approx(56.0 - 10.0 - 2.0)
    assert out.loc["a", "excluded"] == "cpu_average,imu_angular"


def test_weighted_table_ties_share_rank() -> None:
    ones = {m: 1.0 for m in sc.METRICS}
    out = sc.weighted_table(_scores(a=ones, b=ones), sc.DEFAULT_WEIGHTS)
    assert list(out["rank"]) == [1, 1]


def test_weighted_table_missing_weight_raises() -> None:
    weights = dict(sc.DEFAULT_WEIGHTS)
    del weights["imu_linear"]
    with pytest.raises(ValueError, match="imu_linear"):
        sc.weighted_table(_scores(a={m: 1.0 for m in sc.METRICS}), weights)


def test_weighted_table_missing_column_raises() -> None:
    df = _scores(a={m: 1.0 for m in sc.METRICS}).drop(columns="ros")
    with pytest.raises(ValueError, match="ros"):
        sc.weighted_table(df, sc.DEFAULT_WEIGHTS)


def test_scores_job_against_hand_computed_values(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """The scores rule's job: facts, Eq. 7 totals, real-time factors and CPU loads in, the
    weighted table out, every figure computed by hand."""
    import json

    import yaml

    from simpick.score.jobs import scores_job

    facts = {
        "a": {
            "free": True,
            "open_source": True,
            "ros": "none",
            "languages": ["Python"],
            "ui": "none",
            "model_formats": ["URDF"],
            "urdf_sdf_via_manual_plugin": False,
            "physics_engines": ["one"],
        },
        "b": {
            "free": False,
            "open_source": False,
            "ros": "out_of_the_box",
            "languages": ["C++", "Python"],
            "ui": "full",
            "model_formats": ["URDF", "SDF", "MJCF"],
            "urdf_sdf_via_manual_plugin": False,
            "physics_engines": ["one", "two"],
        },
    }
    (tmp_path / "facts.yaml").write_text(yaml.safe_dump(facts))
    pd.DataFrame(
        {"engine": ["a", "a", "b", "b"], "quantity": ["angular", "linear"] * 2, "error": [0.55, 3.61, 0.5, 3.61]}
    ).to_csv(tmp_path / "errors.csv", index=False)
    pd.DataFrame({"engine": ["a", "b"], "real_time_factor": [10.0, 40.0]}).to_csv(tmp_path / "rtf.csv", index=False)
    cpu = []
    for engine, average, intense in (("a", 50.0, 200.0), ("b", 100.0, 100.0)):
        cpu.append(tmp_path / f"{engine}.json")
        cpu[-1].write_text(
            json.dumps({"engine": engine, "average": {"load_percent": average}, "intense": {"load_percent": intense}})
        )
    outputs = {k: str(tmp_path / f"{k}.csv") for k in ("scores", "weighted", "contributions", "drivers")}
    scores_job(
        ["a", "b"],
        str(tmp_path / "errors.csv"),
        str(tmp_path / "rtf.csv"),
        [str(p) for p in cpu],
        str(tmp_path / "facts.yaml"),
        dict(sc.DEFAULT_WEIGHTS),
        outputs,
    )

    weighted = pd.read_csv(outputs["weighted"], index_col="engine")
    a, b = weighted.loc["a"], weighted.loc["b"]
    assert (a.languages, a.model_formats, a.ros, a.physics_engines) == (0.333, 0.5, 0.0, 0.0)
    assert (b.languages, b.model_formats, b.ui, b.physics_engines) == (0.667, 1.0, 1.0, 1.0)
    assert (a.real_time_factor, b.real_time_factor) == (0.25, 1.0)  # R / max R
    assert (a.cpu_average, b.cpu_average, a.cpu_intense, b.cpu_intense) == (1.0, 0.5, 0.5, 1.0)  # min L / L
    assert a.imu_angular == pytest.approx(0.5 / 0.55, abs=1e-6) and b.imu_angular == 1.0  # min E / E
    assert a.imu_linear == b.imu_linear == 1.0
    # a: 4 + 2 + 3 x 0.333 + 4 x 0.5 + 4 x 0.25 + 2 x 1 + 2 x 0.5 + 10 x 0.5/0.55 + 10
    assert a.total == pytest.approx(4 + 2 + 0.999 + 2 + 1 + 2 + 1 + 10 * 0.5 / 0.55 + 10, abs=1e-5)
    # b: 6 + 3 x 0.667 + 6 + 4 + 3 + 4 + 2 x 0.5 + 2 + 10 + 10
    assert b.total == pytest.approx(6 + 2.001 + 6 + 4 + 3 + 4 + 1 + 2 + 20, abs=1e-5)
    assert list(weighted.index) == ["b", "a"] and (b["rank"], a["rank"]) == (1, 2)
    # written at full precision: the exact score, not 6 significant figures
    assert a.imu_angular == 0.5 / 0.55

    # the total taken apart: weight x score per metric, summing to the total; the leader's lead per metric
    parts = pd.read_csv(outputs["contributions"])
    assert len(parts) == 2 * len(sc.METRICS)
    for engine, g in parts.groupby("engine"):
        assert g.points.sum() == pytest.approx(weighted.loc[engine, "total"], abs=1e-12)
        assert g["share"].iloc[0] == pytest.approx(weighted.loc[engine, "total"] / 56)
    a_ros = parts[(parts.engine == "a") & (parts.metric == "ros")].iloc[0]
    assert (a_ros.weight, a_ros.score, a_ros.points, a_ros.label) == (6.0, 0.0, 0.0, "ROS integration")
    drivers = pd.read_csv(outputs["drivers"])
    assert set(drivers.engine) == {"a"} and (drivers.leader == "b").all()
    assert drivers.difference.sum() == pytest.approx(b.total - a.total, abs=1e-12) == drivers.gap.iloc[0]
    first = drivers.sort_values("order").iloc[0]  # ROS: 6 points to b, none to a, the largest lead
    assert (first.metric, first.difference, first.order) == ("ros", 6.0, 1)
    assert drivers.sort_values("order").difference.is_monotonic_decreasing


def test_a_failed_cpu_run_is_not_scored(tmp_path) -> None:  # type: ignore[no-untyped-def]
    import json

    import yaml

    from simpick.score.jobs import scores_job

    fact = {
        "free": True,
        "open_source": True,
        "ros": "none",
        "languages": ["Python"],
        "ui": "none",
        "model_formats": ["URDF"],
        "urdf_sdf_via_manual_plugin": False,
        "physics_engines": ["one"],
    }
    (tmp_path / "facts.yaml").write_text(yaml.safe_dump({"a": fact, "b": fact}))
    pd.DataFrame(
        {"engine": ["a", "a", "b", "b"], "quantity": ["angular", "linear"] * 2, "error": [1.0, 1.0, 1.0, 1.0]}
    ).to_csv(tmp_path / "errors.csv", index=False)
    pd.DataFrame({"engine": ["a", "b"], "real_time_factor": [1.0, 1.0]}).to_csv(tmp_path / "rtf.csv", index=False)
    cpu = []
    for engine, load, status in (("a", 50.0, "ok"), ("b", 10.0, "failed")):  # b fell through: cheap, not good
        cpu.append(str(tmp_path / f"{engine}.json"))
        Path(cpu[-1]).write_text(
            json.dumps(
                {
                    "engine": engine,
                    "average": {"load_percent": load},
                    "intense": {"load_percent": load},
                    "health": {"status": status, "reasons": ["fell through"]},
                }
            )
        )
    outputs = {"scores": str(tmp_path / "scores.csv"), "weighted": str(tmp_path / "weighted.csv")}
    scores_job(
        ["a", "b"],
        str(tmp_path / "errors.csv"),
        str(tmp_path / "rtf.csv"),
        cpu,
        str(tmp_path / "facts.yaml"),
        dict(sc.DEFAULT_WEIGHTS),
        outputs,
    )
    weighted = pd.read_csv(outputs["weighted"], index_col="engine")
    assert weighted.loc["a", "cpu_average"] == 1.0 and math.isnan(weighted.loc["b", "cpu_average"])
    assert weighted.loc["b", "excluded"] == "cpu_average,cpu_intense"


def test_scores_job_records_what_the_scores_rest_on(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """provenance.yaml: the errors file, its tests, each test left out with the failure that left
    it out, the same for the real-time factor, and the CPU runs scored and not."""
    import json

    import yaml

    from simpick.score.jobs import scores_job

    fact = {
        "free": True,
        "open_source": True,
        "ros": "none",
        "languages": ["Python"],
        "ui": "none",
        "model_formats": ["URDF"],
        "urdf_sdf_via_manual_plugin": False,
        "physics_engines": ["one"],
    }
    (tmp_path / "facts.yaml").write_text(yaml.safe_dump({"a": fact, "b": fact}))
    pd.DataFrame(
        {
            "engine": ["a", "a", "b", "b", "kinematic", "kinematic"],
            "quantity": ["angular", "linear"] * 3,
            "error": [1.0] * 6,
            "tests": ["ice-1;snow-2"] * 6,
            "excluded": ["ice-3"] * 6,
        }
    ).to_csv(tmp_path / "errors.csv", index=False)
    pd.DataFrame(
        {
            "engine": ["a", "b", "kinematic"],
            "segment": ["ice-3"] * 3,
            "status": ["ok", "failed", "ok"],
            "reasons": ["", "diverged", ""],
        }
    ).to_csv(tmp_path / "per_test.csv", index=False)
    pd.DataFrame(
        {
            "engine": ["a", "b"],
            "terrain": ["bumps", "bumps"],
            "motion": ["circle"] * 2,
            "status": ["failed", "ok"],
            "reasons": ["fell through", ""],
        }
    ).to_csv(tmp_path / "runs.csv", index=False)
    pd.DataFrame(
        {
            "engine": ["a", "b"],
            "real_time_factor": [1.0, 2.0],
            "tests": ["grass/straight"] * 2,
            "excluded": ["bumps/circle"] * 2,
        }
    ).to_csv(tmp_path / "rtf.csv", index=False)
    cpu = []
    for engine, status in (("a", "ok"), ("b", "failed")):
        cpu.append(str(tmp_path / f"{engine}.json"))
        Path(cpu[-1]).write_text(
            json.dumps(
                {
                    "engine": engine,
                    "average": {"load_percent": 10.0},
                    "intense": {"load_percent": 10.0},
                    "health": {"status": status, "reasons": ["jumped"]},
                }
            )
        )
    outputs = {
        k: str(tmp_path / f"{k}.{'yaml' if k == 'provenance' else 'csv'}") for k in ("scores", "weighted", "provenance")
    }
    accuracy = {"reference": "real", "set": "segments", "dataset": "borealtc"}
    scores_job(
        ["a", "b"],
        str(tmp_path / "errors.csv"),
        str(tmp_path / "rtf.csv"),
        cpu,
        str(tmp_path / "facts.yaml"),
        dict(sc.DEFAULT_WEIGHTS),
        outputs,
        {
            "accuracy": accuracy,
            "accuracy_tests": str(tmp_path / "per_test.csv"),
            "runs": str(tmp_path / "runs.csv"),
            "cpu_test": "grass/straight",
        },
    )
    record = yaml.safe_load(Path(outputs["provenance"]).read_text())
    acc = record["accuracy"]
    assert {k: acc[k] for k in accuracy} == accuracy and acc["errors_file"] == str(tmp_path / "errors.csv")
    assert acc["engines"] == ["a", "b"] and acc["tests"] == ["ice-1", "snow-2"]
    assert acc["excluded"] == [{"test": "ice-3", "why": "b failed: diverged"}]
    assert record["real_time_factor"]["tests"] == ["grass/straight"]
    assert record["real_time_factor"]["excluded"] == [{"test": "bumps/circle", "why": "a failed: fell through"}]
    assert record["cpu"]["engines"] == ["a"] and record["cpu"]["test"] == "grass/straight"
    assert record["cpu"]["excluded"] == [{"engine": "b", "why": "jumped"}]
