"""The report: built from small synthetic inputs in the workflow's file formats."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from simpick.published import load_published, write_outputs
from simpick.scoring import DEFAULT_WEIGHTS, METRICS, weighted_table
from simpick.traces import write_trace

ENGINES = ("pybullet", "mujoco")
TERRAINS = ("grass", "bumps", "gravel")
MOTIONS = ("straight", "circle")
FAILED = ("mujoco", "bumps", "circle")

CONFIG = {
    "seed": 1,
    "terrains": {"grass": {"rule": "flat_tiles", "friction": 0.2},
                 "bumps": {"rule": "plywood_layers", "friction": 0.95},
                 "gravel": {"rule": "gravel_bed", "friction": 0.55}},
    "motions": {"straight": {"v": 0.5, "w": 0.0, "duration": 10.0, "start": [-0.8, 0.0, 0.0]},
                "circle": {"v": 0.5, "w": 0.5, "duration": 12.6, "start": [2.0, -1.0, 0.0]}},
    "weights": dict(DEFAULT_WEIGHTS),
}


def _trace(engine: str, terrain: str, motion: str, seconds: float, rng: np.random.Generator) -> pd.DataFrame:
    spec = CONFIG["motions"][motion]
    t = np.arange(0.0, seconds, 0.01)
    n = t.size
    v, w = spec["v"], spec["w"] * (0.9 if engine == "mujoco" else 0.8)
    x0, y0, yaw0 = spec["start"]
    yaw = yaw0 + w * t
    if w:
        x = x0 + v / w * (np.sin(yaw) - math.sin(yaw0))
        y = y0 - v / w * (np.cos(yaw) - math.cos(yaw0))
    else:
        x, y = x0 + v * t, y0 + 0.01 * t * (1 if engine == "mujoco" else -1)
    rough = {"grass": 0.05, "bumps": 1.5, "gravel": 0.8}[terrain] * (1.2 if engine == "pybullet" else 1.0)
    on_strip = ((x > 0) & (x < 4) & (np.abs(y) < 0.5)).astype(float)
    noise = lambda s: rng.normal(0.0, s, n)  # noqa: E731
    frame = pd.DataFrame({
        "time": t,
        "ax": noise(0.05) + on_strip * noise(rough),
        "ay": v * w + noise(0.05) + on_strip * noise(rough * 0.7),
        "az": 9.81 + noise(0.05) + on_strip * noise(rough * 1.3),
        "wx": noise(0.004) + on_strip * noise(rough * 0.1),
        "wy": noise(0.004) + on_strip * noise(rough * 0.12),
        "wz": w + noise(0.004) + on_strip * noise(rough * 0.03),
        "x": x, "y": y, "z": 0.13228 + on_strip * 0.02,
        "roll": on_strip * noise(0.01), "pitch": on_strip * noise(0.01), "yaw": yaw,
        "vx": v * np.cos(yaw), "vy": v * np.sin(yaw), "vz": np.zeros(n),
        "v_forward": np.full(n, v), "yaw_rate": np.full(n, w),
        "cmd_left": np.full(n, (v - w * 0.555 / 2) / 0.1651),
        "cmd_right": np.full(n, (v + w * 0.555 / 2) / 0.1651),
    })
    for wheel in ("wheel_fl", "wheel_fr", "wheel_rl", "wheel_rr"):
        frame[wheel] = frame["cmd_left"] if wheel.endswith("l") else frame["cmd_right"]
    return frame


def write_synthetic_inputs(root: Path, seconds: float = 3.0, failed: tuple | None = FAILED) -> dict:
    """Write every report input under ``root``; returns the ``inputs`` dict."""
    rng = np.random.default_rng(7)
    root = Path(root)
    (root / "metrics").mkdir(parents=True, exist_ok=True)
    tests = [(t, m) for t in TERRAINS for m in MOTIONS]
    runs, stats, traces = [], [], []
    for e in ENGINES:
        for t, m in tests:
            bad = failed is not None and (e, t, m) == tuple(failed)
            status = "failed" if bad else "ok"
            reasons = "base_link below the ground at t=2.31 s (fell through)" if bad else ""
            wall = seconds / (3.1 if e == "mujoco" else 1.7)
            runs.append({"engine": e, "terrain": t, "motion": m, "sim_time": seconds, "wall_time": wall,
                         "cpu_time": wall * 0.98, "steps": int(seconds * 1000),
                         "steps_per_s": seconds * 1000 / wall, "real_time_factor": seconds / wall,
                         "status": status, "reasons": reasons,
                         "engine_version": "3.2.6" if e == "pybullet" else "3.3.0",
                         "config_hash": "ab12cd34" if e == "pybullet" else "ef56ab78"})
            frame = _trace(e, t, m, seconds, rng)
            for q, cols in (("angular", ("wx", "wy", "wz")), ("linear", ("ax", "ay", "az"))):
                for axis, c in zip("xyz", cols):
                    vals = np.sort(frame[c].to_numpy())
                    k = max(1, round(0.01 * vals.size))
                    stats.append({"engine": e, "terrain": t, "motion": m, "quantity": q, "axis": axis,
                                  "mean": float(vals.mean()), "range": float(vals[-k:].mean() - vals[:k].mean()),
                                  "status": status})
            if not bad:
                path = root / "traces" / e / t / f"{m}.parquet"
                write_trace(frame, {"engine": e, "engine_version": runs[-1]["engine_version"], "terrain": t,
                                    "motion": m, "timestep": 0.001, "seed": 1, "wall_time": wall,
                                    "cpu_time": wall, "steps": int(seconds * 1000),
                                    "health": {"status": "ok", "reasons": []}}, path)
                traces.append(str(path))
    pd.DataFrame(runs).to_csv(root / "metrics" / "runs.csv", index=False)
    pd.DataFrame(stats).to_csv(root / "metrics" / "trace_stats.csv", index=False)

    ref = []
    real = {"angular": {"x": (0.78, -0.11), "y": (1.2, 0.01), "z": (0.45, -0.06)},
            "linear": {"x": (12.2, -0.18), "y": (11.3, -0.10), "z": (11.8, 11.5)}}
    for q, axes in real.items():
        for axis, (rng_, mean) in axes.items():
            ref.append({"terrain": "gravel", "motion": "straight", "quantity": q, "axis": axis,
                        "mean": mean, "range": rng_, "source": "Farley et al. 2022, Tables 6-7"})
    pd.DataFrame(ref).to_csv(root / "metrics" / "reference_stats.csv", index=False)

    st = pd.DataFrame(stats)
    per_test, errors = [], []
    for e in ENGINES:
        for q in ("angular", "linear"):
            total = 0.0
            for axis in "xyz":
                s = st[(st.engine == e) & (st.terrain == "gravel") & (st.motion == "straight")
                       & (st.quantity == q) & (st.axis == axis)].iloc[0]
                rr, mm = real[q][axis]
                re_, me = abs(s["range"] - rr), abs(s["mean"] - mm)
                per_test.append({"engine": e, "terrain": "gravel", "motion": "straight", "quantity": q,
                                 "axis": axis, "range_error": re_, "mean_error": me, "total_error": re_ + me})
                total += re_ + me
            errors.append({"engine": e, "quantity": q, "error": total, "unit": "rad/s" if q == "angular" else "m/s^2",
                           "n_tests": 1, "tests": "gravel/straight", "excluded": ""})
    pd.DataFrame(per_test).to_csv(root / "metrics" / "per_test_errors.csv", index=False)
    pd.DataFrame(errors).to_csv(root / "metrics" / "imu_errors.csv", index=False)

    rf = pd.DataFrame(runs)
    rf = rf[rf.status == "ok"].groupby("engine").agg(sim_time=("sim_time", "sum"), wall_time=("wall_time", "sum"),
                                                    n_runs=("sim_time", "size")).reset_index()
    rf["real_time_factor"] = rf.sim_time / rf.wall_time
    rf[["engine", "sim_time", "wall_time", "real_time_factor", "n_runs"]].to_csv(root / "metrics" / "rtf.csv", index=False)

    cpu = []
    for e, avg, intense in (("pybullet", 31.0, 97.0), ("mujoco", 18.5, 62.0)):
        p = root / "cpu" / f"{e}.json"
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(json.dumps({
            "engine": e,
            "definition": "CPU seconds per simulated second, % of one core; median of 5 repeats, bumps/straight, 10 s.",
            "average": {"robots": 1, "load_percent": avg, "repeats_percent": [avg - 1, avg, avg + 0.5, avg, avg + 2]},
            "intense": {"robots": 5, "load_percent": intense,
                        "repeats_percent": [intense - 3, intense, intense + 1, intense, intense + 4]},
        }))
        cpu.append(str(p))

    qual = {
        "pybullet": {"free": True, "open_source": True, "ros": "none", "languages": ["Python", "C/C++"],
                     "ui": "visualization", "model_formats": ["URDF", "SDF", "MJCF"],
                     "urdf_sdf_via_manual_plugin": False, "physics_engines": ["Bullet"],
                     "paper_simulators": ["CoppeliaSim", "MORSE"],
                     "sources": {"free": "https://github.com/bulletphysics/bullet3/blob/master/LICENSE.txt",
                                 "ros": "No official ROS package (checked index.ros.org)"},
                     "notes": {"ui": "The example browser shows the world; there is no editor."}},
        "mujoco": {"free": True, "open_source": True, "ros": "none", "languages": ["C/C++", "Python", "C#"],
                   "ui": "partial", "model_formats": ["MJCF", "URDF"], "urdf_sdf_via_manual_plugin": False,
                   "physics_engines": ["MuJoCo"], "paper_simulators": [],
                   "sources": {"free": "https://github.com/google-deepmind/mujoco/blob/main/LICENSE"}},
    }
    qpath = root / "qualitative.yaml"
    qpath.write_text(yaml.safe_dump(qual, sort_keys=False))

    from simpick.scoring import accuracy_scores, efficiency_scores, qualitative_scores, real_time_factor_scores
    err = pd.DataFrame(errors)
    scores = pd.DataFrame({e: qualitative_scores(qual[e]) for e in ENGINES}).T
    scores["real_time_factor"] = pd.Series(real_time_factor_scores(dict(zip(rf.engine, rf.real_time_factor))))
    scores["cpu_average"] = pd.Series(efficiency_scores({"pybullet": 31.0, "mujoco": 18.5}))
    scores["cpu_intense"] = pd.Series(efficiency_scores({"pybullet": 97.0, "mujoco": 62.0}))
    for q in ("angular", "linear"):
        sel = err[err.quantity == q]
        scores[f"imu_{q}"] = pd.Series(accuracy_scores(dict(zip(sel.engine, sel.error))))
    scores = scores[list(METRICS)].astype(float)
    scores.index.name = "engine"
    weighted_table(scores, DEFAULT_WEIGHTS).to_csv(root / "weighted.csv", index_label="engine")

    pub = write_outputs(load_published(), root / "published")
    return {
        "weighted": str(root / "weighted.csv"),
        "trace_stats": str(root / "metrics" / "trace_stats.csv"),
        "reference_stats": str(root / "metrics" / "reference_stats.csv"),
        "imu_errors": str(root / "metrics" / "imu_errors.csv"),
        "per_test_errors": str(root / "metrics" / "per_test_errors.csv"),
        "runs": str(root / "metrics" / "runs.csv"),
        "rtf": str(root / "metrics" / "rtf.csv"),
        "cpu": cpu,
        "qualitative": str(qpath),
        "table11": str(pub["table11"]),
        "table11_comparison": str(pub["table11_comparison"]),
        "worked_example": str(pub["worked_example"]),
        "traces": traces,
    }


PARAMS = {"weights": dict(DEFAULT_WEIGHTS), "config": CONFIG, "title": "Synthetic test report"}


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    from simpick.report import build_report

    root = tmp_path_factory.mktemp("report")
    inputs = write_synthetic_inputs(root / "in")
    html, pdf = root / "out" / "report.html", root / "out" / "report.pdf"
    build_report(inputs, PARAMS, html, pdf)
    return inputs, html, pdf


def test_import_is_cheap():
    import subprocess
    import sys

    code = "import sys, simpick.report; print(any(m in sys.modules for m in ('matplotlib', 'weasyprint', 'jinja2')))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_both_files_exist(built):
    _, html, pdf = built
    assert html.is_file() and html.stat().st_size > 10_000
    assert pdf.is_file() and pdf.stat().st_size > 10_000
    assert not list(html.parent.glob("*.partial"))


def test_ranking_table_has_engines_and_totals(built):
    inputs, html, _ = built
    text = html.read_text(encoding="utf-8")
    weighted = pd.read_csv(inputs["weighted"], index_col="engine")
    m = re.search(r'<table[^>]*id="ranking-table".*?</table>', text, re.S)
    assert m, "ranking table missing"
    table = m.group(0)
    for engine, row in weighted.iterrows():
        assert engine in table
        assert f"{row['total']:.3f}" in table
    # Ranked order: the first engine in the file appears first in the table.
    first, second = weighted.index[:2]
    assert table.index(first) < table.index(second)
    assert f"<b>{weighted.index[0]}</b> ranks first" in text


def test_summary_names_the_reference_tests(built):
    _, html, _ = built
    summary = re.search(r'<div class="summary".*?</div>', html.read_text(encoding="utf-8"), re.S).group(0)
    assert "gravel/straight" in summary
    assert "no real" in summary and "not in the accuracy scores" in summary
    for t in ("grass/straight", "bumps/circle"):
        assert t in summary


def test_self_contained(built):
    _, html, _ = built
    text = html.read_text(encoding="utf-8")
    assert not re.search(r"""src\s*=\s*["']?(https?:)?//""", text)
    assert not re.search(r"<link\b", text, re.I)
    assert not re.search(r"<script\b[^>]*\bsrc=", text, re.I)
    assert "@import" not in text and "url(http" not in text
    images = re.findall(r'<img src="data:image/png;base64,', text)
    # contributions + 6 IMU-statistics figures + 6 time series + 1 path figure
    assert len(images) >= 14
    assert len(text) < 8_000_000


def test_failed_run_is_reported(built):
    _, html, _ = built
    text = html.read_text(encoding="utf-8")
    assert "1 of 12 runs failed" in text
    assert "excluded from" in text and "the scores" in text
    assert "fell through" in text  # the reason
    assert re.search(r"<td>mujoco</td><td>bumps/circle</td><td class=\"fail\">failed</td>", text)


def test_published_sections(built):
    _, html, _ = built
    text = html.read_text(encoding="utf-8")
    assert 'id="table11"' in text and "mismatch" in text
    for number in ("32.145", "32.148", "1.237", "23.430", "23.390", "23.190"):
        assert number in text, number


def test_paths_and_command_table(built):
    _, html, _ = built
    text = html.read_text(encoding="utf-8")
    table = re.search(r'<table[^>]*id="endpoints-table".*?</table>', text, re.S).group(0)
    # 11 runs with a trace (the failed one has none), each one row.
    assert table.count("<tr>") - 1 == 11
    assert "commanded (no slip)" not in table and "Top-down paths" in text


def test_pdf_has_several_pages(built):
    import weasyprint

    _, html, pdf = built
    assert pdf.read_bytes()[:4] == b"%PDF"
    doc = weasyprint.HTML(filename=str(html)).render()
    assert len(doc.pages) > 1


def test_all_ok_and_optional_inputs_absent(tmp_path):
    from simpick.report import build_report

    inputs = write_synthetic_inputs(tmp_path / "in", seconds=1.0, failed=None)
    minimal = {k: inputs[k] for k in ("weighted", "runs")}
    html, pdf = tmp_path / "report.html", tmp_path / "report.pdf"
    build_report(minimal, {"config": CONFIG}, html, pdf)
    text = html.read_text(encoding="utf-8")
    assert "All 12 simulation runs passed the health checks" in text
    assert "No traces were given" in text
    assert pdf.read_bytes()[:4] == b"%PDF"


def test_missing_required_input_is_named(tmp_path):
    from simpick.errors import InputError
    from simpick.report import build_report

    with pytest.raises(InputError, match="runs"):
        build_report({"weighted": str(tmp_path / "w.csv")}, {}, tmp_path / "r.html", tmp_path / "r.pdf")
