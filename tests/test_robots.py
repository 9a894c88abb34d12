"""The benchmark across robots: the list of robots (simpick.config.robots), the side-by-side table and
the agreement and pooling rules (simpick.score.robots) on small made-up tables, and the page."""

import math

import pandas as pd
import pytest
import yaml

from conftest import ROOT
from simpick.config.robots import robot_studies
from simpick.errors import InputError
from simpick.score.robots import agreement, klass, side_by_side
from simpick.score.verdict import METRICS


def answer(rows: dict) -> pd.DataFrame:
    """An answer.csv: engine -> {metric: (outcome, diff, low, high, margin)}; unnamed metrics not measurable."""
    out = []
    for engine, metrics in rows.items():
        row = {"engine": engine, "mechanics": "pass"}
        for m in METRICS:
            outcome, diff, low, high, margin = metrics.get(m, ("not measurable", *[float("nan")] * 4))
            row.update(
                {f"{m}_outcome": outcome, f"{m}_diff": diff, f"{m}_low": low, f"{m}_high": high, f"{m}_margin": margin}
            )
        out.append(row)
    return pd.DataFrame(out)


HUSKY = answer(
    {
        "mujoco": {"gain_error": ("best", 0.0, 0.0, 0.0, 0.05)},
        "ode": {"gain_error": ("equivalent", 0.01, -0.01, 0.03, 0.05)},
        "pybullet": {"gain_error": ("worse", 0.10, 0.06, 0.14, 0.05)},
        "dart": {"gain_error": ("undetermined", 0.03, -0.02, 0.09, 0.05)},
    }
)
WARTHOG = answer(
    {
        "mujoco": {"gain_error": ("equivalent", 0.02, 0.0, 0.04, 0.05), "speed_error": ("best", 0, 0, 0, 0.1)},
        "ode": {"gain_error": ("worse", 0.21, 0.15, 0.27, 0.05), "speed_error": ("worse", 0.3, 0.2, 0.4, 0.1)},
        "pybullet": {"gain_error": ("worse", 0.12, 0.08, 0.16, 0.05)},
        "dart": {"gain_error": ("best", 0.0, 0.0, 0.0, 0.05)},
    }
)


def table():
    side = side_by_side({"husky": HUSKY, "warthog": WARTHOG})
    return agreement(side, ["husky", "warthog"], {"husky": "Husky", "warthog": "Warthog"}).set_index(
        ["subject", "metric"]
    )


def test_each_engines_outcomes_sit_side_by_side_per_robot():
    side = side_by_side({"husky": HUSKY, "warthog": WARTHOG})
    assert len(side) == 2 * 4 * len(METRICS)
    ode = side[(side.subject == "ode") & (side.metric == "gain_error")].set_index("robot")
    assert ode.loc["husky", "outcome"] == "equivalent" and ode.loc["warthog", "outcome"] == "worse"
    assert ode.loc["warthog", "diff"] == pytest.approx(0.21) and ode.loc["warthog", "margin"] == pytest.approx(0.05)


def test_agreement_and_pooling():
    t = table()
    # best on one robot, equivalent on the other: the same class, pooled as good as the best on both
    assert t.loc[("mujoco", "gain_error"), "agreement"] == "agree"
    assert t.loc[("mujoco", "gain_error"), "pooled"] == "as good as the best on every robot"
    # worse on both: agree, pooled worse; the robots' differences to the best lie 0.02 apart
    assert t.loc[("pybullet", "gain_error"), "pooled"] == "worse on every robot"
    assert t.loc[("pybullet", "gain_error"), "gap"] == pytest.approx(0.02)
    # equivalent on the Husky, worse on the Warthog: differ, not pooled, and by how much
    ode = t.loc[("ode", "gain_error")]
    assert ode.agreement == "differ" and ode.pooled == "" and ode.pooled_reason == "the robots disagree"
    assert ode.gap == pytest.approx(0.20)
    assert "as good as the best on Husky, worse on Warthog" in ode.statement
    # undetermined on one robot: no disagreement, nothing pooled, the reason named
    dart = t.loc[("dart", "gain_error")]
    assert dart.agreement == "open" and dart.pooled == "" and dart.pooled_reason == "undetermined on Husky"
    # speed measured on the Warthog only: one robot, no pooled outcome, the Husky's reason given
    speed = t.loc[("ode", "speed_error")]
    assert speed.agreement == "one robot" and speed.pooled == ""
    assert speed.pooled_reason == "not measured on Husky (not measurable)"
    assert t.loc[("mujoco", "heading_error"), "agreement"] == "not measured"


def test_an_engine_missing_from_one_robots_study_is_not_pooled():
    side = side_by_side({"husky": HUSKY, "warthog": WARTHOG[WARTHOG.engine != "mujoco"]})
    row = agreement(side, ["husky", "warthog"]).set_index(["subject", "metric"]).loc[("mujoco", "gain_error")]
    assert row.agreement == "one robot" and row.pooled == ""
    assert row.pooled_reason == "not measured on warthog (not in its study)"


def test_one_robot_alone_pools_nothing():
    side = side_by_side({"husky": HUSKY})
    row = agreement(side, ["husky"]).set_index(["subject", "metric"]).loc[("pybullet", "gain_error")]
    assert row.pooled == "" and "pooling needs 2" in row.pooled_reason


def test_simulator_profiles_are_rows_of_their_own():
    sims = pd.DataFrame(
        [
            {"simulator": "gazebo", "variant": "shipped", "model": "gazebo-shipped", "engine": "ode",
             "mechanics": "fail", "gain_outcome": "worse", "gain_error": 0.4, "gain_error_low": 0.3,
             "gain_error_high": 0.5, "gain_diff_to_best": 0.2, "heading_outcome": "worse", "heading_error": 0.5,
             "speed_outcome": None},
            {"simulator": "webots", "variant": "tuned", "model": "", "engine": "ode", "mechanics": "",
             "status": "not run: not selected", "gain_outcome": None, "heading_outcome": None},
        ]
    )  # fmt: skip
    side = side_by_side({"husky": HUSKY, "warthog": WARTHOG}, {"husky": sims, "warthog": sims.iloc[0:0]})
    rows = side[side.kind == "simulator"]
    assert set(rows.subject) == {"gazebo (shipped)"} and set(rows.robot) == {"husky"}
    gain = rows[rows.metric == "gain_error"].iloc[0]
    assert gain["error"] == pytest.approx(0.4) and gain["diff"] == pytest.approx(0.2)
    assert rows[rows.metric == "speed_error"].iloc[0].outcome == "not measurable"
    row = agreement(side, ["husky", "warthog"]).set_index(["subject", "metric"]).loc[("gazebo (shipped)", "gain_error")]
    assert row.pooled_reason == "not measured on warthog (not in its study)"


def test_an_unknown_outcome_or_a_table_without_its_columns_is_refused():
    with pytest.raises(ValueError, match="unknown outcome 'great'"):
        klass("great")
    assert math.isnan(float("nan")) and klass(float("nan")) == "unmeasured"
    with pytest.raises(InputError, match=r"husky/answer.csv: lacks the column\(s\) \['gain_error_outcome'\]"):
        side_by_side({"husky": HUSKY.drop(columns="gain_error_outcome")}, where={"husky": "husky/answer.csv"})


# --- the list of robots ---


def project(tmp_path, files: dict) -> None:
    (tmp_path / "config.yaml").write_text(yaml.safe_dump({"seed": 1, "robot": {"label": "Husky", "track": 0.555}}))
    for name, data in files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(yaml.safe_dump(data))


def test_a_robots_config_is_config_yaml_then_its_files_then_its_settings(tmp_path):
    project(
        tmp_path, {"config/robots/w.yaml": {"robot": {"label": "Warthog", "track": 1.08}, "drive_replay": {"a": 1}}}
    )
    studies = robot_studies(
        {
            "husky": {"config": {"borealtc_dir": "../data"}},
            "warthog": {"configfiles": ["config/robots/w.yaml"], "config": {"drive_replay": {"every": 15}}},
        },
        tmp_path,
    )
    w = studies["warthog"]
    assert w.label == "Warthog" and w.config["robot"] == {"label": "Warthog", "track": 1.08}
    assert w.config["drive_replay"] == {"a": 1, "every": 15} and w.config["seed"] == 1
    assert w.command() == "snakemake --cores 2 --configfile config/robots/w.yaml --config drive_replay='{every: 15}'"
    assert studies["husky"].config["borealtc_dir"] == "../data" and studies["husky"].label == "Husky"
    assert robot_studies({"h": {"config": {"robot": None}}}, tmp_path)["h"].config["robot"] is None


@pytest.mark.parametrize(
    "robots, message",
    [
        (
            {"warthog": {"configfiles": ["config/robots/nope.yaml"]}},
            "config/robots.yaml, robots.warthog.configfiles[0]: config/robots/nope.yaml does not exist "
            "(fix: name a config file relative to the project's folder",
        ),
        ({"warthog": {"configfile": []}}, "robots.warthog: unknown field(s) ['configfile']"),
        ({"Warthog 2": {}}, "robots.Warthog 2: is not a usable robot name"),
        (
            {"warthog": {"configfiles": "config/robots/w.yaml"}},
            "robots.warthog.configfiles: is 'config/robots/w.yaml', ",
        ),
        ({}, "config/robots.yaml, robots: lists no robot"),
        (
            {"twice": {"configfiles": ["twice.yaml"]}},
            "robots.twice.configfiles[0]: twice.yaml, line 2: key 'seed' appears twice",
        ),
    ],
)
def test_a_bad_entry_is_refused_naming_file_field_and_fix(tmp_path, robots, message):
    project(tmp_path, {})
    (tmp_path / "twice.yaml").write_text("seed: 1\nseed: 2\n")
    with pytest.raises(InputError) as exc:
        robot_studies(robots, tmp_path)
    assert message in str(exc.value).replace(str(tmp_path) + "/", "")


# --- the page ---


def test_the_page_sets_the_robots_side_by_side(tmp_path):
    from simpick.report.robots import robots_job

    inputs = {"answers": [], "headlines": [], "simulators": []}
    for robot, frame, units in (("husky", HUSKY, "real runs"), ("warthog", WARTHOG, "DRIVE steps")):
        folder = tmp_path / robot
        folder.mkdir()
        frame.to_csv(folder / "answer.csv", index=False)
        (folder / "headline.yaml").write_text(
            yaml.safe_dump({"source_title": "data", "n_runs": 12, "units": units, "basis": "", "paragraph": "p."})
        )
        pd.DataFrame(columns=["simulator", "variant", "model", "engine", "mechanics"]).to_csv(
            folder / "table.csv", index=False
        )
        inputs["answers"].append(str(folder / "answer.csv"))
        inputs["headlines"].append(str(folder / "headline.yaml"))
        inputs["simulators"].append(str(folder / "table.csv"))
    params = {
        "robots": [
            {"name": "husky", "label": "Husky", "command": "snakemake --cores 2", "settings": {}},
            {"name": "warthog", "label": "Warthog", "command": "c", "settings": {"drive_replay.every": 15}},
        ],
        "pooling": {"min_robots": 2},
    }
    outputs = {k: str(tmp_path / f"out.{k}") for k in ("table", "agreement", "html", "pdf")}
    robots_job(inputs, params, outputs)
    html = (tmp_path / "out.html").read_text()
    assert (
        "gain error: the robots agree on mujoco, pybullet; they differ on ode; undetermined on at least one robot "
        "for dart" in html
    )
    assert "Pooled: as good as the best on every robot: mujoco; worse on every robot: pybullet" in html
    assert "drive_replay.every=15" in html and "No simulator profile ran in the study of Husky, Warthog" in html
    assert (tmp_path / "out.pdf").read_bytes()[:4] == b"%PDF"
    agree = pd.read_csv(tmp_path / "out.agreement")
    assert len(agree) == 4 * len(METRICS)


def test_the_benchmark_config_is_checked_whole_pooling_included():
    """config/robots.yaml as shipped reads; a stray top-level key or a pooling below two robots is refused,
    naming the file and the key."""
    import yaml

    from simpick.config.robots import benchmark

    shipped = yaml.safe_load((ROOT / "config/robots.yaml").read_text())
    robots, pooling = benchmark(shipped, ROOT)
    assert set(robots) == {"husky", "warthog"} and pooling == {"min_robots": 2}
    with pytest.raises(InputError, match=r"config/robots.yaml, pool: is not a setting"):
        benchmark({**shipped, "pool": {}}, ROOT)
    with pytest.raises(InputError, match=r"pooling.min_robots"):
        benchmark({**shipped, "pooling": {"min_robots": 1}}, ROOT)
