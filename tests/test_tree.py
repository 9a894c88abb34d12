"""The decision tree from the study's tables (simpick.score.tree): its questions, leaves and
evidence on a small made-up study, and that another study's tables give another tree."""

import json
import math

import pandas as pd
import pytest
import yaml

from simpick.errors import InputError
from simpick.score import scoring
from simpick.score.tree import build_tree, decision_tree_job, leaf_order, read_tree, study_questions, walk
from simpick.tables import write_csv

# Made-up engines, so that nothing in the tree's logic can lean on a real engine's name.
FACTS = {
    "anvil": {
        "free": True,
        "open_source": True,
        "ros": "none",
        "rtf": 300.0,
        "cpu": 40.0,
        "fails": 0,
        "gain": ("best", 0.20),
    },
    "breeze": {
        "free": True,
        "open_source": True,
        "ros": "official_plugin",
        "rtf": 930.0,
        "cpu": 15.0,
        "fails": 0,
        "gain": ("equivalent", 0.21),
    },
    "comet": {
        "free": True,
        "open_source": True,
        "ros": "out_of_the_box",
        "rtf": 55.0,
        "cpu": 150.0,
        "fails": 3,
        "gain": ("equivalent", 0.19),
    },
    "dune": {
        "free": True,
        "open_source": False,
        "ros": "out_of_the_box",
        "rtf": 2100.0,
        "cpu": 5.0,
        "fails": 0,
        "gain": ("worse", 0.35),
    },
    "ember": {
        "free": True,
        "open_source": True,
        "ros": "none",
        "rtf": 120.0,
        "cpu": 60.0,
        "fails": 0,
        "gain": ("undetermined", 0.24),
    },
}

WEIGHTS = dict(scoring.DEFAULT_WEIGHTS)


def make_study(folder, facts=None, weights=None, outcomes=True) -> dict:
    """The tables the decision tree and the page read, for ``facts`` (engine -> the figures of
    FACTS), written as the study's rules write them; returns the inputs and output paths."""
    facts = facts or FACTS
    folder.mkdir(parents=True, exist_ok=True)
    qualitative = {
        e: {
            "free": f["free"],
            "open_source": f["open_source"],
            "ros": f["ros"],
            "languages": ["C/C++", "Python"],
            "ui": "partial",
            "model_formats": ["URDF", "SDF", "MJCF"],
            "urdf_sdf_via_manual_plugin": False,
            "physics_engines": [e],
            "sources": {"open_source": f"https://example.org/{e}", "ros": f"https://example.org/{e}/ros"},
        }
        for e, f in facts.items()
    }
    (folder / "qualitative.yaml").write_text(yaml.safe_dump(qualitative))
    rows = []
    for e, f in facts.items():
        for i in range(5):
            rows.append(
                {
                    "engine": e,
                    "case": f"turn_{i}",
                    "kind": "yaw_gain",
                    "quantity": "yaw_rate_gain",
                    "passed": i >= f["fails"],
                    "status": "ok",
                }
            )
        rows.append(
            {"engine": e, "case": "slide", "kind": "slide", "quantity": "deceleration", "passed": True, "status": "ok"}
        )
        rows.append(
            {
                "engine": e,
                "case": "incline",
                "kind": "incline",
                "quantity": "slide_acceleration",
                "passed": False,
                "status": "skipped",
            }
        )
    write_csv(pd.DataFrame(rows), folder / "validation_summary.csv")
    write_csv(
        pd.DataFrame(
            [
                {
                    "engine": e,
                    "sim_time": 40.0,
                    "wall_time": 40.0 / f["rtf"],
                    "real_time_factor": f["rtf"],
                    "n_runs": 6,
                    "tests": "",
                    "excluded": "",
                }
                for e, f in facts.items()
            ]
        ),
        folder / "rtf.csv",
    )
    cpu = []
    for e, f in facts.items():
        path = folder / f"cpu_{e}.json"
        path.write_text(
            json.dumps(
                {
                    "engine": e,
                    "average": {"robots": 1, "load_percent": f["cpu"] / 5},
                    "intense": {"robots": 5, "load_percent": f["cpu"]},
                    "health": {"status": "ok", "reasons": []},
                }
            )
        )
        cpu.append(str(path))
    inputs = {
        "qualitative": str(folder / "qualitative.yaml"),
        "validation": str(folder / "validation_summary.csv"),
        "rtf": str(folder / "rtf.csv"),
        "cpu": cpu,
    }
    if outcomes:
        best = min((f["gain"][1], e) for e, f in facts.items() if f["gain"][0] == "best")[1]
        rows = []
        for e, f in facts.items():
            outcome, mean = f["gain"]
            diff = mean - facts[best]["gain"][1]
            rows.append(
                {
                    "metric": "gain_error",
                    "label": "Yaw-rate gain error",
                    "unit": "1",
                    "engine": e,
                    "n_runs": 9,
                    "mean": mean,
                    "low": mean - 0.01,
                    "high": mean + 0.01,
                    "best": best,
                    "is_best": e == best,
                    "diff_to_best": diff,
                    "diff_low": diff - 0.004,
                    "diff_high": diff + 0.004,
                    "margin": 0.02,
                    "margin_basis": "the real robot's run-to-run spread",
                    "p_worse": 0.5,
                    "p_equivalent": 0.01,
                    "outcome": outcome,
                    "runs_needed": 40 if outcome == "undetermined" else math.nan,
                    "mechanics": "fail" if f["fails"] else "pass",
                    "mechanics_failed": f["fails"],
                    "mechanics_note": "",
                    "recommendable": not f["fails"],
                }
            )
        pd.DataFrame(rows).to_csv(folder / "outcomes.csv", index=False, float_format="%.17g")
        inputs["outcomes"] = str(folder / "outcomes.csv")
        write_csv(
            pd.DataFrame(
                [
                    {
                        "engine": e,
                        "mechanics": "fail" if f["fails"] else "pass",
                        "mechanics_failed": f["fails"],
                        "mechanics_cases": 6,
                        "mechanics_note": f"fails {f['fails']} of 6 analytic cases: yaw gain ({f['fails']})"
                        if f["fails"]
                        else "passes all 6 analytic cases",
                    }
                    for e, f in facts.items()
                ]
            ),
            folder / "mechanics.csv",
        )
        inputs["mechanics"] = str(folder / "mechanics.csv")
    scores = pd.DataFrame({e: {m: 0.5 for m in scoring.METRICS} for e in facts}).T
    for e, f in facts.items():
        scores.loc[e, "open_source"] = float(f["open_source"])
        scores.loc[e, "ros"] = scoring.ROS_SCORES[f["ros"]]
        scores.loc[e, "real_time_factor"] = f["rtf"] / max(g["rtf"] for g in facts.values())
        scores.loc[e, "imu_angular"] = min(g["gain"][1] for g in facts.values()) / f["gain"][1]
    scores.loc[next(iter(facts)), "cpu_intense"] = math.nan  # one score not measured: counts as 0
    scores.index.name = "engine"
    write_csv(scoring.weighted_table(scores, weights or WEIGHTS), folder / "weighted.csv", index=True)
    return {"inputs": inputs, "tree": str(folder / "tree.json"), "weighted": str(folder / "weighted.csv")}


@pytest.fixture
def study(tmp_path):
    paths = make_study(tmp_path)
    decision_tree_job(list(FACTS), paths["inputs"], paths["tree"])
    return paths


def test_the_tree_asks_only_the_questions_that_split_the_engines(study):
    tree = read_tree(study["tree"])
    asked = [q["key"] for q in tree["questions"] if q["asked"]]
    assert asked == ["open_source", "ros", "closeness", "mechanics", "real_time_factor", "cpu"]
    assert [q["key"] for q in tree["not_asked"]] == ["free"]
    assert tree["not_asked"][0]["why"] == "every engine meets it"
    root = tree["nodes"][tree["root"]]
    assert root["question"] == "open_source"
    assert root["answers"][0]["keeps"] == ["anvil", "breeze", "comet", "ember"]
    assert root["answers"][0]["drops"][0]["engine"] == "dune"
    assert "closed source" in root["answers"][0]["drops"][0]["why"]


def test_each_path_of_answers_leads_to_the_engines_that_meet_them(study):
    tree = read_tree(study["tree"])
    open_ros = walk(tree, {"open_source": "Yes", "ros": "Yes, out of the box"})
    assert open_ros["kind"] == "question" and open_ros["candidates"] == ["comet"]
    # comet is the only open-source engine with ROS out of the box, and it fails mechanics
    assert walk(tree, {"open_source": "Yes", "ros": "Yes, out of the box"})["question"] == "closeness"
    leaf = walk(tree, {"open_source": "Yes", "ros": "Yes, out of the box", "closeness": "No", "mechanics": "Yes"})
    assert leaf == {**leaf, "kind": "leaf", "engines": []}
    leaf = walk(
        tree, {"open_source": "Yes", "ros": "No", "mechanics": "Yes", "closeness": "Yes, on its yaw-rate gain error"}
    )
    assert leaf["kind"] == "question" and leaf["question"] == "real_time_factor"
    assert [a["label"] for a in leaf["answers"]] == ["At least 500 x real time", "No need"]
    assert walk(
        tree,
        {
            "open_source": "Yes",
            "ros": "No",
            "mechanics": "Yes",
            "closeness": "Yes, on its yaw-rate gain error",
            "real_time_factor": "At least 500 x real time",
        },
    )["engines"] == ["breeze"]
    # the equivalent group: anvil (best) and breeze (equivalent), none separated by CPU at 5 robots
    group = walk(
        tree,
        {
            "open_source": "Yes",
            "ros": "No",
            "mechanics": "Yes",
            "closeness": "Yes, on its yaw-rate gain error",
            "real_time_factor": "No need",
        },
    )
    assert group["kind"] == "leaf" and group["engines"] == ["anvil", "breeze"]
    assert [s["question"] for s in group["path"]] == ["open_source", "ros", "closeness", "real_time_factor"]


def test_an_engine_that_fails_mechanics_is_not_close_whatever_its_figure(study):
    tree = read_tree(study["tree"])
    close = next(q for q in tree["questions"] if q["key"] == "closeness")
    assert close["facts"]["comet"]["value"] == {"gain_error": False}  # "equivalent", yet it fails mechanics
    assert "fails the mechanics" in close["facts"]["comet"]["text"]
    assert close["facts"]["breeze"]["value"] == {"gain_error": True}
    assert "margin 0.02" in close["facts"]["breeze"]["text"]
    assert close["facts"]["ember"]["value"] == {"gain_error": False}
    assert "about 40 runs would decide" in close["facts"]["ember"]["text"]
    mechanics = next(q for q in tree["questions"] if q["key"] == "mechanics")
    # the verdict's gate, in its words
    assert mechanics["facts"]["comet"]["text"] == "fails 3 of 6 analytic cases: yaw gain (3)"
    assert mechanics["facts"]["comet"]["source"].endswith("mechanics.csv: comet")


def test_without_the_verdict_the_mechanics_come_from_the_validation_summary(tmp_path):
    paths = make_study(tmp_path, outcomes=False)
    decision_tree_job(list(FACTS), paths["inputs"], paths["tree"])
    mechanics = next(q for q in read_tree(paths["tree"])["questions"] if q["key"] == "mechanics")
    # the skipped case is no failure and not counted
    assert mechanics["facts"]["comet"]["text"] == "fails 3 of 6 analytic cases: turning (3)"
    assert mechanics["facts"]["comet"]["source"].endswith("comet (turn_0, turn_1, turn_2)")
    assert mechanics["facts"]["anvil"] == {
        **mechanics["facts"]["anvil"],
        "value": True,
        "text": "passes all 6 analytic cases",
    }


def test_every_fact_names_its_source(study):
    tree = read_tree(study["tree"])
    for q in tree["questions"]:
        for engine, fact in q["facts"].items():
            assert fact["source"] and fact["text"], (q["key"], engine)
    ros = next(q for q in tree["questions"] if q["key"] == "ros")
    assert ros["facts"]["comet"]["source"].endswith("comet.ros; https://example.org/comet/ros")
    rtf = next(q for q in tree["questions"] if q["key"] == "real_time_factor")
    assert rtf["facts"]["breeze"]["text"] == "real-time factor 930 on one core"
    assert rtf["facts"]["breeze"]["source"].endswith("rtf.csv: breeze")


def test_every_leaf_is_reached_and_every_engine_in_some_leaf(study):
    tree = read_tree(study["tree"])
    leaves = [n for n in tree["nodes"].values() if n["kind"] == "leaf"]
    targets = {a["next"] for n in tree["nodes"].values() if n["kind"] == "question" for a in n["answers"]}
    assert targets | {tree["root"]} == set(tree["nodes"])
    assert {e for leaf in leaves for e in leaf["engines"]} == set(FACTS)
    for leaf in leaves:  # a leaf's engines are kept by every answer on its path, and only they
        node = tree["nodes"][tree["root"]]
        for step in leaf["path"]:
            answer = next(a for a in node["answers"] if a["label"] == step["answer"])
            assert set(leaf["engines"]) <= set(answer["keeps"]), (step, leaf)
            node = tree["nodes"][answer["next"]]
        assert node is tree["nodes"][leaf["id"]] and answer["keeps"] == leaf["engines"]
    for leaf in leaves:
        for step in (s for s in leaf["path"] if s["answer"] == "Yes"):
            q = next(q for q in tree["questions"] if q["key"] == step["question"])
            assert all(q["facts"][e]["value"] is True for e in leaf["engines"]), (step, leaf)


def test_another_study_gives_another_tree(tmp_path, study):
    facts = {e: dict(f) for e, f in FACTS.items()}
    facts["dune"]["open_source"] = True  # licence changed: the licence question goes
    facts["comet"]["fails"] = 0  # a fixed engine: now ROS out of the box with mechanics exists
    paths = make_study(tmp_path / "other", facts)
    decision_tree_job(list(facts), paths["inputs"], paths["tree"])
    other = read_tree(paths["tree"])
    first = read_tree(study["tree"])
    assert other["nodes"][other["root"]]["question"] == "ros"
    assert "open_source" in [q["key"] for q in other["not_asked"]]
    leaf = walk(other, {"ros": "Yes, out of the box", "closeness": "No", "mechanics": "Yes"})
    assert leaf["kind"] != "leaf" or leaf["engines"]  # no longer empty
    assert other["nodes"] != first["nodes"]
    # without the verdict (a study without real data) there is no closeness question
    paths = make_study(tmp_path / "lab_only", facts, outcomes=False)
    decision_tree_job(list(facts), paths["inputs"], paths["tree"])
    assert "closeness" not in [q["key"] for q in read_tree(paths["tree"])["questions"]]


def test_the_weights_order_a_leaf_and_so_change_the_pick(study):
    totals = pd.read_csv(study["weighted"], index_col="engine")["total"].to_dict()
    assert leaf_order(["anvil", "breeze"], totals) == sorted(["anvil", "breeze"], key=lambda e: -totals[e])
    speed = {**WEIGHTS, "real_time_factor": 100.0}
    accuracy = {**WEIGHTS, "real_time_factor": 0.0, "imu_angular": 300.0}
    scores = pd.read_csv(study["weighted"], index_col="engine")[list(scoring.METRICS)]
    by_speed = scoring.weighted_table(scores, speed)["total"].to_dict()
    by_accuracy = scoring.weighted_table(scores, accuracy)["total"].to_dict()
    assert leaf_order(["anvil", "breeze"], by_speed)[0] == "breeze"
    assert leaf_order(["anvil", "breeze"], by_accuracy)[0] == "anvil"
    assert leaf_order(["anvil", "breeze"], {"breeze": 1.0}) == ["breeze", "anvil"]  # no total: last


def test_bad_tables_are_named_in_one_clear_error(tmp_path):
    paths = make_study(tmp_path)
    pd.read_csv(paths["inputs"]["rtf"]).drop(columns="real_time_factor").to_csv(paths["inputs"]["rtf"], index=False)
    with pytest.raises(InputError, match="rtf.csv: the real-time factors lacks the column.s. real_time_factor"):
        decision_tree_job(list(FACTS), paths["inputs"], paths["tree"])
    paths = make_study(tmp_path / "b")
    with pytest.raises(InputError, match="no facts for engine 'zephyr'"):
        decision_tree_job([*FACTS, "zephyr"], paths["inputs"], paths["tree"])
    (tmp_path / "tree.json").write_text(json.dumps({"schema": "other"}))
    with pytest.raises(InputError, match="schema"):
        read_tree(str(tmp_path / "tree.json"))


def test_the_tree_logic_names_no_engine():
    from pathlib import Path

    import simpick.score.tree as module

    source = Path(module.__file__).read_text().lower()
    facts = yaml.safe_load((Path(module.__file__).parents[3] / "resources/engines/qualitative.yaml").read_text())
    assert not [e for e in facts if f'"{e}"' in source or f"'{e}'" in source]


def test_build_tree_is_deterministic(study):
    questions = study_questions(list(FACTS), study["inputs"])
    assert build_tree(questions, list(FACTS)) == build_tree(study_questions(list(FACTS), study["inputs"]), list(FACTS))


def test_speed_answers_are_classes_at_the_gaps_and_keeping_pace_with_the_clock(tmp_path):
    from simpick.score.tree import speed_question

    factors = {"a": 19.8, "b": 18.5, "c": 9.16, "d": 8.4, "e": 1.25, "f": 0.82, "g": math.nan}
    write_csv(pd.DataFrame({"engine": list(factors), "real_time_factor": list(factors.values())}), tmp_path / "rtf.csv")
    question = speed_question(str(tmp_path / "rtf.csv"), list(factors))
    options = question.options(list(factors))
    # the two largest gaps (8.4 -> 1.25, 18.5 -> 9.16), real time (1.25 -> 0.82), the measured, no need
    assert [(o.label, o.keeps) for o in options] == [
        ("At least 10 x real time", ("a", "b")),
        ("At least 5 x real time", ("a", "b", "c", "d")),
        ("At least real time", ("a", "b", "c", "d", "e")),
        ("At least 0.5 x real time", ("a", "b", "c", "d", "e", "f")),
        ("No need", tuple(factors)),
    ]
    assert question.facts["g"].text == "real-time factor not measured"
    # close factors are one class: nothing to ask
    assert [o.label for o in question.options(["a", "b"])] == ["No need"]


def test_the_printed_tree_draws_every_leaf_at_a4_width_without_weights(study):
    """The figure reads no weight (a weight edit does not redraw it): each leaf its letter and its engines
    in the tree's order; the report's table under it (leaf_rows) orders them by the weighted total."""
    from simpick.report.tree_figure import WIDTH, draw_tree, layout, leaf_letters, leaf_rows

    tree = read_tree(study["tree"])
    totals = pd.read_csv(study["weighted"], index_col="engine")["total"].to_dict()
    fig = draw_tree(tree)
    _, leaves, _ = layout(tree)
    assert fig.get_size_inches()[0] == WIDTH <= 7.5
    texts = [t.get_text() for t in fig.axes[0].texts]
    empty = sum(not tree["nodes"][n]["engines"] for n in leaves)
    assert texts.count("no engine meets these answers") == empty > 0
    letters = leaf_letters(tree)
    assert list(letters) == leaves and list(letters.values())[:3] == ["A", "B", "C"]
    assert set(letters.values()) <= set(texts)
    for n in leaves:  # the tree's order, no total printed
        if tree["nodes"][n]["engines"]:
            listed = ", ".join(tree["nodes"][n]["engines"])
            assert any(t.replace("\u2020", "").replace("\n", " ") == listed for t in texts), listed
    rows = leaf_rows(tree, totals)
    assert [r["letter"] for r in rows] == list(letters.values())
    for row, n in zip(rows, leaves):
        assert [e["engine"] for e in row["engines"]] == leaf_order(tree["nodes"][n]["engines"], totals)
        assert [e["pick"] for e in row["engines"]] == [i == 0 for i in range(len(row["engines"]))]
    # another weighting reorders the table, never the figure
    flipped = {e: -t for e, t in totals.items()}
    multi = [r for r in leaf_rows(tree, flipped) if len(r["engines"]) > 1]
    assert multi and all(
        [e["engine"] for e in r["engines"]] == leaf_order([e["engine"] for e in r["engines"]], flipped) for r in multi
    )


@pytest.mark.workflow
def test_the_rules_plan_the_tree_from_the_study_and_the_figure_without_the_weights(tmp_path):
    """A dry run: rule decision_tree reads the verdict's outcomes and gate with the lab's tables, and
    figure_tree the tree alone (a weight edit reaches neither; the report orders the leaves)."""
    from conftest import snakemake, tiny_config, write_config

    write_config(tmp_path, tiny_config(tmp_path))
    out = snakemake(
        tmp_path,
        "-n",
        "--rerun-triggers",
        "mtime",
        "--",
        "results/verdict/tree.json",
        "results/report/figures/tree.png",
    )
    assert out.returncode == 0, out.stderr[-3000:]
    text = out.stdout + out.stderr
    jobs = {block.split(":")[0].split()[-1]: block for block in text.split("\nrule ")[1:]}
    assert {"decision_tree", "figure_tree", "verdict", "validation_summary"} <= set(jobs)
    assert "weighted" not in jobs  # the figure needs no weighted table
    tree_inputs = jobs["decision_tree"].split("input:")[1].split("\n")[0]
    for needed in (
        "results/verdict/outcomes.csv",
        "results/verdict/mechanics.csv",
        "results/validation/summary.csv",
        "rtf.csv",
        "results/cpu/",
        "qualitative.yaml",
    ):
        assert needed in tree_inputs, needed
    assert "weighted.csv" not in tree_inputs
    figure_inputs = jobs["figure_tree"].split("input:")[1].split("\n")[0]
    assert "results/verdict/tree.json" in figure_inputs and "weighted.csv" not in figure_inputs


def test_the_drive_comparison_counts_by_its_pooled_rows_only(tmp_path):
    """The DRIVE comparison's outcomes hold a pooled row per metric and engine (scope all) and one per
    terrain: closeness is read from the pooled rows, so an engine best on one terrain only is not close."""
    from simpick.score.tree import closeness_question

    def row(scope, engine, outcome, recommendable=True):
        return {
            "scope": scope,
            "paired_by": "step",
            "metric": "gain_error",
            "label": "yaw-rate gain error",
            "unit": "",
            "engine": engine,
            "n_runs": 30,
            "mean": 0.05 if outcome == "best" else 0.3,
            "best": "mujoco",
            "outcome": outcome,
            "diff_to_best": 0.0 if outcome == "best" else 0.25,
            "diff_low": 0.2,
            "diff_high": 0.3,
            "margin": 0.015,
            "runs_needed": float("nan"),
            "recommendable": recommendable,
        }

    rows = [row("all", "mujoco", "best"), row("all", "physx", "worse")]
    rows += [row("gravel", "physx", "best"), row("gravel", "mujoco", "worse")]
    path = tmp_path / "outcomes.csv"
    write_csv(pd.DataFrame(rows), path)
    question = closeness_question(str(path), ["mujoco", "physx"])
    assert question.facts["mujoco"].value == {"gain_error": True}
    assert question.facts["physx"].value == {"gain_error": False}
