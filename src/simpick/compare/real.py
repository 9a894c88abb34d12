"""Simulated real-data cases against the real robot: a segment's window statistics, a replayed run
window by window (Eq. 7, yaw-rate gain, aligned errors, PSD distance), and the per-source summaries
over runs (intervals and paired verdicts from ``statistics.min_runs`` independent runs on).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from simpick.compare import metrics, realmetrics
from simpick.compare.metrics import AXES
from simpick.compare.rows import DETAIL_COLUMNS, RUN_COLUMNS, axis_rows, run_row
from simpick.compare.settings import ReplaySettings
from simpick.real.logs import read_canonical
from simpick.real.segments import load_segments
from simpick.simulate.traces import read_trace

QUANTITIES = ("angular", "linear")


def compared_window(frame: pd.DataFrame, meta: dict) -> pd.DataFrame:
    """The rows of a simulated segment inside its compared window (``meta["window"]``, after settling)."""
    lo, hi = meta["window"]
    return frame[(frame.time > lo) & (frame.time <= hi)]


def trace_rate(sim: pd.DataFrame, meta: dict) -> float:
    """A simulated trace's IMU rate (Hz): from its metadata, else its median sample interval."""
    return float(meta.get("imu_rate_hz") or 1.0 / np.median(np.diff(sim.time)))


def real_imu_at(imu: pd.DataFrame, times, columns=("ax", "ay", "az", "wx", "wy", "wz")) -> dict[str, np.ndarray]:
    """The real IMU interpolated at the simulated sample times (same clock from 0); the simulated
    IMU is already block-averaged to the real one's rate (replay_log)."""
    return {c: np.interp(times, imu.time, imu[c]) for c in columns}


def segment_row(frame: pd.DataFrame, meta: dict, seg: pd.Series, track: float) -> dict:
    """One simulated segment against its real statistics: Eq. 7 errors, yaw-rate gain, speed."""
    row = {
        "engine": meta["engine"],
        "terrain_class": seg.terrain_class,
        "segment": seg.name,
        "run": seg.run,
        "kind": seg.kind,
        "status": meta["health"]["status"],
        "reasons": "; ".join(meta["health"]["reasons"]),
        "yaw_rate_gain_real": seg.yaw_rate_gain,
        "start_heading_deg": meta.get("start_heading_deg", float("nan")),
    }
    if row["status"] == "ok":
        window = compared_window(frame, meta)
        stats = metrics.trace_stats(window)
        for q in QUANTITIES:
            real = {a: {"mean": seg[f"{q}_{a}_mean"], "range": seg[f"{q}_{a}_range"]} for a in AXES}
            row[f"error_{q}"] = metrics.test_error(stats[q], real)
        row["yaw_rate_gain_sim"] = (
            realmetrics.yaw_rate_gain(
                window.wz.to_numpy(), np.full(len(window), seg.v_left), np.full(len(window), seg.v_right), track
            )
            if seg.kind == "turning"
            else float("nan")
        )
        row["gain_error"] = abs(row["yaw_rate_gain_sim"] - float(seg.yaw_rate_gain))  # NaN unless turning
        # the table keeps the real window's mean gyro z: integrated over the window, the heading
        # the real robot turned through; the simulated one's the same way
        row["heading_error"] = realmetrics.heading_error(
            float(window.wz.mean()), float(seg.angular_z_mean), float(seg.duration)
        )
        row["speed_sim"] = float(window.v_forward.mean())
    return row


def segment_compare(segments_csv: str, traces: list[str], track: float):
    """Every simulated segment against its real window statistics (the committed table): per
    test rows (segment_row), per axis rows (compare.rows.axis_rows) and each trace's run row."""
    segments = load_segments(segments_csv).set_index("segment")
    rows, detail, runs = [], [], []
    for path in traces:
        frame, meta = read_trace(path)
        seg = segments.loc[meta["segment"]]
        rows.append(segment_row(frame, meta, seg, track) | {"test": meta["segment"]})
        runs.append(run_row(meta))
        ok = meta["health"]["status"] == "ok"
        real = {
            q: {a: {"mean": seg[f"{q}_{a}_mean"], "range": seg[f"{q}_{a}_range"]} for a in AXES} for q in QUANTITIES
        }
        detail += axis_rows(
            meta, metrics.trace_stats(compared_window(frame, meta)) if ok else None, real | {"source": str(seg.dataset)}
        )
    return (
        pd.DataFrame(rows, columns=SEGMENT_TEST_COLUMNS),
        pd.DataFrame(detail, columns=DETAIL_COLUMNS),
        pd.DataFrame(runs, columns=RUN_COLUMNS),
    )


# the per-test tables' columns: written even when a source has no case (or none that a model completed),
# so that every later job reads a table with its columns and no rows, a normal outcome
SEGMENT_TEST_COLUMNS = [
    "engine",
    "terrain_class",
    "segment",
    "run",
    "kind",
    "status",
    "reasons",
    "yaw_rate_gain_real",
    "start_heading_deg",
    "error_angular",
    "error_linear",
    "yaw_rate_gain_sim",
    "gain_error",
    "heading_error",
    "speed_sim",
    "test",
]


WINDOW_FIGURES = [
    "yaw_rate_gain_real",
    "yaw_rate_gain_sim",
    "gain_error",
    "heading_error",
    "start_heading_deg",
    "rmse_yaw_rate",
    "rmse_ax",
    "psd_distance_az",
]


WINDOW_COLUMNS = [
    "engine",
    "terrain_class",
    "run",
    "status",
    "reasons",
    "window_start",
    "window_end",
    "imu_rate_hz",
    "error_angular",
    "error_linear",
    *WINDOW_FIGURES,
]


REPLAY_TEST_COLUMNS = [
    "engine",
    "terrain_class",
    "run",
    "error_angular",
    "error_linear",
    *WINDOW_FIGURES,
    "status",
    "kind",
    "reasons",
    "real_imu_hz",
    "real_commands_hz",
    "sim_imu_hz",
    "segment",
    "test",
]


def replay_compare(logs: list[str], traces: list[str], params: dict):
    """Every replay trace against its real log, window by window (:class:`ReplaySettings`: the track, the
    window's length): Eq. 7 errors, yaw-rate gains, aligned errors, PSD distance (the per-window rows),
    summed per run (the per-test rows: one test = one run), and each trace's run row."""
    settings = ReplaySettings.model_validate(params)
    track, window_s = settings.track, settings.window
    real = {}
    for path in logs:
        log = read_canonical(path)
        real[(log.meta["terrain_class"].lower(), str(log.meta["run_id"]))] = log
    rows, runs, rates = [], [], []
    for path in traces:
        sim, meta = read_trace(path)
        runs.append(run_row(meta))
        key = (meta["terrain"], meta["run"])
        log = real[key]
        # the rates the report states (measured median of the log's streams, the trace's IMU rate),
        # so that it reads them from this table and not from the logs and traces themselves
        measured = log.meta.get("rates") or {}
        rates.append(
            {
                "engine": meta["engine"],
                "terrain_class": key[0],
                "run": key[1],
                "real_imu_hz": (measured.get("imu") or {}).get("median_hz"),
                "real_commands_hz": (measured.get("commands") or {}).get("median_hz"),
                "sim_imu_hz": meta.get("imu_rate_hz"),
            }
        )
        base = {
            "engine": meta["engine"],
            "terrain_class": key[0],
            "run": key[1],
            "status": meta["health"]["status"],
            "reasons": "; ".join(meta["health"]["reasons"]),
            "start_heading_deg": meta.get("start_heading_deg", float("nan")),
        }
        if base["status"] != "ok":
            rows.append(base)
            continue
        cmd = log.wheel_commands(track)
        imu = log.imu
        rate = trace_rate(sim, meta)
        aligned = real_imu_at(imu, sim.time)
        held = np.clip(np.searchsorted(cmd.time.to_numpy(), sim.time.to_numpy(), side="right") - 1, 0, len(cmd) - 1)
        v_left, v_right = cmd.v_left.to_numpy()[held], cmd.v_right.to_numpy()[held]
        edges = np.arange(0.0, float(sim.time.iloc[-1]) + 1e-9, window_s)
        for w0 in edges:
            sel = ((sim.time > w0) & (sim.time <= w0 + window_s)).to_numpy()
            if sel.sum() < 0.5 * window_s * rate:  # a tail shorter than half a window
                continue
            real_frame = pd.DataFrame({c: v[sel] for c, v in aligned.items()})
            sim_stats, real_stats = metrics.trace_stats(sim[sel]), metrics.trace_stats(real_frame)
            row = dict(base, window_start=w0, window_end=w0 + window_s, imu_rate_hz=rate)
            for q in QUANTITIES:
                row[f"error_{q}"] = metrics.test_error(sim_stats[q], real_stats[q])
            row["yaw_rate_gain_real"] = realmetrics.yaw_rate_gain(real_frame.wz, v_left[sel], v_right[sel], track)
            row["yaw_rate_gain_sim"] = realmetrics.yaw_rate_gain(sim.wz[sel], v_left[sel], v_right[sel], track)
            row["gain_error"] = abs(row["yaw_rate_gain_sim"] - row["yaw_rate_gain_real"])  # NaN where not turning
            row["heading_error"] = realmetrics.heading_error(
                float(sim.wz[sel].mean()), float(real_frame.wz.mean()), float(sel.sum()) / rate
            )
            row["rmse_yaw_rate"] = realmetrics.aligned_rmse(real_frame.wz.to_numpy(), sim.wz[sel].to_numpy(), rate)
            row["rmse_ax"] = realmetrics.aligned_rmse(real_frame.ax.to_numpy(), sim.ax[sel].to_numpy(), rate)
            row["psd_distance_az"] = realmetrics.psd_distance(real_frame.az.to_numpy(), sim.az[sel].to_numpy(), rate)
            rows.append(row)
    per_window = pd.DataFrame(rows, columns=WINDOW_COLUMNS)
    # one test = one run: Eq. 7 sums the windows' errors, the other figures average over windows
    ok = per_window[per_window.status == "ok"]
    keys = ["engine", "terrain_class", "run"]
    per_run = metrics.eq7_per_run(ok, keys, QUANTITIES).merge(
        ok.groupby(keys)[WINDOW_FIGURES].mean().reset_index(), on=keys
    )
    per_run["status"], per_run["kind"] = "ok", "replay"
    failed = per_window[per_window.status != "ok"][["engine", "terrain_class", "run", "status", "reasons"]]
    per_test = pd.concat([frame for frame in (per_run, failed) if len(frame)] or [per_run], ignore_index=True)
    per_test = per_test.merge(
        pd.DataFrame(
            rates, columns=["engine", "terrain_class", "run", "real_imu_hz", "real_commands_hz", "sim_imu_hz"]
        ),
        on=["engine", "terrain_class", "run"],
        how="left",
    )
    per_test["segment"] = per_test["terrain_class"].astype(str) + "-" + per_test["run"].astype(str)
    per_test["test"] = per_test["segment"]
    return per_test.reindex(columns=REPLAY_TEST_COLUMNS), per_window, pd.DataFrame(runs, columns=RUN_COLUMNS)


FIGURES = (
    "error_angular",
    "error_linear",
    "yaw_rate_gain_sim",
    "gain_error",
    "heading_error",
    "rmse_yaw_rate",
    "rmse_ax",
    "psd_distance_az",
)


def summary_table(per_test: pd.DataFrame, group: str, statistics: dict | None = None) -> pd.DataFrame:
    """Per engine and ``group`` (terrain class, or the lab's terrain): every figure's mean over
    runs (a run's tests averaged first: segments and windows of one run are not independent) with
    its BCa bootstrap interval from ``statistics["min_runs"]`` runs on, over the tests the engine
    ran healthily (a failed test is counted by the caller, never averaged in). Per-test rows need
    engine, ``group``, test, run and status."""
    min_runs, level = realmetrics.statistics_settings(statistics)
    ok = per_test[per_test.status == "ok"]
    shown = [fig for fig in FIGURES + ("yaw_rate_gain_real",) if fig in per_test]
    rows = []
    for (engine, cls), g in ok.groupby(["engine", group]):
        row = {"engine": engine, group: cls, "n_tests": len(g), "n_runs": int(g["run"].nunique())}
        for fig in shown:
            mean, lo, hi, _ = realmetrics.mean_ci(g[fig].to_numpy(float), g["run"].to_numpy(), min_runs, level)
            row.update({fig: mean, f"{fig}_low": lo, f"{fig}_high": hi})
        rows.append(row)
    return pd.DataFrame(
        rows,
        columns=[
            "engine",
            group,
            "n_tests",
            "n_runs",
            *[f"{fig}{end}" for fig in shown for end in ("", "_low", "_high")],
        ],
    )


def pairwise_table(per_test: pd.DataFrame, group: str, statistics: dict | None = None) -> pd.DataFrame:
    """Per ``group`` and pair of engines: the paired difference of each Eq. 7 error over the tests
    both ran healthily, judged by a sign-flip permutation test over runs (``too few runs`` below
    ``statistics["min_runs"]``)."""
    min_runs, level = realmetrics.statistics_settings(statistics)
    ok = per_test[per_test.status == "ok"]
    pairs = []
    engines = sorted(ok.engine.unique())
    for cls, g in ok.groupby(group):
        wide = g.pivot_table(index="test", columns="engine", values=["error_angular", "error_linear"])
        run_of = g.drop_duplicates("test").set_index("test")["run"]
        for i, a in enumerate(engines):
            for b in engines[i + 1 :]:
                for fig in ("error_angular", "error_linear"):
                    if (fig, a) not in wide or (fig, b) not in wide:
                        continue
                    t = realmetrics.paired_test(
                        wide[(fig, a)], wide[(fig, b)], run_of.reindex(wide.index).to_numpy(), min_runs, level
                    )
                    closer = {"a": b, "b": a}.get(t["verdict"], "")
                    outcome = "closer" if closer else t["verdict"]
                    verdict = f"{closer} closer" if closer else t["verdict"]
                    if verdict == "too few runs":
                        verdict = f"too few runs ({t['n_runs']} < {min_runs})"
                    pairs.append(
                        {
                            group: cls,
                            "figure": fig,
                            "engine_a": a,
                            "engine_b": b,
                            "mean_a_minus_b": t["mean"],
                            "low": t["low"],
                            "high": t["high"],
                            "p_value": t["p_value"],
                            "n_runs": t["n_runs"],
                            "verdict": verdict,
                            "outcome": outcome,
                            "closer": closer,
                            "min_runs": min_runs,
                        }
                    )
    return pd.DataFrame(
        pairs,
        columns=[
            group,
            "figure",
            "engine_a",
            "engine_b",
            "mean_a_minus_b",
            "low",
            "high",
            "p_value",
            "n_runs",
            "verdict",
            "outcome",
            "closer",
            "min_runs",
        ],
    )


# A pair's typed outcome (pairwise_table's ``outcome``; ``closer`` names the engine where it is "closer"),
# and a class's (class_verdicts' ``<figure>_outcome``): the engine with the smallest mean of a figure is
# "clear" when the paired test puts it closer than every other engine; otherwise why not.
PAIR_OUTCOMES = ("closer", "no clear difference", "too few runs")
CLASS_OUTCOMES = (
    "clear",
    "not separated",
    "too few runs",
    "intervals disagree",
    "only one engine",
    "no paired comparison",
)


def class_verdicts(summary: pd.DataFrame, pairwise: pd.DataFrame, group: str) -> pd.DataFrame:
    """The summary with, per figure it holds, ``<figure>_closest`` (the engine with the smallest mean
    in its ``group``; ties to the first name) and ``<figure>_outcome`` (one of ``CLASS_OUTCOMES``,
    the same on every row of the group): whether the pairwise tests separate that engine from every
    other, so that a reader takes the verdict from the table and derives none."""
    out = summary.copy()
    figures = [
        f
        for f in FIGURES + ("yaw_rate_gain_real",)
        if f in summary and f not in ("yaw_rate_gain_sim", "yaw_rate_gain_real")
    ]
    for fig in figures:
        closest, outcome = pd.Series(False, index=out.index), pd.Series("", index=out.index, dtype=object)
        for cls, sel in out.groupby(group):
            means = pd.to_numeric(sel[fig], errors="coerce")
            means = means[np.isfinite(means)]
            if means.empty:
                continue
            best_index = min(means.index, key=lambda i: (means[i], str(out.at[i, "engine"])))
            best = out.at[best_index, "engine"]
            others = [e for e in sel.loc[means.index, "engine"] if e != best]
            pw = pairwise[(pairwise[group] == cls) & (pairwise.figure == fig)] if len(pairwise) else pairwise
            pairs = pw[(pw.engine_a == best) | (pw.engine_b == best)] if len(pw) else pw
            kinds = set(pairs.outcome) if len(pairs) else set()
            if not others:
                verdict = "only one engine"
            elif len(pairs) == 0:
                verdict = "no paired comparison"
            elif len(pairs) >= len(others) and kinds == {"closer"} and set(pairs.closer) == {best}:
                verdict = "clear"
            elif "too few runs" in kinds:
                verdict = "too few runs"
            elif any(c and c != best for c in pairs.closer):
                verdict = "intervals disagree"
            else:
                verdict = "not separated"
            closest[best_index] = True
            outcome[sel.index] = verdict
        out[f"{fig}_closest"], out[f"{fig}_outcome"] = closest, outcome
    return out
