"""The first page answers the simulators' question: which simulator, as shipped, tuned or calibrated to the robot,
reproduces it on its real runs, and with which settings file; the engines beneath, as the simulators' physics.
Built from a simulators' table written here in rule simulators' columns (results/simulators/table.csv)."""

from __future__ import annotations

import html
import json
import re
from pathlib import Path

import pandas as pd
import pytest

from simpick.score.simulators import TABLE_COLUMNS

# the columns the calibrated profiles add to every row (the calibration's contract with the report)
HELDOUT_COLUMNS = [
    "heldout_gain_error",
    "heldout_gain_error_low",
    "heldout_gain_error_high",
    "heldout_runs",
    "real_spread",
    "within_spread",
    "heldout_heading_error",
    "calibrated_settings",
    "turning_settable",
    "mechanics_own",
]
SPREAD = 0.045
LABELS = {
    "gazebo_classic": ("Gazebo Classic", "ode", "sdf"),
    "mujoco": ("MuJoCo", "mujoco", "xml"),
    "webots": ("Webots", "ode", "wbt"),
    "isaac_sim": ("Isaac Sim", "physx", "py"),
    "drake": ("Drake", "drake", "yaml"),
}
# simulator -> variant -> (held-out gain error, low, high, mechanics failed of 20, calibrated settings,
# turning settable, mechanics_own)
PROFILES = {
    "gazebo_classic": {
        "shipped": (0.300, 0.27, 0.33, 0, "", "yes", ""),
        "tuned": (0.275, 0.25, 0.30, 0, "", "yes", ""),
        "calibrated": (0.031, 0.020, 0.042, 0, "friction_ratio=0.62", "yes", "passes 20/20"),
    },
    "mujoco": {
        "shipped": (0.250, 0.23, 0.27, 0, "", "yes", ""),
        "tuned": (0.222, 0.20, 0.24, 0, "", "yes", ""),
        "calibrated": (0.040, 0.030, 0.050, 0, "friction_ratio=0.70; impratio=10", "yes", "passes 20/20"),
    },
    "webots": {
        "shipped": (0.230, 0.21, 0.25, 2, "", "yes", ""),
        "tuned": (0.196, 0.18, 0.21, 0, "", "yes", ""),
        # fits the runs by breaking the mechanics of its own parameters: never the pick
        "calibrated": (
            0.012,
            0.005,
            0.020,
            0,
            "friction_ratio=0.20",
            "yes",
            "passes 17/20; breaks mechanics its tuned profile keeps: slope_10, slope_20, slide",
        ),
    },
    "isaac_sim": {
        "shipped": (0.420, 0.40, 0.44, 0, "", "yes", ""),
        "tuned": (0.390, 0.37, 0.41, 0, "", "yes", ""),
        "calibrated": (
            0.390,
            0.37,
            0.41,
            0,
            "",
            "no: PhysX materials are isotropic (NVIDIA-Omniverse/PhysX physx/include/PxMaterial.h:120)",
            "passes 20/20",
        ),
    },
}


def table_rows(calibrated: str = "run", heldout: bool = True) -> pd.DataFrame:
    """The simulators' table: ``calibrated`` "run" (calibrated rows with figures), "off" (listed, not run: the
    study's variants leave them out) or "absent" (a table from before them); ``heldout`` False: without the
    held-out columns."""
    rows = []
    for sim, (label, engine, _) in LABELS.items():
        for variant in ("shipped", "tuned", "calibrated"):
            base = {"simulator": sim, "label": label, "variant": variant, "engine": engine}
            if variant == "calibrated" and calibrated == "absent":
                continue
            if sim == "drake":
                rows.append(base | {"model": "", "status": "not run: pydrake is not installed"})
                continue
            if variant == "calibrated" and calibrated == "off":
                rows.append(base | {"model": "", "status": "not run: variant not selected (simulators.variants)"})
                continue
            error, low, high, failed, settings, settable, own = PROFILES[sim][variant]
            row = base | {
                "model": f"{sim}-{variant}",
                "status": "run",
                "mechanics": "pass" if not failed else "fail",
                "mechanics_failed": failed,
                "mechanics_cases": 20,
                "mechanics_note": "" if not failed else f"fails {failed} of 20 analytic cases: slopes ({failed})",
                "gain_flat": 0.478,
                "gain_flat_min": 0.47,
                "gain_flat_max": 0.49,
                "gain_coulomb": 0.478,
                # over every real run (the tuned and shipped profiles' settings saw none of them)
                "gain_error": error + 0.004,
                "gain_error_low": low,
                "gain_error_high": high + 0.008,
                "gain_outcome": "worse",
                "gain_diff_to_best": error - 0.012,
                "heading_error": 0.05,
                "heading_outcome": "undetermined",
                "n_runs": 14,
                "runs_failed": 0,
                "settings_file": f"results/simulators/settings/{sim}-{variant}",
            }
            if heldout:
                row |= {
                    "heldout_gain_error": error,
                    "heldout_gain_error_low": low,
                    "heldout_gain_error_high": high,
                    "heldout_runs": 6,
                    "real_spread": SPREAD,
                    "within_spread": error <= SPREAD,
                    "heldout_heading_error": 0.05,
                    "calibrated_settings": settings,
                    "turning_settable": PROFILES[sim]["calibrated"][5],
                    "mechanics_own": own or f"passes {20 - failed}/20",
                }
            rows.append(row)
    columns = TABLE_COLUMNS + (HELDOUT_COLUMNS if heldout else [])
    return pd.DataFrame(rows, columns=columns)


def write_simulators(folder: Path, calibrated: str = "run", heldout: bool = True) -> Path:
    """results/simulators/ as the report reads it: table.csv and the settings files."""
    folder.mkdir(parents=True, exist_ok=True)
    table = table_rows(calibrated, heldout)
    table.to_csv(folder / "table.csv", index=False)
    (folder / "settings").mkdir(exist_ok=True)
    for r in table[table.status == "run"].itertuples():
        (folder / "settings" / f"{r.simulator}-{r.variant}.{LABELS[r.simulator][2]}").write_text("settings\n")
    return folder


@pytest.fixture(scope="module")
def real_study(tmp_path_factory):
    from test_report import _real_params, write_synthetic_inputs, write_synthetic_real_inputs, write_verdict

    root = tmp_path_factory.mktemp("report_simulators")
    real = write_synthetic_real_inputs(root / "real", replay=False)
    inputs = write_synthetic_inputs(root / "in", seconds=1.0, failed=None, accuracy_errors=real["segments_imu_errors"])
    inputs.update(real)
    inputs.update(write_verdict(root / "verdict", real["segments_per_test"], inputs["weighted"]))
    return root, inputs, {k: v for k, v in _real_params().items() if k != "title"}


def _page(root: Path, inputs: dict, params: dict, name: str, **table) -> str:
    from test_report import _render

    folder = write_simulators(root / name / "simulators", **table)
    return _render(inputs, {**params, "simulators": str(folder)})


def _lead(text: str) -> str:
    found = re.search(r'id="simulators-answer-lead">(.*?)</p>', text, re.S).group(1)
    return " ".join(html.unescape(re.sub(r"<[^>]+>", "", found)).split())


def _rows(text: str) -> dict[str, str]:
    table = re.search(r'<table[^>]*id="simulators-answer-table".*?</table>', text, re.S).group(0)
    return {
        m.group(1): html.unescape(m.group(0))
        for m in re.finditer(r'<tr data-simulator="(\w+)".*?</tr>', table.split("<tbody>")[1], re.S)
    }


def test_the_first_page_names_the_simulator_its_profile_and_its_settings_file(real_study):
    root, inputs, params = real_study
    text = _page(root, inputs, params, "calibrated")
    assert "<h1>simpick: which simulator reproduces" in text and "with which settings?</h1>" in text
    lead = _lead(text)
    # the closest profile that passes its own mechanics (Webots' calibrated profile comes closer by failing it)
    assert lead.startswith("Closest to the real")
    assert "Gazebo Classic, calibrated (friction_ratio 0.62)" in lead
    assert "0.031 [0.020, 0.042], within the robot's own spread of 0.045" in lead
    assert "6 held-out runs" in lead
    assert '<a href="../simulators/settings/gazebo_classic-calibrated.sdf">gazebo_classic-calibrated.sdf</a>' in text
    rows = _rows(text)
    # the simulators by their pick's held-out error; the one that did not run last, with why
    # (a simulator that did not run is a line below the table, with why: the table holds the answer)
    assert list(rows) == ["gazebo_classic", "mujoco", "webots", "isaac_sim"]
    assert 'data-best="calibrated"' in rows["gazebo_classic"] and "own mechanics 20/20" in rows["mujoco"]
    # a cell gives the count of the mechanics a profile breaks, not the cases nor the reasons (the simulators'
    # section does): the first page holds the whole answer
    assert 'data-best="tuned"' in rows["webots"] and "✗ own mechanics 17/20</span>" in rows["webots"]
    assert "breaks mechanics its tuned profile keeps" not in rows["webots"]
    assert "webots-tuned.wbt" in rows["webots"] and "webots-calibrated" not in rows["webots"].split("The pick")[-1]
    assert (
        "turning not settable</span>" in rows["isaac_sim"] and "PhysX materials are isotropic" not in rows["isaac_sim"]
    )
    assert "<code>" not in "".join(rows.values())  # no settings in the cells: the lead and the files name them
    assert "6.1× the spread" in rows["gazebo_classic"]  # as shipped: 0.300 / 0.045
    idle = html.unescape(re.search(r'id="simulators-not-run">(.*?)</p>', text, re.S).group(1))
    assert '<span data-simulator="drake"><b>Drake</b> (pydrake is not installed)</span>' in idle
    sentences = html.unescape(re.search(r'id="simulators-sentences">(.*?)</ul>', text, re.S).group(1))
    assert "as shipped, MuJoCo (0.250, 5.6x the spread)" in sentences
    assert "as tuned, Webots (0.196" in sentences
    # the reason's first clause: its source is the simulators' section's, not the first page's
    assert "Isaac Sim cannot move its turning within its own settings (PhysX materials are isotropic)" in sentences
    assert "PxMaterial.h" not in sentences and "(the sources: the simulators' section)" in sentences
    assert (
        "Webots, calibrated (friction_ratio 0.20) comes closer (0.012), but its own mechanics: passes 17/20"
        in sentences
    )
    assert "No calibrated profile" not in sentences


def test_the_simulators_come_before_the_engines_their_physics(real_study):
    root, inputs, params = real_study
    text = _page(root, inputs, params, "order")
    body = text[text.index("<body>") :]
    assert (
        body.index('id="simulators-answer-table"')
        < body.index('id="engines-answer"')
        < body.index('id="answer-table"')
        < body.index('id="decision-tree"')
    )
    assert "Beneath the simulators: their physics engines" in body


@pytest.mark.parametrize(
    "calibrated, heldout, why",
    [
        (
            "absent",
            False,
            "this study's simulators' table has no calibrated rows: it was written before the calibrated profiles",
        ),
        ("off", True, "no calibrated profile ran in this study: variant not selected (simulators.variants)"),
    ],
)
def test_without_calibrated_rows_the_page_answers_with_shipped_and_tuned_and_says_why(
    real_study, calibrated, heldout, why
):
    root, inputs, params = real_study
    text = _page(root, inputs, params, calibrated, calibrated=calibrated, heldout=heldout)
    lead = _lead(text)
    # the closest of shipped and tuned: Webots as tuned, over every real run where the table has no held-out runs
    assert "Webots, tuned" in lead and "calibrated" not in lead
    assert ("0.200 [0.180, 0.218]" if not heldout else "0.196 [0.180, 0.210]") in lead
    assert ("on 6 held-out runs" if heldout else "on 14 real runs") in lead
    assert '<a href="../simulators/settings/webots-tuned.wbt">' in text
    sentences = " ".join(html.unescape(re.search(r'id="simulators-sentences">(.*?)</ul>', text, re.S).group(1)).split())
    assert why[0].upper() + why[1:] in sentences and "the answer rests on the shipped and tuned profiles" in sentences
    rows = _rows(text)
    assert all('data-best="calibrated"' not in r for r in rows.values())
    # no column for a variant no simulator ran
    assert "<th>calibrated</th>" not in text and "<th>tuned</th>" in text


def test_without_simulators_the_page_asks_the_engines_question(real_study):
    from test_report import _render

    root, inputs, params = real_study
    text = _render(inputs, params)
    assert "which physics engine reproduces" in text and 'id="simulators-answer"' not in text
    assert 'id="engines-answer"' not in text and 'id="answer-table"' in text


def _simulators_tree():
    """A simulators' tree over two questions: ROS 2 (Gazebo Classic and Isaac Sim out of the box) and closeness
    to the real robot (Gazebo Classic and Webots as close as the best)."""
    from simpick.score.tree import Fact, Question, _binary, build_tree

    sims = ["gazebo_classic", "mujoco", "webots", "isaac_sim"]
    ros = _binary(
        "ros",
        "Do you need ROS 2?",
        "qualitative.yaml",
        {s: Fact(s in ("gazebo_classic", "isaac_sim"), s, "") for s in sims},
    )
    close = {s: Fact(s in ("gazebo_classic", "webots"), f"{s} closeness", "outcomes.csv") for s in sims}
    closeness = Question(
        "closeness",
        "Must it be as close to the real robot as the best?",
        "outcomes.csv",
        close,
        _binary("closeness", "", "", close, yes="Yes, on its yaw-rate gain error").options,
    )
    return build_tree([ros, closeness], sims)


def _leaf(tree: dict, **answers) -> dict:
    from simpick.score.tree import walk

    return walk(tree, answers)


def test_the_tree_s_leaves_name_the_calibrated_profile_where_the_user_asks_for_closeness(tmp_path):
    from simpick.report.simulators import simulators_section
    from simpick.score.profiles import name_profiles
    from simpick.score.scoring import DEFAULT_WEIGHTS

    folder = write_simulators(tmp_path / "simulators")
    tree = name_profiles(_simulators_tree(), pd.read_csv(folder / "table.csv"), str(folder / "settings"))
    close = _leaf(tree, ros="Yes", closeness="Yes, on its yaw-rate gain error")
    assert close["engines"] == ["gazebo_classic"]
    (named,) = close["profiles"]
    assert named["variant"] == "calibrated" and named["text"] == (
        "Gazebo Classic, calibrated: friction_ratio 0.62 "
        "(settings file results/simulators/settings/gazebo_classic-calibrated.sdf)"
    )
    # closeness not asked for: the tuned profile, the calibrated one beside it
    anyhow = {p["simulator"]: p for p in _leaf(tree, ros="Yes", closeness="No")["profiles"]}
    assert anyhow["gazebo_classic"]["variant"] == "tuned"
    assert anyhow["gazebo_classic"]["closest"].startswith("Gazebo Classic, calibrated: friction_ratio 0.62")
    # a calibrated profile that breaks its own mechanics, or one that cannot move the turning, is never named
    webots = {p["simulator"]: p for p in _leaf(tree, ros="No", closeness="Yes, on its yaw-rate gain error")["profiles"]}
    assert (
        webots["webots"]["variant"] == "tuned"
        and "its own mechanics: passes 17/20; breaks" in webots["webots"]["closest"]
    )
    isaac = {p["simulator"]: p for p in _leaf(tree, ros="Yes", closeness="No")["profiles"]}["isaac_sim"]
    assert isaac["variant"] == "tuned" and "not settable: PhysX materials are isotropic" in isaac["closest"]
    assert tree["profiles"] == {"calibrated": True, "why_not": "", "closeness_asked": True}

    # the report's ROS 2 paths (the most demanding answer to closeness) name the same profile
    (folder / "tree.json").write_text(json.dumps(tree))
    paths = {p["answer"]: p for p in simulators_section(str(folder), dict(DEFAULT_WEIGHTS))["ros_paths"]}
    assert paths["Yes"]["leaf"] == named["text"]

    # without calibrated rows every leaf keeps the tuned profile
    old = write_simulators(tmp_path / "old", calibrated="absent", heldout=False)
    tree = name_profiles(_simulators_tree(), pd.read_csv(old / "table.csv"), str(old / "settings"))
    leaf = _leaf(tree, ros="Yes", closeness="Yes, on its yaw-rate gain error")
    assert [(p["variant"], p.get("closest")) for p in leaf["profiles"]] == [("tuned", None)]
    assert tree["profiles"]["calibrated"] is False and "no calibrated rows" in tree["profiles"]["why_not"]


def test_the_page_across_robots_answers_which_simulator_per_robot(tmp_path):
    """The robots page opens with each robot's closest simulator profile and its settings file, and a table of
    each simulator's pick per robot: the Husky's table with calibrated rows, the Warthog's from before them."""
    import yaml

    from simpick.report.robots import robots_job
    from test_robots import HUSKY, WARTHOG

    inputs = {"answers": [], "headlines": [], "simulators": [], "settings": []}
    for robot, frame, units, calibrated in (
        ("husky", HUSKY, "runs", "run"),
        ("warthog", WARTHOG, "steps", "absent"),
    ):
        folder = tmp_path / "robots" / robot
        sims = write_simulators(folder / "simulators", calibrated=calibrated, heldout=calibrated == "run")
        # Isaac Sim closest of all on both robots, but every profile of it breaks its mechanics
        table = pd.read_csv(sims / "table.csv", dtype={"mechanics_own": object})
        isaac = table.simulator == "isaac_sim"
        table.loc[isaac, ["mechanics", "mechanics_failed"]] = ["fail", 5]
        table.loc[isaac, "gain_error"] = 0.001
        if calibrated == "run":  # the Husky's table judges on held-out runs
            table.loc[isaac, ["heldout_gain_error", "heldout_gain_error_low", "heldout_gain_error_high"]] = 0.001
            table.loc[isaac, "mechanics_own"] = "passes 15/20; breaks mechanics its tuned profile keeps: slope_10"
        table.to_csv(sims / "table.csv", index=False)
        if robot == "husky":  # the Husky's calibrated Gazebo Classic profile has a model that opens as it is
            table = pd.read_csv(sims / "table.csv")
            table["model_file"] = ""
            pick = (table.simulator == "gazebo_classic") & (table.variant == "calibrated")
            table.loc[pick, "model_file"] = "results/simulators/models/gazebo_classic-calibrated.world"
            table.to_csv(sims / "table.csv", index=False)
        frame.to_csv(folder / "answer.csv", index=False)
        (folder / "headline.yaml").write_text(
            yaml.safe_dump({"source_title": "data", "n_runs": 12, "units": units, "basis": "", "paragraph": "p."})
        )
        inputs["answers"].append(str(folder / "answer.csv"))
        inputs["headlines"].append(str(folder / "headline.yaml"))
        inputs["simulators"].append(str(sims / "table.csv"))
        inputs["settings"].append(str(sims / "settings"))
    params = {
        "robots": [
            {"name": "husky", "label": "Husky", "command": "snakemake --cores 2", "settings": {}},
            {"name": "warthog", "label": "Warthog", "command": "c", "settings": {}},
        ],
        "pooling": {"min_robots": 2},
    }
    outputs = {k: str(tmp_path / "robots" / f"benchmark.{k}") for k in ("table", "agreement", "html", "pdf")}
    robots_job(inputs, params, outputs)
    text = html.unescape((tmp_path / "robots" / "benchmark.html").read_text())
    leads = re.search(r'id="simulators-leads">(.*?)</ul>', text, re.S).group(1)
    husky, warthog = leads.split("</li>")[:2]
    assert "Closest to the real Husky on 6 held-out runs: Gazebo Classic, calibrated (friction_ratio 0.62)" in husky
    assert '<a href="husky/simulators/settings/gazebo_classic-calibrated.sdf">' in husky
    assert "Closest to the real Warthog on 14 real steps: Webots, tuned" in warthog
    assert '<a href="warthog/simulators/settings/webots-tuned.wbt">' in warthog and "no calibrated rows" in warthog
    # the simulators' answer comes before the engines' side-by-side tables
    assert text.index('id="simulators-per-robot"') < text.index('id="engine"')
    table = re.search(r'<table[^>]*id="simulators-per-robot".*?</table>', text, re.S).group(0)
    rows = dict(re.findall(r'<tr data-simulator="(\w+)">(.*?)</tr>', table, re.S))
    assert list(rows)[:2] == ["gazebo_classic", "mujoco"]
    husky_cell, warthog_cell = re.findall(r'<td class="cell">(.*?)</td>', rows["gazebo_classic"], re.S)
    assert "<b>calibrated</b>" in husky_cell and "within the robot's spread" in husky_cell
    # a cell as compact as the first page's: the model's file where there is one (its settings are in it), the
    # count of mechanics passed, no settings and no case names
    assert '<a href="husky/simulators/models/gazebo_classic-calibrated.world">' in husky_cell
    assert "gazebo_classic-calibrated.sdf" not in husky_cell and "<code>" not in husky_cell
    assert "own mechanics 20/20" in husky_cell
    assert "breaks mechanics" not in table and "passes 17/20" not in table
    # a simulator whose every pick breaks its mechanics comes after those with a pick that keeps them, however close
    kept = [
        any("<b>" in c and "✗</b>" not in c for c in re.findall(r'<td class="cell">(.*?)</td>', body, re.S))
        for body in rows.values()
    ]
    assert kept == sorted(kept, reverse=True) and dict(zip(rows, kept))["isaac_sim"] is False, dict(zip(rows, kept))
    assert "0.001" in rows["isaac_sim"] and list(rows).index("isaac_sim") > list(rows).index("webots")
    assert "<b>tuned</b>" in warthog_cell and "gazebo_classic-tuned.sdf" in warthog_cell
    assert "not run: pydrake is not installed" in rows["drake"]


def test_the_warthog_s_first_page_answers_on_its_drive_steps(tmp_path):
    """A DRIVE study (the Warthog's): the simulators' answer counts held-out steps against the robot's
    step-to-step spread; where the profiles did not replay DRIVE, the page says so and how to switch them on."""
    from test_drive_answer import _answer
    from test_report import PARAMS, _render, write_synthetic_inputs

    drive, out = _answer(tmp_path)
    inputs = write_synthetic_inputs(tmp_path / "in", seconds=1.0, failed=None)
    inputs |= {
        "verdict_outcomes": drive["outcomes"],
        "verdict_answer": out["answer"],
        "verdict_sentences": out["answer_yaml"],
        "verdict_headline": out["headline"],
    }
    config = {**PARAMS["config"], "robot": {"label": "Clearpath Warthog", "real_data_robot": "husky_a200"}}
    params = {k: v for k, v in PARAMS.items() if k != "title"} | {"config": config}
    table = table_rows()
    table["real_spread"] = 0.015
    table["within_spread"] = table.heldout_gain_error <= 0.015
    folder = tmp_path / "simulators"
    write_simulators(folder)
    table.to_csv(folder / "table.csv", index=False)
    text = _render(inputs, params | {"simulators": str(folder)})
    assert "which simulator reproduces the Clearpath Warthog" in text
    lead = _lead(text)
    assert "Closest to the real Clearpath Warthog on 6 held-out steps: Gazebo Classic, calibrated" in lead
    assert "0.031 [0.020, 0.042], 2.1 times the robot's own spread of 0.015" in lead

    # the profiles did not replay DRIVE (simulators.drive false): no figure on the real steps
    for column in ("gain_error", "gain_error_low", "gain_error_high", *HELDOUT_COLUMNS[:3]):
        table[column] = float("nan")
    table.to_csv(folder / "table.csv", index=False)
    text = " ".join(html.unescape(_render(inputs, params | {"simulators": str(folder)})).split())
    assert 'id="simulators-answer-missing"' in text and 'simulators={"drive": true}' in text
    assert 'id="answer-table"' in text  # the engines still answer


def test_a_table_with_no_rows_says_no_simulator_ran(real_study, tmp_path):
    from test_report import _render

    root, inputs, params = real_study
    folder = tmp_path / "simulators"
    folder.mkdir()
    pd.DataFrame(columns=TABLE_COLUMNS).to_csv(folder / "table.csv", index=False)
    text = " ".join(html.unescape(_render(inputs, params | {"simulators": str(folder)})).split())
    assert "No simulator can be named: the study ran no simulator profile." in text


def test_the_per_class_fits_stand_beside_the_pooled_with_their_held_out_runs_and_files(real_study):
    from test_report import _render

    root, inputs, params = real_study
    folder = write_simulators(root / "per_class" / "simulators")
    rows = [
        ("MuJoCo", "mujoco", "flooring", 0.576, 0.698, 1, 0.011, 0.079, True),
        ("MuJoCo", "mujoco", "sandy_loam", 0.8755, 0.698, 1, 0.060, 0.043, True),
        ("Gazebo Classic", "gazebo_classic", "ice", 0.70, 0.698, 0, None, None, False),
    ]
    table = pd.DataFrame(
        [
            {
                "simulator": sim,
                "label": label,
                "terrain_class": cls,
                "train_runs": 2,
                "real_gain": 0.7,
                "pooled_settings": f"friction_ratio = {pooled}",
                "class_settings": f"friction_ratio = {ratio}",
                "engine_gain": 0.7,
                "heldout_runs": held,
                # flooring's fits were judged on 1 of its 3 held-out runs (as on DRIVE: a few steps of many)
                "heldout_available": held + 2 if cls == "flooring" else held,
                "train_fitted": 1 if cls == "flooring" else 2,  # flooring's fit replayed 1 of its 2 training runs
                # flooring's spread as DRIVE's is taken: over pairs of steps of similar command
                "class_spread": 0.02,
                "spread_runs": 12,
                "spread_basis": "step-to-step repeatability of its gain over 12 pairs of steps of similar command"
                if cls == "flooring"
                else "standard deviation of its runs' real gains",
                "class_fit_error": own,
                # flooring has enough held-out runs for an interval of its class fit's error
                "class_fit_error_low": 0.006 if cls == "flooring" else None,
                "class_fit_error_high": 0.02 if cls == "flooring" else None,
                "pooled_fit_error": other,
                "settings_file": f"results/simulators/settings/{sim}-calibrated-{cls}" if has_file else "",
            }
            for label, sim, cls, ratio, pooled, held, own, other, has_file in rows
        ]
    )
    table.to_csv(folder / "per_class.csv", index=False)
    for _label, sim, cls, *_ in rows[:2]:
        (folder / "settings" / f"{sim}-calibrated-{cls}.xml").write_text("settings\n")
    text = _render(inputs, {**params, "simulators": str(folder)})
    found = re.search(r'<table[^>]*id="simulators-per-class-table".*?</table>', text, re.S)
    assert found, "no per-class table"
    body = html.unescape(found.group(0))
    assert body.split("<tbody>")[1].count("<tr>") == 3
    assert 'href="../simulators/settings/mujoco-calibrated-flooring.xml"' in body
    assert 'href="../simulators/settings/mujoco-calibrated-sandy_loam.xml"' in body
    assert "friction_ratio = 0.576 (friction_ratio = 0.698)" in body and "0.011 [0.006, 0.020]" in body
    assert '<td class="num">0.079</td>' in body  # the pooled error without an interval has none written
    assert '<td class="num">0.020 (12 pairs)</td>' in body and '<td class="num">0.020 (12)</td>' in body
    assert '<td>flooring</td>\n<td class="num">1 of 2</td>' in body, body
    assert '<td class="num">1 of 3</td>' in body and '<td class="num">1</td><td class="num">0.060</td>' in body
    # a class without held-out runs shows no error, not a zero
    ice = re.search(r"<tr><td>Gazebo Classic</td><td>ice</td>.*?</tr>", body, re.S).group(0)
    assert '<td class="num">0</td><td class="num">–</td><td class="num">–</td>' in ice, ice


def test_the_first_page_names_at_most_three_broken_cases_of_a_calibrated_profile():
    """A calibrated profile that breaks many cases its tuned profile keeps (Webots on the Warthog: 13) is named
    with three of them and the count of the rest on the first page; the simulators' section lists them all."""
    from simpick.score.profiles import _mechanics

    cases = [f"gain_case_{k}" for k in range(13)]
    own = f"passes 7/22; breaks mechanics its tuned profile keeps: {', '.join(cases)}"
    passes, words = _mechanics({"variant": "calibrated", "mechanics_own": own})
    assert not passes and words.endswith("gain_case_0, gain_case_1, gain_case_2 and 10 more")
    passes, words = _mechanics({"variant": "calibrated", "mechanics_own": own.replace(", gain_case_3", "", 1)[:90]})
    assert "more" not in words


def test_the_first_page_links_a_picked_profile_s_model_that_opens_as_it_is():
    """Where rule simulator_models wrote a model of the profile (the table's model_file), the first page's file
    column links it beside the settings file; a profile without one names its settings file alone."""
    from simpick.score.profiles import simulator_answer

    table = table_rows()
    table = table.loc[:, ~table.columns.duplicated()]  # the held-out columns are among the table's own now
    table["model_file"] = ""
    table.loc[(table.simulator == "mujoco") & (table.variant == "calibrated"), "model_file"] = (
        "results/simulators/models/mujoco-calibrated.xml"
    )
    answer = simulator_answer(table, spread=SPREAD)
    by = {s["simulator"]: s for s in answer["simulators"]}
    mujoco = {p["variant"]: p for p in by["mujoco"]["profiles"]}
    assert mujoco["calibrated"]["model"] == {
        "name": "mujoco-calibrated.xml",
        "href": "../simulators/models/mujoco-calibrated.xml",
    }
    assert mujoco["tuned"]["model"] is None and by["webots"]["profiles"][0]["model"] is None


def test_the_simulators_section_says_where_a_model_was_not_opened_in_its_simulator(tmp_path):
    """A model whose simulator has no loader here (the table's model_note, from the writer's opened_here) is listed
    with "fields checked; not opened in <simulator> here" beside its link; one opened in the tests is not."""
    from test_report import PARAMS, _render, write_synthetic_inputs

    inputs = write_synthetic_inputs(tmp_path / "in", seconds=1.0, failed=None)
    folder = tmp_path / "simulators"
    write_simulators(folder)
    table = table_rows()
    table = table.loc[:, ~table.columns.duplicated()]
    table["model_file"], table["model_note"] = "", ""
    webots = (table.simulator == "webots") & (table.variant == "tuned")
    mujoco = (table.simulator == "mujoco") & (table.variant == "tuned")
    table.loc[webots, "model_file"] = "results/simulators/models/webots-tuned.wbt"
    table.loc[webots, "model_note"] = "fields checked; not opened in Webots here"
    table.loc[mujoco, "model_file"] = "results/simulators/models/mujoco-tuned.xml"
    table.to_csv(folder / "table.csv", index=False)
    params = {k: v for k, v in PARAMS.items() if k != "title"}
    text = " ".join(html.unescape(_render(inputs, params | {"simulators": str(folder)})).split())
    models = text[text.index('id="simulators-models"') :].split("</p>")[0]
    assert "webots-tuned.wbt</a> (fields checked; not opened in Webots here)" in models
    assert "mujoco-tuned.xml</a>;" in models or "mujoco-tuned.xml</a>." in models


def test_per_class_the_first_page_names_the_closest_calibrated_file_that_keeps_its_mechanics():
    """Per class with held-out runs: the class file (or the pooled calibrated file) of the smallest held-out error
    among the simulators whose calibrated profile passes its own mechanics, with the class's spread. Webots'
    calibrated profile breaks mechanics: its better figure on flooring is not the pick. A class without held-out
    runs gets no line."""
    from simpick.score.profiles import class_answer

    table = table_rows()
    per_class = pd.DataFrame(
        [
            # simulator, class, held-out runs, class file, class fit error, pooled fit error, class spread
            ("mujoco", "flooring", 1, "results/simulators/settings/mujoco-calibrated-flooring", 0.012, 0.080, 0.007),
            ("gazebo_classic", "flooring", 1, "", 0.30, 0.05, 0.007),
            ("webots", "flooring", 1, "", 0.001, 0.001, 0.007),
            ("mujoco", "ice", 1, "", 0.02, 0.065, 0.018),
            ("gazebo_classic", "ice", 1, "", 0.11, 0.117, 0.018),
            ("mujoco", "snow", 0, "", None, None, None),
        ],
        columns=[
            "simulator",
            "terrain_class",
            "heldout_runs",
            "settings_file",
            "class_fit_error",
            "pooled_fit_error",
            "class_spread",
        ],
    )
    answer = {a["terrain_class"]: a for a in class_answer(per_class, table)}
    assert sorted(answer) == ["flooring", "ice"]
    assert answer["flooring"]["simulator"] == "mujoco" and answer["flooring"]["fit"] == "its class's own fit"
    assert answer["flooring"]["error"] == pytest.approx(0.012) and answer["flooring"]["files"][0]["name"] == (
        "mujoco-calibrated-flooring.*"
    )
    assert answer["flooring"]["spread_ratio"] == pytest.approx(0.012 / 0.007)
    # where the pooled file turns closer on the class's held-out runs than the class's own, the pooled file
    sandy = per_class.iloc[[0]].assign(terrain_class="sandy_loam", class_fit_error=0.030, pooled_fit_error=0.022)
    (pick,) = class_answer(sandy, table)
    assert pick["fit"] == "the pooled fit" and pick["error"] == pytest.approx(0.022)
    # on ice MuJoCo has no class file: its pooled file, judged by the pooled fit's error
    assert answer["ice"]["fit"] == "the pooled fit" and answer["ice"]["error"] == pytest.approx(0.065)
    assert answer["ice"]["files"][0]["name"] == "mujoco-calibrated.*"
    assert answer["ice"]["low"] is None  # no interval columns: none given
    # a class with enough held-out runs for an interval carries the picked fit's own interval
    held = per_class.assign(pooled_fit_error_low=0.05, pooled_fit_error_high=0.081, class_fit_error_low=None)
    ice = {a["terrain_class"]: a for a in class_answer(held, table)}["ice"]
    assert (ice["error"], ice["low"], ice["high"]) == (0.065, 0.05, 0.081)


def test_a_study_where_no_profile_ran_adds_no_empty_reason_about_calibration():
    """Where no simulator ran any profile the answer's own reason says so; the calibrated profiles' missing reason
    is not printed as an empty list ("... ran in this study: .")."""
    from simpick.score.profiles import _why_no_calibrated

    table = pd.DataFrame(
        {
            "simulator": ["mujoco", "mujoco", "drake"],
            "variant": ["tuned", "calibrated", "calibrated"],
            "status": ["not run: not in simulators.run"] * 2 + ["not run: pydrake is not installed"],
        }
    )
    assert _why_no_calibrated(table, ["tuned", "calibrated"], heldout=True) == ""
    table.loc[0, "status"] = "run"
    assert _why_no_calibrated(table, ["tuned", "calibrated"], heldout=True) == (
        "no calibrated profile ran in this study: not in simulators.run"
    )
