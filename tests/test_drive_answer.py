"""The first page's answer where the study's real data are DRIVE's steps (no BorealTC verdict): the DRIVE
comparison writes the verdict's tables beside its outcomes (simpick.score.steps.verdict_tables), rule answer
reads them through the same code as the verdict's (simpick.score.answer), and the report opens with the answer
table, speed error included, naming the dataset and its unit. Small synthetic frames, no replay."""

import html
import json
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from test_report import PARAMS, write_synthetic_inputs
from test_verdict import STATS, VERDICT_SETTINGS, WEIGHTS, _validation, _weighted

ENGINES = ["a", "b"]
N_STEPS = 12  # two sessions of six steps, one per terrain


def _errors() -> pd.DataFrame:
    """DRIVE-style per-step errors (simpick.compare.steps.step_errors' columns the verdict reads): ``a`` is
    close to the real robot on every metric, ``b`` far off on speed and heading, alike on the gain; ``k``
    (a reference model) turns exactly as the real robot."""
    rng = np.random.default_rng(3)
    rows = []
    for i in range(N_STEPS):
        session, terrain = ("s_asphalt", "asphalt") if i < N_STEPS // 2 else ("s_grass", "grass")
        gain_real = 0.6 + 0.02 * rng.standard_normal()
        for engine, gain, heading, speed in (
            ("a", 0.55, 0.05, 0.10),
            ("b", 0.55, 0.40, 0.60),
            ("k", gain_real, 0.02, 0.30),
        ):
            jitter = 0.01 * rng.standard_normal()
            rows.append(
                {
                    "session": session,
                    "step": i + 1,
                    "case": f"{session}/{i + 1:03d}",
                    "terrain_class": terrain,
                    "engine": engine,
                    "status": "ok",
                    "reasons": "",
                    "gain_real": gain_real,
                    "gain_sim": gain + jitter,
                    "gain_error": abs(gain + jitter - gain_real),
                    "heading_error": heading + abs(jitter),
                    "speed_error": speed + abs(jitter),
                }
            )
    return pd.DataFrame(rows)


def _drive_comparison(root: Path) -> dict[str, str]:
    """What rule drive_compare writes that rule answer reads: the outcomes (all terrains, then per terrain)
    and the verdict's tables beside them."""
    from simpick.score.steps import outcomes, verdict_tables

    root.mkdir(parents=True, exist_ok=True)
    errors = _errors()
    steps = errors[errors.engine == "a"][["session", "step", "terrain_class"]]
    validation = _validation(engines=ENGINES)
    frames = {"outcomes": outcomes(errors, steps, ENGINES, VERDICT_SETTINGS, 1.0, validation, "step", STATS, 1)}
    frames |= verdict_tables(errors, ENGINES, validation, "step", STATS, 1)
    paths = {}
    for name, frame in frames.items():
        paths[name] = str(root / f"{name}.csv")
        frame.to_csv(paths[name], index=False)
    return paths


BASIS = {
    "dataset": "DRIVE",
    "unit": "step",
    "noun": "DRIVE steps",
    "title": "the test Warthog's own sessions, each step replayed in every engine",
    "others": [],
}


def _answer(tmp_path: Path) -> tuple[dict, dict]:
    from simpick.score.answer import answer_job

    drive = _drive_comparison(tmp_path / "drive")
    weighted = tmp_path / "weighted.csv"
    _weighted().to_csv(weighted)
    provenance = tmp_path / "provenance.yaml"
    provenance.write_text(yaml.safe_dump({"accuracy": {"set": "lab"}}))
    rtf = tmp_path / "rtf.csv"
    pd.DataFrame({"engine": ENGINES, "real_time_factor": [2.0, 5.0]}).to_csv(rtf, index=False)
    cpu = []
    for e in ENGINES:
        cpu.append(str(tmp_path / f"{e}.json"))
        Path(cpu[-1]).write_text(
            json.dumps({"engine": e, "average": {"load_percent": 10.0}, "intense": {"load_percent": 30.0}})
        )
    out = {k: str(tmp_path / "verdict" / f"{k}.csv") for k in ("ranking", "separation", "answer")}
    out |= {
        "answer_yaml": str(tmp_path / "verdict" / "answer.yaml"),
        "headline": str(tmp_path / "verdict" / "headline.yaml"),
    }
    (tmp_path / "verdict").mkdir()
    inputs = {k: v for k, v in drive.items() if k != "metrics"}  # as PLAN.answer_inputs gives them: no discrimination
    answer_job(
        inputs
        | {
            "accuracy_tests": str(tmp_path / "no-accuracy-tests.csv"),
            "weighted": str(weighted),
            "provenance": str(provenance),
            "rtf": str(rtf),
            "cpu": cpu,
        },
        {
            "engines": [*ENGINES, "c"],  # c: a study engine the DRIVE replay left out (drive_replay.models)
            "statistics": STATS,
            "weights": WEIGHTS,
            "seed": 1,
            "source": "drive",
            "source_title": BASIS["title"],
            "robot": "test Warthog",
            "basis": BASIS,
        },
        out,
    )
    return drive, out


def test_the_answer_job_reads_drives_outcomes_and_answers_with_the_speed_error(tmp_path):
    drive, out = _answer(tmp_path)
    # the comparison's per-terrain rows are not the answer's: it reads the rows over every terrain
    assert set(pd.read_csv(drive["outcomes"]).scope) == {"all", "asphalt", "grass"}
    answer = pd.read_csv(out["answer"], keep_default_na=False).set_index("engine")
    assert list(answer.index) == ENGINES
    assert answer.loc["a", "speed_error_outcome"] == "best" and answer.loc["b", "speed_error_outcome"] == "worse"
    assert answer.loc["a", "heading_error_outcome"] == "best" and answer.loc["b", "heading_error_outcome"] == "worse"
    assert answer.loc["b", "gain_error_outcome"] in ("equivalent", "undetermined")
    assert float(answer.loc["b", "speed_error_diff"]) == pytest.approx(0.5, abs=0.02)
    assert float(answer.loc["a", "gain_ratio"]) == pytest.approx(0.55 / 0.6, abs=0.03)
    said = {s["need"]: s["text"] for s in yaml.safe_load(Path(out["answer_yaml"]).read_text())["sentences"]}
    assert said["closest"].startswith("Closest to the test Warthog on yaw-rate gain error")
    assert f"over {N_STEPS} DRIVE steps" in said["closest"]
    assert "real runs" not in " ".join(said.values())
    assert re.search(r"speed error worse than a by 0\.\d+ m/s", said["avoid"])
    head = yaml.safe_load(Path(out["headline"]).read_text())
    assert head["n_runs"] == N_STEPS and head["units"] == "steps"
    assert head["basis"].startswith(f"The answer rests on {N_STEPS} DRIVE steps (the test Warthog's own sessions")
    assert "; c was not replayed on these data and is not in the table." in head["basis"]


def test_an_outcomes_table_that_is_not_one_is_refused_by_name(tmp_path):
    from simpick.errors import InputError
    from simpick.score.answer import read_outcomes

    bad = tmp_path / "outcomes.csv"
    pd.DataFrame({"metric": ["gain_error"], "engine": ["a"]}).to_csv(bad, index=False)
    with pytest.raises(InputError, match=r"outcomes.csv: not an outcomes table: columns \['outcome'"):
        read_outcomes(str(bad))


def test_the_first_page_of_a_drive_study_is_the_answer_table(tmp_path):
    """A Warthog-like study (no BorealTC verdict: the committed segments are another robot's) whose real data
    are DRIVE's steps opens with the answer table, the speed error among its columns, and says what it rests
    on; not the "No answer table" notice."""
    from simpick.report.load import load_inputs
    from simpick.report.render import render_html

    drive, out = _answer(tmp_path)
    inputs = write_synthetic_inputs(tmp_path / "in", seconds=1.0, failed=None)
    inputs |= {
        "verdict_outcomes": drive["outcomes"],
        "verdict_metrics": drive["metrics"],
        "verdict_table": drive["table"],
        "verdict_answer": out["answer"],
        "verdict_ranking": out["ranking"],
        "verdict_separation": out["separation"],
        "verdict_sentences": out["answer_yaml"],
        "verdict_headline": out["headline"],
    }
    config = {**PARAMS["config"], "robot": {"label": "test Warthog", "real_data_robot": "husky_a200"}}
    text = render_html(load_inputs({k: v for k, v in inputs.items() if k != "traces"}), {**PARAMS, "config": config})
    section = text[text.index('<section id="answer">') : text.index("</section>", text.index('<section id="answer">'))]
    assert 'id="answer-table"' in section and 'id="answer-missing"' not in section
    assert "No answer table" not in text and "No verdict." not in text
    table = re.search(r'<table[^>]*id="answer-table".*?</table>', section, re.S).group(0)
    head = table.split("<tbody>")[0]
    assert "yaw-rate gain error" in head and "heading error (rad)" in head and "speed error (m/s)" in head
    assert "worse" in table and "best" in table
    basis = html.unescape(re.search(r'<p class="note" id="answer-basis">(.*?)</p>', section, re.S).group(1))
    assert basis.startswith(f"The answer rests on {N_STEPS} DRIVE steps")
    # the outcomes section prints the pooled rows, once per engine and metric
    outcomes = re.search(r'<table[^>]*id="outcomes-table".*?</table>', text, re.S).group(0)
    assert outcomes.count('<td class="outcome ') == len(ENGINES) * 3
