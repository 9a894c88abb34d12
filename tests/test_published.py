"""The paper's published figures (farley2022.yaml) against simpick's arithmetic."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest

from simpick.compare.metrics import axis_errors
from simpick.inputs.published import DEFAULT_PATH, load_published
from simpick.score.published import recompute_table11, table11_comparison, worked_example, write_outputs
from simpick.score.scoring import DEFAULT_WEIGHTS, METRICS, qualitative_scores

SIMS = ["CoppeliaSim", "Gazebo", "MORSE", "Webots"]


@pytest.fixture(scope="module")
def pub() -> dict:
    return load_published(DEFAULT_PATH)


@pytest.fixture(scope="module")
def t11(pub: dict) -> pd.DataFrame:
    return recompute_table11(pub)


def test_yaml_blocks_carry_sources(pub: dict) -> None:
    assert pub["simulators"] == SIMS
    for key in ("table3", "table4", "table10", "table11", "worked_example"):
        assert "Table" in pub[key]["source"]
    for key in ("table6", "table7", "table8", "table9", "text_totals"):
        assert pub["worked_example"][key]["source"]


def test_paper_weights_are_the_defaults(pub: dict) -> None:
    assert {k: float(v) for k, v in pub["table11"]["weights"].items()} == DEFAULT_WEIGHTS
    assert pub["table11"]["weight_total"] == 56


@pytest.mark.parametrize("sim", SIMS)
def test_table3_facts_give_table4_scores(pub: dict, sim: str) -> None:
    assert qualitative_scores(pub["table3"]["facts"][sim]) == pub["table4"]["scores"][sim]


@pytest.mark.parametrize("sim", SIMS)
def test_table11_qualitative_scores_equal_table4(pub: dict, sim: str) -> None:
    t4 = pub["table4"]["scores"][sim]
    assert {k: pub["table11"]["scores"][sim][k] for k in t4} == t4


def test_table11_shape(t11: pd.DataFrame) -> None:
    assert list(t11.index) == SIMS
    assert t11.index.name == "simulator"
    assert list(t11.columns) == [*METRICS, "total", "total_from_published_scores", "published_total"]


@pytest.mark.parametrize(("sim", "expected"), [("CoppeliaSim", 49.100), ("Gazebo", 49.087), ("Webots", 44.226)])
def test_totals_from_published_scores(t11: pd.DataFrame, sim: str, expected: float) -> None:
    assert t11.loc[sim, "total_from_published_scores"] == pytest.approx(expected, abs=5e-4)
    assert t11.loc[sim, "published_total"] == expected


def test_morse_printed_total_does_not_follow_its_printed_scores(t11: pd.DataFrame) -> None:
    # Weights x Table 11's MORSE scores = 32.145; the table prints 32.148.
    assert t11.loc["MORSE", "total_from_published_scores"] == pytest.approx(32.145, abs=5e-4)
    assert t11.loc["MORSE", "published_total"] == 32.148


def test_morse_printed_total_matches_exact_thirds(pub: dict) -> None:
    # The 0.003 gap is what exact 1/3 for languages (w 3) and UI (w 6) gives.
    scores = dict(pub["table11"]["scores"]["MORSE"], languages=1 / 3, ui=1 / 3)
    total = sum(DEFAULT_WEIGHTS[m] * scores[m] for m in METRICS)
    assert total == pytest.approx(32.148, abs=5e-4)


@pytest.mark.parametrize("metric", ["cpu_average", "cpu_intense", "real_time_factor"])
def test_cpu_and_rtf_scores_reproduce(pub: dict, t11: pd.DataFrame, metric: str) -> None:
    for sim in SIMS:
        assert t11.loc[sim, metric] == pytest.approx(pub["table11"]["scores"][sim][metric], abs=1e-3), sim


def test_qualitative_scores_reproduce_exactly(pub: dict, t11: pd.DataFrame) -> None:
    for sim in SIMS:
        for metric in METRICS[:7]:
            assert t11.loc[sim, metric] == pub["table11"]["scores"][sim][metric]


def test_imu_scores_do_not_follow_eq8(t11: pd.DataFrame) -> None:
    assert t11.loc["MORSE", "imu_angular"] == pytest.approx(18.76 / 24.42, abs=1e-12)
    assert t11.loc["MORSE", "imu_angular"] == pytest.approx(0.768, abs=1e-3)
    assert abs(t11.loc["MORSE", "imu_angular"] - 0.792) > 0.02
    assert t11.loc["Gazebo", "imu_angular"] == 1.0
    assert t11.loc["CoppeliaSim", "imu_linear"] == 1.0


def test_comparison_long_form(pub: dict) -> None:
    comp = table11_comparison(pub)
    assert list(comp.columns) == ["simulator", "metric", "published", "recomputed", "difference", "matches"]
    assert len(comp) == len(SIMS) * len(METRICS)
    row = comp[(comp.simulator == "MORSE") & (comp.metric == "imu_angular")].iloc[0]
    assert row.published == 0.792
    assert row.recomputed == pytest.approx(0.768, abs=1e-3)
    assert row.difference == pytest.approx(row.recomputed - row.published)
    assert not row.matches
    mismatched = set(map(tuple, comp.loc[~comp.matches, ["simulator", "metric"]].values))
    # Every mismatch is an IMU score; the rest of Table 11 reproduces.
    assert mismatched and all(m in ("imu_angular", "imu_linear") for _, m in mismatched)
    assert ("Gazebo", "imu_angular") not in mismatched
    assert ("CoppeliaSim", "imu_linear") not in mismatched


def test_recomputed_totals(t11: pd.DataFrame) -> None:
    # Eq. 8 applied to Table 10 moves Gazebo ahead of CoppeliaSim.
    assert t11.loc["Gazebo", "total"] > t11.loc["CoppeliaSim", "total"]
    assert t11.loc["CoppeliaSim", "total"] == pytest.approx(49.094, abs=5e-4)
    assert t11.loc["Gazebo", "total"] == pytest.approx(49.224, abs=5e-4)


def test_axis_errors() -> None:
    e = axis_errors({"x": {"range": 1.0, "mean": -0.5}}, {"x": {"range": 3.0, "mean": 0.5}})
    assert e == {"x": {"range_error": 2.0, "mean_error": 1.0, "total_error": 3.0}}
    with pytest.raises(ValueError):
        axis_errors({"x": {"range": 1, "mean": 0}}, {"y": {"range": 1, "mean": 0}})


def test_worked_example_angular(pub: dict) -> None:
    ang = worked_example(pub)["angular"]
    assert ang["total_from_inputs"] == pytest.approx(1.237, abs=1e-9)
    assert ang["printed_rows_sum"] == pytest.approx(1.237, abs=1e-9)
    assert ang["text_total"] == 1.237
    for axis in "xyz":
        for k, v in ang["axes"][axis].items():
            assert v == pytest.approx(ang["printed_axes"][axis][k], abs=1e-9)


def test_worked_example_linear(pub: dict) -> None:
    lin = worked_example(pub)["linear"]
    assert lin["total_from_inputs"] == pytest.approx(23.43, abs=1e-9)
    assert lin["printed_rows_sum"] == pytest.approx(23.39, abs=1e-9)
    assert lin["text_total"] == 23.19
    assert lin["axes"]["x"]["mean_error"] == pytest.approx(0.20, abs=1e-9)
    assert lin["printed_axes"]["x"]["mean_error"] == 0.16


def test_worked_example_declares_frame(pub: dict) -> None:
    frame = worked_example(pub)["sensor_frame"]
    assert frame["axes"] == {"x": "forward", "y": "right", "z": "down"}
    assert frame["assumption"] is True
    assert frame["rotation_matrix"] == [[1, 0, 0], [0, -1, 0], [0, 0, -1]]
    assert pub["worked_example"]["table7"]["real"]["z"]["mean"] < 0


def test_write_outputs(pub: dict, tmp_path: Path) -> None:
    paths = write_outputs(pub, tmp_path / "out")
    t11 = pd.read_csv(paths["table11"], index_col="simulator")
    assert list(t11.index) == SIMS
    assert t11.loc["Gazebo", "published_total"] == 49.087
    comp = pd.read_csv(paths["table11_comparison"])
    assert len(comp) == 48
    ex = json.loads(paths["worked_example"].read_text())
    assert ex["linear"]["text_total"] == 23.19


def test_load_rejects_incomplete_yaml(tmp_path: Path) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text("simulators: [A]\n")
    with pytest.raises(ValueError, match="table3"):
        load_published(bad)
