"""The report's interactive part in a real browser (headless Chromium through Playwright): answering
the decision tree's questions gives the pick, and the page's weighted totals at the study's weights
are those of weighted.csv. The page is built from a made-up study's tables (test_tree.make_study).

Chromium comes from the system (Debian's chromium, which `make test` installs); a machine without
it fails here, with the fix, rather than skipping."""

from pathlib import Path

import pandas as pd
import pytest

from simpick.report.interactive import choose_page
from simpick.score import scoring
from simpick.score.tree import decision_tree_job, leaf_order, read_tree, walk
from test_tree import FACTS, WEIGHTS, make_study

CHROMIUM = "/usr/bin/chromium"
ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


@pytest.fixture(scope="module")
def browser():
    if not Path(CHROMIUM).exists():
        pytest.fail(
            f"no Chromium at {CHROMIUM}: install it with `apt-get install chromium` (as root; make test does)",
            pytrace=False,
        )
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        pytest.fail(
            "the Python package playwright is missing: pip install -c constraints.txt -e '.[test]'", pytrace=False
        )
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield browser
        browser.close()


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    folder = tmp_path_factory.mktemp("study")
    paths = make_study(folder)
    decision_tree_job(list(FACTS), paths["inputs"], paths["tree"])
    page = folder / "page.html"
    page.write_text(choose_page(read_tree(paths["tree"]), pd.read_csv(paths["weighted"]), WEIGHTS))
    return {**paths, "page": page}


@pytest.fixture
def page(browser, study):
    context = browser.new_context()
    # nothing leaves the page: any request other than the file itself fails the test
    requests = []
    context.on("request", lambda r: requests.append(r.url) if not r.url.startswith("file://") else None)
    page = context.new_page()
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(study["page"].as_uri())
    page.wait_for_selector("#simpick-choose[data-ready=true]")
    yield page
    assert not errors, errors
    assert not requests, requests
    context.close()


def answer(page, question: str, label: str) -> None:
    page.click(f'#sc-current button[data-question="{question}"][data-answer="{label}"]')


def test_the_questions_lead_to_the_pick(page, study):
    tree = read_tree(study["tree"])
    totals = pd.read_csv(study["weighted"], index_col="engine")["total"].to_dict()
    answers = {
        "open_source": "Yes",
        "ros": "No",
        "closeness": "Yes, on its yaw-rate gain error",
        "real_time_factor": "No need",
    }
    leaf = walk(tree, answers)
    assert leaf["kind"] == "leaf" and len(leaf["engines"]) > 1
    for question, label in answers.items():
        assert page.get_attribute("#sc-current .sc-question", "data-question") == question
        answer(page, question, label)
    expected = leaf_order(leaf["engines"], totals)
    assert page.get_attribute("#sc-pick", "data-engine") == expected[0]
    assert page.eval_on_selector_all("#sc-leaf li", "items => items.map(i => i.dataset.engine)") == expected
    evidence = page.inner_text(".sc-evidence")
    assert "real-time factor 930 on one core" in evidence and "rtf.csv: breeze" in evidence
    assert "dune left out by" in page.inner_text(".sc-dropped")


def test_an_answer_no_engine_meets_says_so_and_can_be_changed(page):
    answer(page, "open_source", "Yes")
    answer(page, "ros", "Yes, out of the box")
    answer(page, "closeness", "No")
    answer(page, "mechanics", "Yes")
    assert page.get_attribute("#sc-pick", "data-engine") == ""
    assert "No engine of this study meets all these answers" in page.inner_text("#sc-current")
    assert "comet left out by" in page.inner_text(".sc-dropped")
    page.click("#sc-path li:nth-child(4) .sc-back")  # change the mechanics answer
    answer(page, "mechanics", "No")
    assert page.get_attribute("#sc-current .sc-question", "data-question") == "cpu"  # comet runs 5 robots at 150 %
    answer(page, "cpu", "No")
    assert page.get_attribute("#sc-pick", "data-engine") == "comet"
    assert "fails 3 of 6 analytic cases" in page.inner_text("#sc-pick")  # the pick carries its flag


def test_the_page_totals_at_the_study_weights_are_those_of_weighted_csv(page, study):
    weighted = pd.read_csv(study["weighted"], index_col="engine")
    shown = page.eval_on_selector_all(
        ".sc-engine-total", "cells => cells.map(c => [c.dataset.engine, Number(c.dataset.total), c.textContent])"
    )
    assert sorted(e for e, _, _ in shown) == sorted(weighted.index)
    for engine, total, text in shown:
        assert total == pytest.approx(weighted.loc[engine, "total"], rel=1e-5)  # the CSV keeps 6 figures
        assert text == f"{weighted.loc[engine, 'total']:.3f}"
    ranks = page.eval_on_selector_all(".sc-engine-rank", "cells => cells.map(c => [c.dataset.engine, c.textContent])")
    for engine, text in ranks:
        assert int(text.split()[0]) == weighted.loc[engine, "rank"]
    # the paper's rank flagged where mechanics fail, and why
    assert [e for e, text in ranks if text.endswith("\u2020")] == ["comet"]
    assert "\u2020 fails analytic mechanics: comet fails 3 of 6 analytic cases" in page.inner_text("#sc-ranking")


def test_a_weight_edit_recomputes_the_totals_and_reorders_the_leaf(page, study):
    scores = pd.read_csv(study["weighted"], index_col="engine")[list(scoring.METRICS)]
    weights = {**WEIGHTS, "real_time_factor": 0.0, "imu_angular": 300.0}
    expected = scoring.weighted_table(scores, weights)
    for metric in ("real_time_factor", "imu_angular"):
        page.fill(f'input[data-metric="{metric}"]', str(weights[metric]))
    shown = dict(
        page.eval_on_selector_all(
            ".sc-engine-total", "cells => cells.map(c => [c.dataset.engine, Number(c.dataset.total)])"
        )
    )
    for engine in expected.index:
        assert shown[engine] == pytest.approx(expected.loc[engine, "total"], rel=1e-5)
    for question, label in {
        "open_source": "Yes",
        "ros": "No",
        "closeness": "Yes, on its yaw-rate gain error",
        "real_time_factor": "No need",
    }.items():
        answer(page, question, label)
    assert (
        page.get_attribute("#sc-pick", "data-engine")
        == leaf_order(["anvil", "breeze"], expected["total"].to_dict())[0]
        == "anvil"
    )
    page.fill('input[data-metric="real_time_factor"]', "100")  # speed first: the faster engine is the pick
    assert page.get_attribute("#sc-pick", "data-engine") == "breeze"
    page.click("#sc-reset")
    assert float(page.input_value('input[data-metric="real_time_factor"]')) == WEIGHTS["real_time_factor"]
    totals = pd.read_csv(study["weighted"], index_col="engine")["total"].to_dict()
    assert page.get_attribute("#sc-pick", "data-engine") == leaf_order(["anvil", "breeze"], totals)[0]


def test_the_whole_tree_lists_every_leaf_ordered_by_the_weights(page, study):
    tree = read_tree(study["tree"])
    leaves = {n["id"]: n["engines"] for n in tree["nodes"].values() if n["kind"] == "leaf"}
    totals = pd.read_csv(study["weighted"], index_col="engine")["total"].to_dict()

    def shown():
        return dict(
            page.eval_on_selector_all(
                "#sc-outline .sc-outline-leaf", "spans => spans.map(s => [s.dataset.leaf, s.dataset.engines])"
            )
        )

    assert shown() == {i: " ".join(leaf_order(e, totals)) for i, e in leaves.items()}
    page.fill('input[data-metric="real_time_factor"]', "100")
    scores = pd.read_csv(study["weighted"], index_col="engine")[list(scoring.METRICS)]
    faster = scoring.weighted_table(scores, {**WEIGHTS, "real_time_factor": 100.0})["total"].to_dict()
    assert (
        shown()
        == {i: " ".join(leaf_order(e, faster)) for i, e in leaves.items()}
        != {i: " ".join(leaf_order(e, totals)) for i, e in leaves.items()}
    )


def test_a_fact_with_markup_in_it_is_shown_as_text(browser, study, tmp_path):
    tree = read_tree(study["tree"])
    ros = next(q for q in tree["questions"] if q["key"] == "ros")
    ros["facts"]["anvil"]["text"] = "</script><!-- <b>not bold</b>"
    path = tmp_path / "page.html"
    path.write_text(choose_page(tree, pd.read_csv(study["weighted"]), WEIGHTS))
    page = browser.new_page()
    page.goto(path.as_uri())
    page.wait_for_selector("#simpick-choose[data-ready=true]")
    for question, label in {
        "open_source": "Yes",
        "ros": "No",
        "closeness": "Yes, on its yaw-rate gain error",
        "real_time_factor": "No need",
    }.items():
        answer(page, question, label)
    assert "</script><!-- <b>not bold</b>" in page.inner_text(".sc-evidence")
    page.close()


def test_the_page_needs_no_network_and_hides_in_print(study):
    """Nothing is loaded from elsewhere; in print (WeasyPrint, the report's PDF) the interactive part
    is left out, where the static figure of the tree stands for it."""
    import weasyprint

    html = study["page"].read_text()
    assert "<script src" not in html and "<link" not in html and "@import" not in html

    def texts(box):
        return ([box.text] if getattr(box, "text", None) else []) + [
            t for c in getattr(box, "children", None) or [] for t in texts(c)
        ]

    printed = weasyprint.HTML(string=html.replace("<body>", "<body><p>printed beside it</p>")).render()
    words = " ".join(t for page in printed.pages for t in texts(page._page_box))
    assert "printed beside it" in words and "Pick an engine" not in words and "Ranking" not in words


# --- the simulators' tree: the catalog's real ROS 2 facts, a mechanics pattern made up for the test ---

SIMULATOR_FAILS = {  # analytic cases failed (of 6): the out-of-the-box simulators mixed, so both ends are tested
    "gazebo": 3,
    "isaac_sim": 3,
    "isaac_lab_newton": 0,
    "gazebo_classic": 0,
    "webots": 2,
    "mujoco": 0,
    "drake": 0,
    "coppeliasim": 3,
    "morse": 3,
    "genesis": 0,
}


@pytest.fixture(scope="module")
def simulators_study(tmp_path_factory):
    from conftest import ROOT
    from simpick.engines.catalog import load_catalog

    catalog = load_catalog(ROOT / "resources/simulators/simulators.yaml")
    facts = {
        name: {
            "free": sim.qualitative.free,
            "open_source": sim.qualitative.open_source,
            "ros": sim.qualitative.ros,
            "rtf": 100.0 + 10 * i,
            "cpu": 20.0 + i,
            "fails": SIMULATOR_FAILS[name],
            "gain": ("best" if name == "mujoco" else "equivalent", 0.05 + 0.001 * i),
        }
        for i, (name, sim) in enumerate(catalog.simulators.items())
        if sim.engine is not None
    }
    folder = tmp_path_factory.mktemp("simulators")
    paths = make_study(folder, facts)
    decision_tree_job(list(facts), paths["inputs"], paths["tree"])
    page = folder / "page.html"
    page.write_text(choose_page(read_tree(paths["tree"]), pd.read_csv(paths["weighted"]), WEIGHTS))
    return {**paths, "page": page, "facts": facts}


@pytest.mark.parametrize("ros", ["Yes, out of the box", "Yes; an official plugin built by hand will do"])
def test_the_ros2_paths_of_the_simulators_tree_end_at_a_simulator_that_passes_mechanics(browser, simulators_study, ros):
    from simpick.report.simulators import leaf_for

    tree = read_tree(simulators_study["tree"])
    labels = [a["label"] for n in tree["nodes"].values() if n.get("question") == "ros" for a in n["answers"]]
    assert ros in labels, labels
    leaf = leaf_for(tree, {"ros": ros})
    facts = simulators_study["facts"]
    levels = {"out_of_the_box"} | ({"official_plugin"} if "plugin" in ros else set())
    meets = [s for s, f in facts.items() if f["ros"] in levels and not f["fails"]]
    assert meets, "the made-up pattern leaves a passing simulator on this path"
    assert leaf["kind"] == "leaf" and leaf["engines"] and set(leaf["engines"]) <= set(meets)

    page = browser.new_page()
    page.goto(simulators_study["page"].as_uri())
    page.wait_for_selector("#simpick-choose[data-ready=true]")
    node = tree["nodes"][tree["root"]]
    while node["kind"] == "question":  # answer as leaf_for does: closeness and mechanics demanding, the rest no need
        q = node["question"]
        label = (
            ros
            if q == "ros"
            else (node["answers"][0]["label"] if q in ("closeness", "mechanics") else node["answers"][-1]["label"])
        )
        assert page.get_attribute("#sc-current .sc-question", "data-question") == q
        answer(page, q, label)
        node = tree["nodes"][next(a for a in node["answers"] if a["label"] == label)["next"]]
    pick = page.get_attribute("#sc-pick", "data-engine")
    assert pick in meets and pick in leaf["engines"]
    page.close()


def test_the_pick_names_the_calibrated_profile_and_its_file_where_closeness_is_asked(
    browser, simulators_study, tmp_path
):
    """The simulators' tree with each leaf's profiles (simpick.score.profiles.name_profiles): answered as the
    report's ROS 2 paths answer it (closeness demanded), the page lists the leaf's simulators with the profile
    its answers ask for, MuJoCo's calibrated profile with its settings and file."""
    from simpick.report.simulators import leaf_for
    from simpick.score.profiles import name_profiles
    from test_report_simulators import write_simulators

    folder = write_simulators(tmp_path / "simulators")
    tree = name_profiles(read_tree(simulators_study["tree"]), pd.read_csv(folder / "table.csv"), folder / "settings")
    ros = "Yes; an official plugin built by hand will do"
    leaf = leaf_for(tree, {"ros": ros})
    assert "mujoco" in leaf["engines"] and any(s["question"] == "closeness" for s in leaf["path"])
    mujoco = next(p for p in leaf["profiles"] if p["simulator"] == "mujoco")
    assert mujoco["variant"] == "calibrated" and mujoco["text"] == (
        "MuJoCo, calibrated: friction_ratio 0.70, impratio 10 "
        "(settings file results/simulators/settings/mujoco-calibrated.xml)"
    )
    page_file = tmp_path / "page.html"
    page_file.write_text(choose_page(tree, pd.read_csv(simulators_study["weighted"]), WEIGHTS))
    page = browser.new_page()
    page.goto(page_file.as_uri())
    page.wait_for_selector("#simpick-choose[data-ready=true]")
    node = tree["nodes"][tree["root"]]
    while node["kind"] == "question":
        q = node["question"]
        label = (
            ros
            if q == "ros"
            else (node["answers"][0]["label"] if q in ("closeness", "mechanics") else node["answers"][-1]["label"])
        )
        answer(page, q, label)
        node = tree["nodes"][next(a for a in node["answers"] if a["label"] == label)["next"]]
    shown = page.locator("#sc-profiles li[data-engine=mujoco]")
    assert shown.get_attribute("data-variant") == "calibrated" and shown.inner_text() == mujoco["text"]
    page.close()
