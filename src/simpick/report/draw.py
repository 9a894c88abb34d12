"""The figure jobs: each figure rule (rules/report.smk) draws one figure, or one figure of a
family over a wildcard, from the workflow's tables and traces into results/report/figures/.

The report job only embeds these files; no figure shows the weights (the page draws the weighted
contributions itself from the scores job's table), so neither a weight edit nor a template edit redraws one.
Every job writes its
file: with nothing to draw, a small panel says why (:func:`simpick.report.figures.nothing_to_draw`).

Engine colours come from ``engines`` (the study's engines, then its baselines, each sorted by
name: rules/report.smk FIGURE_ENGINES), never from the ranking, so an engine keeps its colour when a weight edit
reorders the ranking; the
report's swatches use the same list (:func:`colors`).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from simpick.inputs.terrain import TILES
from simpick.report import figures
from simpick.report.load import load_inputs
from simpick.report.params import (
    FigureParams,
    PathsFigureParams,
    RealGainFigureParams,
    ReplayFigureParams,
    ReportConfig,
)


def colors(engines: Sequence[str] | None, seen: Sequence[str] = ()) -> dict[str, str]:
    """Engine -> colour: ``engines`` first, in their order, then any other engine seen."""
    order = list(dict.fromkeys([*(engines or []), *seen]))
    return figures.engine_colors(order)


def _order(engines: Sequence[str] | None, seen: Sequence[str]) -> list[str]:
    return [e for e in (engines or []) if e in set(seen)] + [e for e in dict.fromkeys(seen) if e not in (engines or [])]


def _status(runs: pd.DataFrame | None) -> dict[tuple[str, str, str], str]:
    if runs is None:
        return {}
    return {(r["engine"], r["terrain"], r["motion"]): str(r["status"]).strip().lower() for r in runs.to_dict("records")}


def _failed(status: Mapping, engine: str, terrain: str, motion: str) -> bool:
    return status.get((engine, terrain, motion), "ok") != "ok"


# --------------------------------------------------------------------------
# Lab study
# --------------------------------------------------------------------------


def test_label(terrain: str, motion: str) -> str:
    return f"{terrain}/{motion}"


def weights_of(raw: Mapping[str, float] | None) -> dict[str, float]:
    """The report's weights (the paper's defaults when None), one per metric."""
    from simpick.errors import InputError
    from simpick.score.scoring import DEFAULT_WEIGHTS, METRICS

    if raw is None:
        return dict(DEFAULT_WEIGHTS)
    missing = [m for m in METRICS if m not in raw]
    if missing:
        raise InputError("the report's weights (rule report's params)", f"metrics {missing} have no weight")
    return {m: float(raw[m]) for m in METRICS}


def _typed(model: type[FigureParams], params: Mapping[str, Any] | FigureParams) -> Any:
    """A figure's params as its rule's model (validated where given as a mapping, less ``code``, the rules'
    rerun trigger)."""
    if isinstance(params, model):
        return params
    return model.model_validate({k: v for k, v in dict(params).items() if k != "code"})


def _endpoints(config: ReportConfig, motion: str, series, engines: list[str]):
    """Per engine: where the run ended against where the no-slip command would have taken it."""
    spec = config.motions.get(motion)  # a mapping keyed by the study's motion names
    have = {label: frame for label, _, frame in series}
    out = []
    for e in engines:
        frame = have.get(e)
        if frame is None or not len(frame):
            out.append(None)
            continue
        if spec is None:
            out.append(None)
            continue
        try:
            t_end = float(frame["time"].iloc[-1])
            cmd = figures.commanded_path(spec.start, spec.v, spec.w, t_end)
            yaw_cmd = spec.start[2] + spec.w * t_end
        except (KeyError, ValueError, IndexError):
            out.append(None)
            continue
        dx = float(frame["x"].iloc[-1]) - float(cmd[-1, 0])
        dy = float(frame["y"].iloc[-1]) - float(cmd[-1, 1])
        dyaw = (float(frame["yaw"].iloc[-1]) - yaw_cmd + math.pi) % (2 * math.pi) - math.pi
        out.append(
            {
                "engine": e,
                "t": t_end,
                "dist": math.hypot(dx, dy),
                "dyaw_deg": math.degrees(dyaw),
                "v_cmd": spec.v,
                "w_cmd": spec.w,
                "v_mean": float(frame["v_forward"].mean()),
                "w_mean": float(frame["yaw_rate"].mean()),
            }
        )
    return out


def _strip(config: ReportConfig, terrain: str):
    if terrain not in config.terrains:
        return None
    # a strip's settings as configured (simpick.report.params.ReportConfig: the config's Terrain validated them)
    tiles = int((config.terrains[terrain] or {}).get("tiles", TILES))
    return (0.0, float(tiles), -0.5, 0.5)


def _commanded(config: ReportConfig, motion: str):
    spec = config.motions.get(motion)
    if spec is None:
        return None
    try:
        return figures.commanded_path(spec.start, spec.v, spec.w, spec.duration)
    except ValueError:
        return None


def imu_stats(inputs: Mapping[str, Any], params: FigureParams, terrain: str, motion: str, output: str) -> None:
    """One lab test's IMU mean and range per axis, every healthy engine and the paper's reference."""
    p = _typed(FigureParams, params)
    data = load_inputs(
        {k: inputs[k] for k in ("trace_stats", "reference_stats", "runs") if k in inputs}, required=("trace_stats",)
    )
    ts, ref, status = data.trace_stats, data.reference_stats, _status(data.runs)
    palette = colors(p.engines, list(ts["engine"]))
    series = []
    for e in _order(p.engines, list(ts["engine"])):
        sel = ts[(ts["engine"] == e) & (ts["terrain"] == terrain) & (ts["motion"] == motion)]
        if not len(sel) or _failed(status, e, terrain, motion) or (sel["status"].str.lower() != "ok").any():
            continue
        series.append((e, palette[e], sel))
    if ref is not None:
        rsel = ref[(ref["terrain"] == terrain) & (ref["motion"] == motion)]
        if len(rsel):
            series.append((figures.REFERENCE_LABEL, figures.REFERENCE_COLOR, rsel))
    if series:
        figures.imu_stats_figure(series, output)
    else:
        figures.nothing_to_draw(output, f"no engine finished {terrain}/{motion} healthily")


def traces(inputs: Mapping[str, Any], params: FigureParams, terrain: str, motion: str, output: str) -> None:
    """One lab test's IMU time series, every engine whose run passed the health checks."""
    p = _typed(FigureParams, params)
    data = load_inputs({"traces": list(inputs["traces"]), "runs": inputs["runs"]}, required=("traces", "runs"))
    status = _status(data.runs)
    have = {t.engine: t for t in data.traces if (t.terrain, t.motion) == (terrain, motion)}
    palette = colors(p.engines, list(have))
    series = [
        (e, palette[e], have[e].frame) for e in _order(p.engines, list(have)) if not _failed(status, e, terrain, motion)
    ]
    if series:
        figures.timeseries_figure(series, output)
    else:
        figures.nothing_to_draw(output, f"no engine finished {terrain}/{motion} healthily")


def _tests(config: ReportConfig, seen: Sequence[tuple[str, str]]) -> list[tuple[str, str]]:
    """The tests in config order (terrain, then motion); any other test after them."""
    terrains, motions = list(config.terrains), list(config.motions)
    seen = list(dict.fromkeys(seen))

    def key(tm):
        t, m = tm
        return (
            terrains.index(t) if t in terrains else len(terrains),
            motions.index(m) if m in motions else len(motions),
            seen.index(tm),
        )

    return sorted(seen, key=key)


def paths(inputs: Mapping[str, Any], params: PathsFigureParams, output: str, endpoints: str) -> None:
    """Top-down paths of every test in one figure, and beside it the table of where each run
    ended against the no-slip command (the report's endpoints table)."""
    p = _typed(PathsFigureParams, params)
    config = p.config
    data = load_inputs({"traces": list(inputs["traces"]), "runs": inputs["runs"]}, required=("traces", "runs"))
    status = _status(data.runs)
    by_test = {(t.engine, t.terrain, t.motion): t for t in data.traces}
    engines = _order(p.engines, [t.engine for t in data.traces] + list(data.runs["engine"]))
    palette = colors(p.engines, engines)
    tests = _tests(
        config, list(zip(data.runs["terrain"], data.runs["motion"])) + [(t.terrain, t.motion) for t in data.traces]
    )
    panels, rows = [], []
    for t, m in tests:
        series = [
            (e, palette[e], by_test[(e, t, m)].frame)
            for e in engines
            if (e, t, m) in by_test and not _failed(status, e, t, m)
        ]
        panels.append(
            {
                "title": test_label(t, m),
                "series": series,
                "strip": _strip(config, t),
                "commanded": _commanded(config, m),
            }
        )
        rows += [dict(end, terrain=t, motion=m) for end in _endpoints(config, m, series, engines) if end]
    columns = ["engine", "terrain", "motion", "t", "dist", "dyaw_deg", "v_cmd", "w_cmd", "v_mean", "w_mean"]
    Path(endpoints).parent.mkdir(parents=True, exist_ok=True)
    pd.DataFrame(rows, columns=columns).to_csv(endpoints, index=False)
    if any(p["series"] for p in panels):
        motions = list(dict.fromkeys(m for _, m in tests))
        figures.paths_figure(panels, output, ncols=max(1, min(len(motions), 3)))
    else:
        figures.nothing_to_draw(output, "no run finished healthily")


def validation(inputs: Mapping[str, Any], params: FigureParams, output: str) -> None:
    """Yaw-rate gain against commanded yaw rate, left and right turns with their spread over start
    headings, every engine and the quasi-static Coulomb gain."""
    from simpick.report.validation import gain_series

    p = _typed(FigureParams, params)
    data = load_inputs({"validation_gains": inputs["validation_gains"]}, required=("validation_gains",))
    series, analytic, _ = gain_series(data.validation_gains, list(p.engines))
    if series:
        figures.validation_gain_figure(series, analytic, colors(p.engines, [e for e, _ in series]), output)
    else:
        figures.nothing_to_draw(output, "no yaw-rate-gain case at v = 0.5 m/s")


def sweep(inputs: Mapping[str, Any], params: FigureParams, output: str) -> None:
    """Per terrain class: real-data error against real-time factor over the sweep's timesteps."""
    from simpick.report.sweep import sweep_panels

    p = _typed(FigureParams, params)
    data = load_inputs({"sweep": inputs["sweep"]}, required=("sweep",))
    panels = sweep_panels(data.sweep, list(p.engines))
    if panels:
        figures.sweep_figure(panels, colors(p.engines, list(data.sweep.engine)), output)
    else:
        figures.nothing_to_draw(output, "no sweep point finished healthily")


# --------------------------------------------------------------------------
# Real robot data
# --------------------------------------------------------------------------


def real_gain(inputs: Mapping[str, Any], params: RealGainFigureParams, output: str) -> None:
    """Yaw-rate gain per terrain class, the real robot against every model, one panel per set."""
    from simpick.report import real

    p = _typed(RealGainFigureParams, params)
    data = load_inputs(dict(inputs), required=())
    engines = _order(
        p.engines,
        [e for s in data.real.values() for t in s.values() if "engine" in t.columns for e in t["engine"]],
    )
    panels = real.gain_panels(data, p, engines, colors(p.engines, engines))
    if panels:
        figures.gain_figure(panels, output)
    else:
        figures.nothing_to_draw(output, "no terrain class has a yaw-rate gain")


def _read_real_series(path: str, track: float):
    from simpick.real.logs import read_canonical

    log = read_canonical(path)
    imu = log.imu[["time", "ax", "ay", "az", "wx", "wy", "wz"]].copy()
    cmd = log.wheel_commands(track)
    commanded = pd.DataFrame({"time": cmd["time"].to_numpy(), "w": (cmd["v_right"] - cmd["v_left"]).to_numpy() / track})
    return imu, commanded, log.meta


def _rate(frame: pd.DataFrame) -> float:
    dt = np.diff(frame["time"].to_numpy(dtype=float))
    dt = dt[dt > 0]
    return float(1.0 / np.median(dt)) if dt.size else 100.0


def _mean_psd(signals: list[tuple[np.ndarray, float]]):
    """Mean Welch PSD over runs (each at its own rate; runs on another grid are left out)."""
    from simpick.compare.realmetrics import psd, psd_segment

    spectra = []
    for x, rate in signals:
        if len(x) < psd_segment(rate):
            continue
        spectra.append(psd(x, rate))
    if not spectra:
        return None
    f0 = spectra[0][0]
    same = [p for f, p in spectra if f.shape == f0.shape and np.allclose(f, f0)]
    return f0, np.mean(same, axis=0), len(same)


def _f(x: Any) -> float:
    try:
        return float(x)
    except (TypeError, ValueError):
        return float("nan")


def replay(inputs: Mapping[str, Any], params: ReplayFigureParams, cls: str, output: str, notes: str) -> None:
    """One terrain class of the full replay: time plots of one representative run and the mean
    vertical-acceleration spectra over the class's runs. ``notes`` (JSON) tells the report which
    run was drawn and why, what the spectra average over and what was left out."""
    from simpick.compare.realmetrics import LOWPASS_HZ, PSD_BAND_HZ
    from simpick.report.real import TIME_PLOT_MAX_S
    from simpick.simulate.traces import read_metadata, read_trace

    settings = _typed(ReplayFigureParams, params)
    cls = cls.lower()
    data = load_inputs(dict(inputs), required=("real_logs",))
    track = settings.track
    logs = {Path(p).stem: p for p in data.real_logs or [] if Path(p).parent.name.lower() == cls}
    traces: dict[tuple[str, str], tuple[str, dict]] = {}
    for p in data.replay_traces or []:
        meta = read_metadata(p)
        path = Path(p)
        if str(meta.get("terrain") or path.parent.name).lower() != cls:
            continue
        engine = str(meta.get("engine") or path.parent.parent.name)
        traces[(engine, str(meta.get("run") or path.stem))] = (p, meta)
    engines = _order(settings.engines, [e for e, _ in traces])
    palette = colors(settings.engines, engines)
    runs = sorted(logs)
    if not runs:
        figures.nothing_to_draw(output, f"no real log of class {cls}")
        Path(notes).write_text(json.dumps({"cls": cls, "drawn": False}))
        return
    per_test = data.real.get("replay", {}).get("per_test")
    # the representative run: Eq. 7 angular error (mean over engines) nearest the class median
    chosen, why = runs[0], "the first run of the class"
    if per_test is not None and "error_angular" in per_test.columns:
        ok = per_test[
            (per_test["terrain_class"] == cls) & (per_test["status"].str.lower() == "ok") & per_test["run"].isin(runs)
        ]
        turning = ok
        if "yaw_rate_gain_real" in ok.columns:
            turning = ok[np.isfinite([_f(x) for x in ok["yaw_rate_gain_real"]])]
        pool, among = (turning, "of the runs that turn, ") if len(turning) else (ok, "")
        if len(pool):
            per_run = pool.groupby("run")["error_angular"].mean()
            med = float(per_run.median())
            chosen = str((per_run - med).abs().sort_values(kind="mergesort").index[0])
            why = f"{among}the one whose Eq. 7 angular error, averaged over the engines, is nearest the class median"

    def healthy(hit) -> bool:
        return str(((hit[1].get("health") or {}).get("status")) or "ok").lower() == "ok"

    imu, commanded, _ = _read_real_series(logs[chosen], track)
    rate = _rate(imu)
    series = [(figures.REAL_LABEL, figures.REAL_COLOR, imu)]
    skipped, frames = [], {}
    for e in engines:
        hit = traces.get((e, chosen))
        if hit is None:
            skipped.append(f"{e} (no replay trace)")
        elif not healthy(hit):
            skipped.append(f"{e} (run failed: {hit[1]['health'].get('status')})")
        else:
            frames[e] = read_trace(hit[0])[0]
            series.append((e, palette[e], frames[e]))
    # spectra: mean over every run of the class that has the real log and the engine's healthy trace
    psd_series, n_psd = [], {}
    real_sig = [
        (
            (imu if r == chosen else _read_real_series(logs[r], track)[0])["az"].to_numpy(dtype=float),
            _rate(imu if r == chosen else _read_real_series(logs[r], track)[0]),
        )
        for r in runs
    ]
    m = _mean_psd(real_sig)
    if m:
        psd_series.append((figures.REAL_LABEL, figures.REAL_COLOR, m[0], m[1]))
        n_psd[figures.REAL_LABEL] = m[2]
    for e in engines:
        sig = []
        for r in runs:
            hit = traces.get((e, r))
            if hit is None or not healthy(hit):
                continue
            frame = frames[e] if r == chosen and e in frames else read_trace(hit[0])[0]
            sig.append((frame["az"].to_numpy(dtype=float), _rate(frame)))
        m = _mean_psd(sig)
        if m:
            psd_series.append((e, palette[e], m[0], m[1]))
            n_psd[e] = m[2]
    duration = float(imu["time"].iloc[-1]) if len(imu) else 0.0
    t_max = TIME_PLOT_MAX_S if duration > TIME_PLOT_MAX_S else None
    band = (PSD_BAND_HZ[0], min(PSD_BAND_HZ[1], rate / 2))  # a slower IMU's spectrum ends at Nyquist
    figures.replay_figure(series, psd_series, commanded, rate, output, t_max=t_max, band=band, cutoff_hz=LOWPASS_HZ)
    counts = sorted(set(n_psd.values()))
    psd_text = (
        f"{counts[0]} run{'s' if counts[0] != 1 else ''}"
        if len(counts) == 1
        else ", ".join(f"{label} {n}" for label, n in n_psd.items()) + " runs"
    )
    Path(notes).write_text(
        json.dumps(
            {
                "cls": cls,
                "drawn": True,
                "label": cls.replace("_", " "),
                "run": chosen,
                "why": why,
                "n_runs": len(runs),
                "psd_text": psd_text,
                "duration": duration,
                "t_max": t_max,
                "skipped": skipped,
                "n_psd": n_psd,
                "lowpass_hz": LOWPASS_HZ,
                "band": list(band),
            },
            indent=1,
        )
    )


# The figure rules, by name: rule -> (function, wildcard names passed after params, output names, params model)
def real_turning(inputs: Mapping[str, Any], params: FigureParams, output: str) -> None:
    """How the real robot turns: the turning windows of a replayed dataset (rule real_turning)."""
    windows = pd.read_csv(inputs["windows"])
    if windows.empty:
        figures.nothing_to_draw(output, "no steady-command turning window in this dataset")
    else:
        figures.turning_figure(windows, output)


def answer(inputs: Mapping[str, Any], params: FigureParams, output: str) -> None:
    """The first page's figure: per real-data metric and engine, the values on every real run and
    the difference to the best engine with its interval, the margin shaded (the verdict's tables:
    outcomes.csv and the per-run metrics.csv)."""
    p = _typed(FigureParams, params)
    data = load_inputs({"verdict_outcomes": inputs["outcomes"], "verdict_metrics": inputs["metrics"]}, required=())
    outcomes, per_run = data.verdict["outcomes"], data.verdict["metrics"]
    seen = list(dict.fromkeys(outcomes["engine"]))
    engines = _order(p.engines, seen)
    panels = []
    for metric, g in outcomes.groupby("metric", sort=False):
        rows = {r["engine"]: r for r in g.to_dict("records")}
        runs = per_run[per_run["metric"] == metric]
        measured = [e for e in engines if e in rows and str(rows[e]["outcome"]) != "not measurable"]
        first = g.iloc[0]
        panels.append(
            {
                "label": str(first["label"]),
                "unit": str(first["unit"]),
                "margin": _value(first["margin"]),
                "engines": [
                    {
                        "engine": e,
                        "values": [_value(v) for v in runs.loc[runs["model"] == e, "value"]],
                        "mean": _value(rows[e]["mean"]),
                        "diff": _value(rows[e]["diff_to_best"]),
                        "low": _value(rows[e]["diff_low"]),
                        "high": _value(rows[e]["diff_high"]),
                        "outcome": str(rows[e]["outcome"]),
                        "is_best": bool(rows[e]["is_best"]),
                        "recommendable": bool(rows[e]["recommendable"]),
                    }
                    for e in measured
                ],
            }
        )
    if not any(p["engines"] for p in panels):
        figures.nothing_to_draw(output, "no real-data metric was measured for any engine")
        return
    figures.answer_figure(panels, colors(p.engines, seen), output)


def _value(x: Any) -> float | None:
    try:
        v = float(x)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


RULES = {
    "figure_answer": (answer, (), ("png",), FigureParams),
    "figure_imu_stats": (imu_stats, ("lab_terrain", "lab_motion"), ("png",), FigureParams),
    "figure_traces": (traces, ("terrain", "motion"), ("png",), FigureParams),
    "figure_paths": (paths, (), ("png", "endpoints"), PathsFigureParams),
    "figure_validation": (validation, (), ("png",), FigureParams),
    "figure_sweep": (sweep, (), ("png",), FigureParams),
    "figure_real_gain": (real_gain, (), ("png",), RealGainFigureParams),
    "figure_replay": (replay, ("terrain_class",), ("png", "notes"), ReplayFigureParams),
    "figure_real_turning": (real_turning, (), ("png",), FigureParams),
}


def figure_job(
    rule: str,
    inputs: Mapping[str, Any],
    params: Mapping[str, Any],
    wildcards: Mapping[str, str],
    outputs: Mapping[str, str],
) -> None:
    """Rule ``rule``'s figure: its params validated as the rule's model (RULES), drawn by its function. A rule
    used from the study as a module (rules/robots.smk: ``use rule * from husky as husky_*``) carries a prefix."""
    known = [name for name in RULES if rule == name or rule.endswith("_" + name)]
    if not known:
        raise KeyError(f"rule {rule!r} draws no figure this module knows (simpick.report.draw.RULES)")
    function, names, outs, model = RULES[max(known, key=len)]
    function(inputs, _typed(model, params), *(wildcards[n] for n in names), *(outputs[o] for o in outs))
