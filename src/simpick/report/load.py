"""Read the report's inputs (files written by the other workflow rules) and check their columns."""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd
import yaml

from simpick.errors import InputError
from simpick.score.answer import ANSWER_COLUMNS
from simpick.score.contributions import CONTRIBUTION_COLUMNS, DRIVER_COLUMNS
from simpick.score.equivalence import OUTCOME_COLUMNS, pooled
from simpick.score.scoring import METRICS

# the first page's row per engine: every column but the per-metric ones, which the report reads from outcomes,
# and the failed runs, which reach the page in the answer's sentences (answer.yaml), not from these tables
FAILED_COLUMNS = ("runs_completed", "runs_failed", "runs_all", "failed_runs")
ANSWER_REQUIRED = tuple(
    c
    for c in ANSWER_COLUMNS
    if not c.endswith(("_outcome", "_diff", "_low", "_high", "_margin")) and c not in FAILED_COLUMNS
)

COLUMNS: dict[str, tuple[str, ...]] = {
    "weighted": (*METRICS, "total", "excluded", "rank"),
    "runs": (
        "engine",
        "terrain",
        "motion",
        "sim_time",
        "wall_time",
        "cpu_time",
        "steps",
        "steps_per_s",
        "real_time_factor",
        "status",
        "reasons",
    ),
    "trace_stats": ("engine", "terrain", "motion", "quantity", "axis", "mean", "range", "status"),
    "reference_stats": ("terrain", "motion", "quantity", "axis", "mean", "range", "source"),
    "imu_errors": ("engine", "quantity", "error", "unit", "n_tests", "tests", "excluded"),
    "per_test_errors": ("engine", "terrain", "motion", "quantity", "axis", "range_error", "mean_error", "total_error"),
    "detail": (
        "engine",
        "terrain",
        "motion",
        "quantity",
        "axis",
        "mean",
        "range",
        "status",
        "ref_mean",
        "ref_range",
        "source",
        "range_error",
        "mean_error",
        "total_error",
    ),
    "rtf": ("engine", "sim_time", "wall_time", "real_time_factor", "n_runs"),
    "table11": (*METRICS, "total", "total_from_published_scores", "published_total"),
    "table11_comparison": ("simulator", "metric", "published", "recomputed", "difference", "matches"),
    "sweep": (
        "terrain_class",
        "engine",
        "timestep",
        "n_segments",
        "n_failed",
        "n_compared",
        "excluded",
        "error_angular",
        "error_linear",
        "gain_error",
        "real_time_factor",
        "steps_per_s",
    ),
    "calibration": (
        "terrain_class",
        "engine",
        "set",
        "n_units",
        "n_runs",
        "objective_configured",
        "objective_calibrated",
        "change",
        "parameters",
        "rank_configured",
        "rank_calibrated",
    ),
    "calibration_turning": (
        "terrain_class",
        "engine",
        "variant",
        "n_runs",
        "gain_real",
        "gain_sim",
        "gain_ratio",
        "gain_error",
        "gain_error_low",
        "gain_error_high",
        "separation_multiplier",
        "separation_multiplier_real",
    ),
    "calibration_target": (
        "engine",
        "is_engine",
        "n_runs",
        "error_calibrated",
        "error_configured",
        "error_reference",
        "p_vs_configured",
        "p_vs_reference",
        "classes_off_gain",
        "meets",
        "best",
    ),
    "validation": (
        "engine",
        "case",
        "kind",
        "quantity",
        "unit",
        "engine_value",
        "analytic_value",
        "error",
        "error_kind",
        "tolerance",
        "passed",
        "status",
    ),
    "validation_gains": (
        "engine",
        "v",
        "w",
        "mu",
        "analytic",
        "n_left",
        "left_mean",
        "left_min",
        "left_max",
        "n_right",
        "right_mean",
        "right_min",
        "right_max",
        "spread",
        "headings",
    ),
    # real robot data (rules/real.smk, simpick.compare.real)
    "accuracy_errors": ("engine", "quantity", "error", "unit", "n_tests", "tests", "excluded"),
    "accuracy_per_test": ("engine", "terrain_class", "segment", "run", "status"),
    "segments": (
        "segment",
        "terrain_class",
        "run",
        "kind",
        "t_start",
        "t_end",
        "settle",
        "duration",
        "v_left",
        "v_right",
        "v",
        "w",
        "yaw_rate_gain",
    ),
    "segments_per_test": (
        "engine",
        "terrain_class",
        "segment",
        "run",
        "kind",
        "status",
        "reasons",
        "yaw_rate_gain_real",
    ),
    "segments_summary": ("engine", "terrain_class", "n_tests"),
    "segments_pairwise": (
        "terrain_class",
        "figure",
        "engine_a",
        "engine_b",
        "mean_a_minus_b",
        "low",
        "high",
        "verdict",
    ),
    "segments_imu_errors": ("engine", "quantity", "error", "unit", "n_tests", "tests", "excluded"),
    "replay_per_window": ("engine", "terrain_class", "run", "status", "reasons"),
    "replay_per_test": ("engine", "terrain_class", "segment", "run", "kind", "status", "reasons"),
    "replay_summary": ("engine", "terrain_class", "n_tests"),
    "replay_pairwise": ("terrain_class", "figure", "engine_a", "engine_b", "mean_a_minus_b", "low", "high", "verdict"),
    "replay_imu_errors": ("engine", "quantity", "error", "unit", "n_tests", "tests", "excluded"),
    # simpick's verdict (simpick.score.verdict): the report prints these, it computes none of them
    "verdict_table": (
        "metric",
        "label",
        "unit",
        "model",
        "is_engine",
        "n_runs",
        "mean",
        "low",
        "high",
        "rank",
        "next",
        "p_to_next",
        "separates_from_next",
        "runs_needed",
        "note",
    ),
    "verdict_separation": ("metric", "label", "method", "n_runs", "best", "second", "separates", "statement"),
    "verdict_ranking": ("engine", "total", "total_low", "total_high", "share_first", "n_runs"),
    "verdict_discrimination": (
        "quantity",
        "engine",
        "error",
        "floor",
        "engine_part",
        "floor_share",
        "score",
        "score_low",
        "score_high",
        "spread",
        "half_width",
        "separates",
        "n_runs",
        "floor_models",
    ),
    "verdict_metrics": ("run", "model", "metric", "value"),
    # the paper's weighted table cell by cell (simpick.score.contributions)
    "contributions": tuple(CONTRIBUTION_COLUMNS),
    # what puts the leader ahead of each engine, metric by metric (simpick.score.contributions.drivers)
    "drivers": tuple(DRIVER_COLUMNS),
    # the answer: every engine against the best per real-data metric, and the first page's row per engine
    # note: free text, optional
    "verdict_outcomes": tuple(c for c in OUTCOME_COLUMNS if c != "note" and c not in FAILED_COLUMNS),
    "verdict_answer": ANSWER_REQUIRED,
    "verdict_headings": (
        "model",
        "test",
        "start_heading_deg",
        "yaw_rate_gain_sim",
        "yaw_rate_gain_reference",
        "gain_ratio",
    ),
    # where each lab run ended against the command (rule figure_paths, beside its figure)
    "endpoints": ("engine", "terrain", "motion", "t", "dist", "dyaw_deg", "v_cmd", "w_cmd", "v_mean", "w_mean"),
}

# The real-data sets: one per way of comparing with the real robot (simpick.compare.real).
REAL_SETS: tuple[str, ...] = ("segments", "replay")
REAL_TABLES: tuple[str, ...] = ("per_test", "summary", "pairwise", "imu_errors")
VERDICT_TABLES: tuple[str, ...] = (
    "metrics",
    "table",
    "separation",
    "ranking",
    "discrimination",
    "headings",
    "outcomes",
    "answer",
)

# Text columns: read as strings, an empty cell becomes "" rather than NaN.
TEXT_COLUMNS = {
    "excluded",
    "reasons",
    "tests",
    "status",
    "source",
    "engine",
    "terrain",
    "motion",
    "quantity",
    "axis",
    "unit",
    "engine_version",
    "config_hash",
    "simulator",
    "metric",
    "terrain_class",
    "segment",
    "run",
    "kind",
    "figure",
    "engine_a",
    "engine_b",
    "verdict",
    "dataset",
    "case",
    "error_kind",
    "model",
    "next",
    "note",
    "label",
    "method",
    "best",
    "second",
    "statement",
    "floor_models",
    "outcome",
    "margin_basis",
    "group",
    "mechanics",
    "mechanics_note",
    "paper_flag",
}
# Bool columns per table: True/False in the CSV, read as bool (an empty cell as False); in every table a
# summary's <figure>_closest (simpick.compare.real.class_verdicts).
BOOL_COLUMNS = {
    "contributions": {"excluded"},
    "verdict_outcomes": {"is_best", "recommendable"},
    "table11_comparison": {"matches"},
}


@dataclass
class Trace:
    engine: str
    terrain: str
    motion: str
    frame: pd.DataFrame
    meta: dict
    path: str


@dataclass
class ReportData:
    weighted: pd.DataFrame
    runs: pd.DataFrame
    contributions: pd.DataFrame | None = None  # the weighted table cell by cell (results/scores/contributions.csv)
    drivers: pd.DataFrame | None = None  # what puts the leader ahead of each engine (results/scores/drivers.csv)
    trace_stats: pd.DataFrame | None = None
    reference_stats: pd.DataFrame | None = None
    imu_errors: pd.DataFrame | None = None
    per_test_errors: pd.DataFrame | None = None
    rtf: pd.DataFrame | None = None
    cpu: list[dict] | None = None
    qualitative: dict | None = None
    table11: pd.DataFrame | None = None
    table11_comparison: pd.DataFrame | None = None
    worked_example: dict | None = None
    traces: list[Trace] | None = None
    # what the scores rest on (results/scores/provenance.yaml), the Eq. 7 totals it names and,
    # for real data, the per-test table beside them
    scores_provenance: dict | None = None
    accuracy_errors: pd.DataFrame | None = None
    accuracy_per_test: pd.DataFrame | None = None
    # engines against analytic mechanics (rules/validate.smk)
    validation: pd.DataFrame | None = None
    validation_gains: pd.DataFrame | None = None  # per engine, gain left / right over start headings
    # speed-accuracy sweep (rules/sweep.smk), when the study ran with one
    sweep: pd.DataFrame | None = None
    # calibration on training runs, judged on test runs (rules/calibration.smk), when run
    calibration: pd.DataFrame | None = None
    calibration_turning: pd.DataFrame | None = None  # held-out yaw-rate gains
    calibration_target: pd.DataFrame | None = None  # the turning target, per calibrated model
    # real robot data: the committed segment table, and per set ("segments", "replay") its tables
    segments: pd.DataFrame | None = None
    segments_provenance: dict | None = None
    real: dict[str, dict[str, pd.DataFrame]] = field(default_factory=dict)
    replay_per_window: pd.DataFrame | None = None
    real_turning: pd.DataFrame | None = None  # how the real robot turns (rule real_turning), per class
    # simpick's verdict (results/verdict/: simpick.score.verdict), table name -> table, and its headline
    verdict: dict[str, pd.DataFrame] = field(default_factory=dict)
    verdict_headline: dict | None = None
    verdict_sentences: dict | None = None  # answer.yaml: one sentence per user need
    tree: dict | None = None  # the decision tree (results/verdict/tree.json: simpick.score.tree)
    # real canonical logs and replay traces: paths only, read when the figures are drawn
    real_logs: list[str] | None = None
    replay_traces: list[str] | None = None
    # the figure rules' files (rules/report.smk): key (path under figures/, no suffix) -> PNG,
    # and the notes some of them write beside the PNG (key -> the JSON's mapping)
    figures: dict[str, str] = field(default_factory=dict)
    figure_notes: dict[str, dict] = field(default_factory=dict)
    endpoints: pd.DataFrame | None = None
    sources: dict[str, Any] = field(default_factory=dict)


def _path(name: str, value: Any) -> Path:
    if isinstance(value, (list, tuple)):
        if len(value) != 1:
            raise InputError(f"report input {name!r}", f"expected one path, got {len(value)}")
        value = value[0]
    p = Path(str(value))
    if not p.is_file():
        raise InputError(str(p), f"report input {name!r} does not exist", "run the rule that writes it first")
    return p


def _paths(name: str, value: Any) -> list[Path]:
    values = [value] if isinstance(value, (str, Path)) else list(value)
    out = []
    for v in values:
        p = Path(str(v))
        if not p.is_file():
            raise InputError(str(p), f"report input {name!r} does not exist", "run the rule that writes it first")
        out.append(p)
    return out


def _csv(name: str, path: Path, index: str | None = None) -> pd.DataFrame:
    try:
        head = pd.read_csv(path, nrows=0)
    except (pd.errors.EmptyDataError, pd.errors.ParserError, UnicodeDecodeError) as exc:
        raise InputError(str(path), f"not a readable CSV: {exc}") from None
    bools = {c for c in head.columns if c in BOOL_COLUMNS.get(name, ()) or c.endswith("_closest")}
    dtypes = {c: "string" for c in head.columns if (c in TEXT_COLUMNS or c.endswith("_outcome")) and c not in bools}
    df = pd.read_csv(path, dtype=dtypes, keep_default_na=True)
    for c in dtypes:
        df[c] = df[c].fillna("").astype(str)
    for c in bools:
        df[c] = df[c].astype(str).str.strip().str.lower().isin(["true", "1", "1.0"])
    have = set(df.columns)
    missing = [c for c in COLUMNS.get(name, ()) if c not in have]
    if missing:
        raise InputError(str(path), f"columns {missing} are missing", "rerun the rule that writes it")
    if index is not None:
        if index not in df.columns:
            # The index column may have been written without a name.
            first = df.columns[0]
            if first.startswith("Unnamed"):
                df = df.rename(columns={first: index})
            else:
                raise InputError(str(path), f"index column {index!r} is missing")
        df[index] = df[index].astype(str)
        df = df.set_index(index)
    return df


# The lab's per-axis table (results/metrics/lab/detail.csv: simpick.sources.lab) holds the
# simulated statistics, the paper's and the errors between them; the report reads three views of it.
DETAIL_VIEWS = {
    "trace_stats": lambda d: d[["engine", "terrain", "motion", "quantity", "axis", "mean", "range", "status"]],
    "reference_stats": lambda d: (
        d[d["ref_mean"].notna()]
        .drop_duplicates(["terrain", "motion", "quantity", "axis"])[
            ["terrain", "motion", "quantity", "axis", "ref_mean", "ref_range", "source"]
        ]
        .rename(columns={"ref_mean": "mean", "ref_range": "range"})
        .reset_index(drop=True)
    ),
    "per_test_errors": lambda d: d[d["total_error"].notna()][
        ["engine", "terrain", "motion", "quantity", "axis", "range_error", "mean_error", "total_error"]
    ].reset_index(drop=True),
}


def figure_key(path: str | Path) -> str:
    """A figure file's name in the report: its path under the last ``figures`` folder, no suffix
    (results/report/figures/traces/grass/straight.png -> traces/grass/straight)."""
    parts = Path(path).with_suffix("").parts
    if "figures" not in parts:
        return Path(path).stem
    i = len(parts) - 1 - parts[::-1].index("figures")
    return "/".join(parts[i + 1 :])


def load_inputs(inputs: Mapping[str, Any], required: tuple[str, ...] | None = None) -> ReportData:
    """Read every input that is given; raise :class:`InputError` for a missing required one
    (``required``: the report's by default; a figure job names what it draws from)."""
    from simpick.report.inputs import OPTIONAL_INPUTS, REQUIRED_INPUTS

    if required is None:
        required = REQUIRED_INPUTS
    for key in required:
        if inputs.get(key) in (None, "", []):
            raise InputError(f"report inputs[{key!r}]", "required input is not given")
    unknown = sorted(set(inputs) - set(REQUIRED_INPUTS) - set(OPTIONAL_INPUTS))
    if unknown:
        raise InputError("report inputs", f"unknown keys {unknown}")

    def given(key: str) -> bool:
        return inputs.get(key) not in (None, "", [])

    sources: dict[str, Any] = {}
    kw: dict[str, Any] = {}
    for key, index in (
        ("weighted", "engine"),
        ("runs", None),
        ("trace_stats", None),
        ("reference_stats", None),
        ("imu_errors", None),
        ("per_test_errors", None),
        ("rtf", None),
        ("table11", "simulator"),
        ("table11_comparison", None),
        ("endpoints", None),
    ):
        if given(key):
            p = _path(key, inputs[key])
            sources[key] = str(p)
            if key in DETAIL_VIEWS and "ref_mean" in pd.read_csv(p, nrows=0).columns:
                kw[key] = DETAIL_VIEWS[key](_csv("detail", p)).copy()
            else:
                kw[key] = _csv(key, p, index)

    for key in (
        "contributions",
        "drivers",
        "accuracy_errors",
        "accuracy_per_test",
        "segments",
        "replay_per_window",
        "validation",
        "validation_gains",
        "sweep",
        "calibration",
        "calibration_turning",
        "calibration_target",
        "real_turning",
    ):
        if given(key):
            p = _path(key, inputs[key])
            sources[key] = str(p)
            kw[key] = _csv(key, p)
    real: dict[str, dict[str, pd.DataFrame]] = {}
    for set_ in REAL_SETS:
        for table in REAL_TABLES:
            key = f"{set_}_{table}"
            if given(key):
                p = _path(key, inputs[key])
                sources[key] = str(p)
                real.setdefault(set_, {})[table] = _csv(key, p)
    kw["real"] = real
    verdict: dict[str, pd.DataFrame] = {}
    for table in VERDICT_TABLES:
        key = f"verdict_{table}"
        if given(key):
            p = _path(key, inputs[key])
            sources[key] = str(p)
            verdict[table] = _csv(key, p)
    if "outcomes" in verdict:  # the DRIVE comparison's outcomes where the answer rests on DRIVE: its pooled rows
        verdict["outcomes"] = pooled(verdict["outcomes"])
    kw["verdict"] = verdict
    for key in ("segments_provenance", "scores_provenance", "verdict_headline", "verdict_sentences"):
        if given(key):
            p = _path(key, inputs[key])
            try:
                with open(p, encoding="utf-8") as fh:
                    prov = yaml.safe_load(fh) or {}
            except yaml.YAMLError as exc:
                raise InputError(str(p), f"not valid YAML: {exc}") from None
            if not isinstance(prov, dict):
                raise InputError(str(p), "expected a mapping")
            kw[key] = prov
            sources[key] = str(p)
    for key in ("real_logs", "replay_traces"):
        if given(key):
            kw[key] = [str(p) for p in _paths(key, inputs[key])]
            sources[key] = kw[key]

    if given("figures"):
        figs, notes = {}, {}
        for p in _paths("figures", inputs["figures"]):
            if p.suffix == ".json":
                notes[figure_key(p)] = json.loads(p.read_text(encoding="utf-8"))
            else:
                figs[figure_key(p)] = str(p)
        kw["figures"], kw["figure_notes"] = figs, notes
        sources["figures"] = sorted(figs.values())

    runs = kw.get("runs")
    for col in ("engine_version", "config_hash"):
        if runs is not None and col not in runs.columns:
            runs[col] = ""

    if given("cpu"):
        cpu = []
        for p in _paths("cpu", inputs["cpu"]):
            try:
                rec = json.loads(p.read_text(encoding="utf-8"))
            except json.JSONDecodeError as exc:
                raise InputError(str(p), f"not valid JSON: {exc}") from None
            for k in ("engine", "average", "intense"):
                if k not in rec:
                    raise InputError(str(p), f"key {k!r} is missing")
            cpu.append(rec)
        kw["cpu"] = cpu
        sources["cpu"] = [str(p) for p in _paths("cpu", inputs["cpu"])]

    if given("qualitative"):
        p = _path("qualitative", inputs["qualitative"])
        with open(p, encoding="utf-8") as fh:
            q = yaml.safe_load(fh) or {}
        if not isinstance(q, dict):
            raise InputError(str(p), "expected a mapping engine -> fact record")
        if isinstance(q.get("engines"), dict):
            q = q["engines"]
        kw["qualitative"] = {str(k): v for k, v in q.items() if isinstance(v, dict)}
        sources["qualitative"] = str(p)

    if given("tree"):
        from simpick.score.tree import read_tree

        p = _path("tree", inputs["tree"])
        kw["tree"] = read_tree(str(p))
        sources["tree"] = str(p)

    if given("worked_example"):
        p = _path("worked_example", inputs["worked_example"])
        try:
            kw["worked_example"] = json.loads(p.read_text(encoding="utf-8"))
        except json.JSONDecodeError as exc:
            raise InputError(str(p), f"not valid JSON: {exc}") from None
        sources["worked_example"] = str(p)

    if given("traces"):
        from simpick.simulate.traces import read_trace

        traces = []
        for p in _paths("traces", inputs["traces"]):
            frame, meta = read_trace(p)
            # results/traces/<source>/{engine}/{terrain}/{motion}.parquet; metadata wins when present.
            engine = str(meta.get("engine") or p.parent.parent.name)
            terrain = str(meta.get("terrain") or p.parent.name)
            motion = str(meta.get("motion") or p.stem)
            traces.append(Trace(engine, terrain, motion, frame, meta, str(p)))
        kw["traces"] = traces
        sources["traces"] = [t.path for t in traces]

    kw.setdefault("weighted", None)
    kw.setdefault("runs", None)
    return ReportData(sources=sources, **kw)
