"""Real robot data in the workflow: segments, replays, and their comparison with the engines.

Two ways in:
- the committed constant-command segments (``resources/real/*_segments.csv``): every engine
  drives each segment's command on its terrain class; no download needed;
- the full replay of a dataset folder (``borealtc_dir`` set; :mod:`simpick.datasets`): every
  run imported to the canonical form, driven through every engine by its recorded wheel
  speeds, its simulated IMU block-averaged to the run's own IMU rate, compared window by
  window. The folder's own segment table is derived too, as a result; only the maintainer
  target ``maintain_segments`` copies it over the committed one.

Both produce the paper's Eq. 7 errors per test (so they can feed the accuracy scores), the
yaw-rate gain, and per-engine summaries over runs: intervals and paired verdicts only from
the config's ``statistics.min_runs`` independent runs on (:mod:`simpick.realmetrics`).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from simpick import metrics, realmetrics
from simpick.errors import InputError
from simpick.metrics import AXES
from simpick.tables import write_csv

QUANTITIES = ("angular", "linear")


def flat_terrain(name: str, friction: float) -> dict:
    from simpick.terrain import generate

    return generate(name, "flat", 0, friction, tiles=0)


def load_segments(path: str | Path) -> pd.DataFrame:
    from simpick.realsegments import COLUMNS

    try:
        frame = pd.read_csv(path, dtype={"run": str})
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise InputError(str(path), f"cannot read the segments table: {exc}") from None
    missing = [c for c in COLUMNS if c not in frame.columns]
    if missing:
        raise InputError(str(path), f"columns {missing} are missing",
                         "restore it (git checkout -- PATH) or regenerate it: "
                         "snakemake --cores 2 maintain_segments --config borealtc_dir=PATH")
    return frame


# --- segments -------------------------------------------------------------------------------------

def segments_job(logs: list[str], output_csv: str, output_provenance: str, params: dict) -> None:
    """The constant-command segments of a dataset's imported runs (a result, never the committed table)."""
    from simpick.reallogs import read_canonical
    from simpick.realsegments import derive_from_logs

    rules = params["segment_rules"]
    table, provenance = derive_from_logs((read_canonical(p) for p in logs), tolerance=rules["tolerance"],
                                         min_duration=rules["min_duration"], max_duration=rules["max_duration"],
                                         settle=rules["settle"], min_turn=rules["min_turn"],
                                         per_kind=int(rules["per_kind"]), track=params["track"],
                                         source=params["source"])
    write_csv(table, output_csv)
    Path(output_provenance).write_text(yaml.safe_dump(provenance, sort_keys=False))


def maintain_segments_job(derived_csv: str, derived_provenance: str, committed: dict, receipt: str) -> None:
    """The maintainer's deliberate step: the derived table (and provenance) over the committed
    ones. Each file is written beside its target and renamed over it, so a failure leaves the
    committed file as it was; the receipt (a result) says what changed."""
    import hashlib
    import os

    def digest(path) -> str | None:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest() if Path(path).is_file() else None

    load_segments(derived_csv)  # refuse a table the study could not read
    done = {}
    for key, source in (("csv", derived_csv), ("provenance", derived_provenance)):
        target = Path(committed[key])
        before = digest(target)
        partial = target.with_name(f".{target.name}.partial")
        partial.write_bytes(Path(source).read_bytes())
        os.replace(partial, target)
        done[key] = {"file": str(target), "from": str(source), "sha256_before": before,
                     "sha256_after": digest(target), "changed": before != digest(target)}
    Path(receipt).parent.mkdir(parents=True, exist_ok=True)
    Path(receipt).write_text(yaml.safe_dump(done, sort_keys=False))
    changed = [d["file"] for d in done.values() if d["changed"]]
    print(f"simpick: maintain_segments: {', '.join(changed) or 'nothing'} changed; commit it if intended",
          file=sys.stderr)


def start_heading(seed: int, dataset: object, terrain_class: object, run: object, case: object) -> float:
    """The start heading (rad, in [0, 2 pi)) of one real-data case: drawn uniformly from the config
    seed and the case's names, the same for every model (so paired comparisons stay paired), a
    different one for every case. Mechanics says a robot on isotropic flat ground turns the same
    whichever way it faces; an engine that does not (PyBullet's gain has a 90-degree period, 0.10
    along the world axes, 0.54 at 45 degrees: issue 17) then shows that as spread over the runs,
    which every interval over runs carries, instead of a bias fixed by one chosen start (every case
    started at heading 0, PyBullet's worst, before issue 17). One heading per case costs no extra
    simulation; several per case would multiply the real-data simulation by their number."""
    from simpick.simulate import stable_seed

    u = stable_seed(int(seed), "start heading", str(dataset), str(terrain_class), str(run), str(case)) / 2.0 ** 32
    return float(2.0 * np.pi * u)


def simulate_segment(seg: pd.Series, urdf: str, params: dict) -> tuple[pd.DataFrame, dict]:
    """One real segment's command driven on ``params["engine"]`` over its class's flat ground,
    from its seeded start heading (:func:`start_heading`)."""
    from simpick.health import HealthLimits
    from simpick.imu import ImuModel
    from simpick.simulate import Case, config_hash, run_case

    friction = params["class"]["friction"]
    heading = start_heading(params["seed"], seg.dataset, seg.terrain_class, seg.run, seg.name)
    case = Case(engine=params["engine"], terrain=params["terrain_class"], motion=seg.name, v=float(seg.v),
                w=float(seg.w), duration=float(seg.settle + seg.duration), start=(0.0, 0.0, heading))
    frame, meta = run_case(case, urdf=urdf, terrain=flat_terrain(params["terrain_class"], friction),
                           track=params["robot"]["track"], max_wheel_torque=params["robot"]["max_wheel_torque"],
                           timestep=params["physics"]["timestep"], ground_friction=friction,
                           engine_settings=params["engine_settings"], imu=ImuModel(**params["imu"]),
                           seed=int(params["seed"]), limits=HealthLimits(**params["health"]),
                           robot_options=params["robot"])
    meta.update({"dataset": seg.dataset, "run": seg.run, "segment": seg.name,
                 "start_heading_deg": float(np.degrees(heading)),
                 "window": [float(seg.settle), float(seg.settle + seg.duration)],
                 "friction_source": params["class"].get("source", ""),
                 "config_hash": config_hash(params)})
    return frame, meta


def class_segments(segments_csv: str, terrain_class: str) -> pd.DataFrame:
    segments = load_segments(segments_csv)
    return segments[segments.terrain_class == terrain_class].set_index("segment")


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
    row = {"engine": meta["engine"], "terrain_class": seg.terrain_class, "segment": seg.name, "run": seg.run,
           "kind": seg.kind, "status": meta["health"]["status"], "reasons": "; ".join(meta["health"]["reasons"]),
           "yaw_rate_gain_real": seg.yaw_rate_gain, "start_heading_deg": meta.get("start_heading_deg", float("nan"))}
    if row["status"] == "ok":
        window = compared_window(frame, meta)
        stats = metrics.trace_stats(window)
        for q in QUANTITIES:
            real = {a: {"mean": seg[f"{q}_{a}_mean"], "range": seg[f"{q}_{a}_range"]} for a in AXES}
            row[f"error_{q}"] = metrics.test_error(stats[q], real)
        row["yaw_rate_gain_sim"] = (realmetrics.yaw_rate_gain(
            window.wz.to_numpy(), np.full(len(window), seg.v_left), np.full(len(window), seg.v_right), track)
            if seg.kind == "turning" else float("nan"))
        row["gain_error"] = abs(row["yaw_rate_gain_sim"] - float(seg.yaw_rate_gain))  # NaN unless turning
        # the table keeps the real window's mean gyro z: integrated over the window, the heading
        # the real robot turned through; the simulated one's the same way
        row["heading_error"] = realmetrics.heading_error(float(window.wz.mean()), float(seg.angular_z_mean),
                                                         float(seg.duration))
        row["speed_sim"] = float(window.v_forward.mean())
    return row


def segment_compare(segments_csv: str, traces: list[str], track: float):
    """Every simulated segment against its real window statistics (the committed table): per
    test rows (segment_row), per axis rows (tables.axis_rows) and each trace's run row."""
    from simpick.traces import read_trace
    from simpick.tables import DETAIL_COLUMNS, RUN_COLUMNS, axis_rows, run_row

    segments = load_segments(segments_csv).set_index("segment")
    rows, detail, runs = [], [], []
    for path in traces:
        frame, meta = read_trace(path)
        seg = segments.loc[meta["segment"]]
        rows.append(segment_row(frame, meta, seg, track) | {"test": meta["segment"]})
        runs.append(run_row(meta))
        ok = meta["health"]["status"] == "ok"
        real = {q: {a: {"mean": seg[f"{q}_{a}_mean"], "range": seg[f"{q}_{a}_range"]} for a in AXES}
                for q in QUANTITIES}
        detail += axis_rows(meta, metrics.trace_stats(compared_window(frame, meta)) if ok else None,
                            real | {"source": str(seg.dataset)})
    return (pd.DataFrame(rows, columns=SEGMENT_TEST_COLUMNS), pd.DataFrame(detail, columns=DETAIL_COLUMNS),
            pd.DataFrame(runs, columns=RUN_COLUMNS))


# the per-test tables' columns: written even when a source has no case (or none that a model completed),
# so that every later job reads a table with its columns and no rows, a normal outcome (issue 21)
SEGMENT_TEST_COLUMNS = ["engine", "terrain_class", "segment", "run", "kind", "status", "reasons", "yaw_rate_gain_real",
                        "start_heading_deg", "error_angular", "error_linear", "yaw_rate_gain_sim", "gain_error",
                        "heading_error", "speed_sim", "test"]
WINDOW_FIGURES = ["yaw_rate_gain_real", "yaw_rate_gain_sim", "gain_error", "heading_error", "start_heading_deg",
                  "rmse_yaw_rate", "rmse_ax", "psd_distance_az"]
WINDOW_COLUMNS = ["engine", "terrain_class", "run", "status", "reasons", "window_start", "window_end", "imu_rate_hz",
                  "error_angular", "error_linear", *WINDOW_FIGURES]
REPLAY_TEST_COLUMNS = ["engine", "terrain_class", "run", "error_angular", "error_linear", *WINDOW_FIGURES, "status",
                       "kind", "reasons", "real_imu_hz", "real_commands_hz", "sim_imu_hz", "segment", "test"]


# --- full replay ----------------------------------------------------------------------------------

def dataset_manifest_job(dataset: dict, output: str) -> None:
    """results/real/<dataset>/dataset.yaml: the folder whose results that folder holds."""
    Path(output).parent.mkdir(parents=True, exist_ok=True)
    Path(output).write_text(yaml.safe_dump(dict(dataset), sort_keys=False))


def import_job(imu: str, pro: str, terrain_class: str, output: str, params: dict) -> None:
    """One run of a dataset folder -> canonical log (rates measured, checked against any declared)."""
    from simpick.reallogs import borealtc, write_canonical

    declared = params["declared"]
    log = borealtc.read_run(imu, pro, terrain_class, track=params["track"],
                            imu_rate_hz=declared.get("imu_hz"), command_rate_hz=declared.get("commands_hz"),
                            declared_by=f"real_data.datasets.{params['dataset']} in the config",
                            dataset=params["label"])
    write_canonical(log, output)


def log_imu_rate(log) -> float:
    """A real log's IMU rate (Hz): the reader's measured median rate, else from its times."""
    rate = ((log.meta.get("rates") or {}).get("imu") or {}).get("median_hz")
    return float(rate) if rate else float(1.0 / np.median(np.diff(log.imu["time"].to_numpy(dtype=float))))


def replay_log(log, urdf: str, params: dict, duration: float | None = None) -> tuple[pd.DataFrame, dict]:
    """Drive one engine with a real run's recorded wheel speeds (zero-order hold, from rest, from
    the run's seeded start heading: :func:`start_heading`)."""
    from simpick.health import HealthLimits
    from simpick.imu import model_at_rate
    from simpick.robot import load_from_config
    from simpick.simulate import run_commands, stable_seed

    robot = load_from_config({**params["robot"], "urdf": urdf})
    dt = params["physics"]["timestep"]
    cmd = log.wheel_commands(params["robot"]["track"])
    end = float(min(log.imu.time.iloc[-1], cmd.time.iloc[-1]))
    t = dt * np.arange(int(round((end if duration is None else min(end, duration)) / dt)))
    held = np.clip(np.searchsorted(cmd.time.to_numpy(), t, side="right") - 1, 0, len(cmd) - 1)
    left, right = cmd.v_left.to_numpy()[held], cmd.v_right.to_numpy()[held]
    wheels = robot.joint_speeds(left, right)  # (steps, driven wheels): the Husky's [l, r, l, r] / radius
    friction = params["class"]["friction"]
    heading = start_heading(params["seed"], log.meta.get("dataset"), params["terrain_class"], log.meta["run_id"],
                            log.meta["name"])
    frame, meta = run_commands(params["engine"], wheels, robot=robot,
                               terrain=flat_terrain(params["terrain_class"], friction), start=(0.0, 0.0, heading),
                               timestep=dt, ground_friction=friction, max_wheel_torque=params["robot"]["max_wheel_torque"],
                               engine_settings=params["engine_settings"],
                               imu=model_at_rate(params["imu"], log_imu_rate(log), dt),
                               noise_seed=stable_seed(params["seed"], params["engine"], log.meta["name"]),
                               limits=HealthLimits(**params["health"]))
    meta.update({"terrain": params["terrain_class"], "motion": f"replay-{log.meta['run_id']}",
                 "dataset": log.meta.get("dataset"), "run": str(log.meta["run_id"]), "seed": params["seed"],
                 "replay_of": log.meta.get("source_files"), "real_imu_rate_hz": log_imu_rate(log),
                 "start_heading_deg": float(np.degrees(heading))})
    return frame, meta


def replay_compare(logs: list[str], traces: list[str], params: dict):
    """Every replay trace against its real log, window by window: Eq. 7 errors, yaw-rate gains,
    aligned errors, PSD distance (the per-window rows), summed per run (the per-test rows: one
    test = one run), and each trace's run row."""
    from simpick.reallogs import read_canonical
    from simpick.traces import read_trace
    from simpick.tables import RUN_COLUMNS, run_row

    track, window_s = params["track"], params["window"]
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
        rates.append({"engine": meta["engine"], "terrain_class": key[0], "run": key[1],
                      "real_imu_hz": (measured.get("imu") or {}).get("median_hz"),
                      "real_commands_hz": (measured.get("commands") or {}).get("median_hz"),
                      "sim_imu_hz": meta.get("imu_rate_hz")})
        base = {"engine": meta["engine"], "terrain_class": key[0], "run": key[1],
                "status": meta["health"]["status"], "reasons": "; ".join(meta["health"]["reasons"]),
                "start_heading_deg": meta.get("start_heading_deg", float("nan"))}
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
            row["heading_error"] = realmetrics.heading_error(float(sim.wz[sel].mean()), float(real_frame.wz.mean()),
                                                             float(sel.sum()) / rate)
            row["rmse_yaw_rate"] = realmetrics.aligned_rmse(real_frame.wz.to_numpy(), sim.wz[sel].to_numpy(), rate)
            row["rmse_ax"] = realmetrics.aligned_rmse(real_frame.ax.to_numpy(), sim.ax[sel].to_numpy(), rate)
            row["psd_distance_az"] = realmetrics.psd_distance(real_frame.az.to_numpy(), sim.az[sel].to_numpy(), rate)
            rows.append(row)
    per_window = pd.DataFrame(rows, columns=WINDOW_COLUMNS)
    # one test = one run: Eq. 7 sums the windows' errors, the other figures average over windows
    ok = per_window[per_window.status == "ok"]
    keys = ["engine", "terrain_class", "run"]
    per_run = metrics.eq7_per_run(ok, keys, QUANTITIES).merge(
        ok.groupby(keys)[WINDOW_FIGURES].mean().reset_index(), on=keys)
    per_run["status"], per_run["kind"] = "ok", "replay"
    failed = per_window[per_window.status != "ok"][["engine", "terrain_class", "run", "status", "reasons"]]
    per_test = pd.concat([frame for frame in (per_run, failed) if len(frame)] or [per_run], ignore_index=True)
    per_test = per_test.merge(pd.DataFrame(rates, columns=["engine", "terrain_class", "run", "real_imu_hz",
                                                           "real_commands_hz", "sim_imu_hz"]),
                              on=["engine", "terrain_class", "run"], how="left")
    per_test["segment"] = per_test["terrain_class"].astype(str) + "-" + per_test["run"].astype(str)
    per_test["test"] = per_test["segment"]
    return per_test.reindex(columns=REPLAY_TEST_COLUMNS), per_window, pd.DataFrame(runs, columns=RUN_COLUMNS)


# --- summaries shared by every source -------------------------------------------------------------------------

FIGURES = ("error_angular", "error_linear", "yaw_rate_gain_sim", "gain_error", "heading_error", "rmse_yaw_rate",
           "rmse_ax", "psd_distance_az")


def summaries(per_test: pd.DataFrame, group: str, outputs: dict, statistics: dict | None = None) -> None:
    """:func:`summary_table` and :func:`pairwise_table` written to ``outputs["summary"]`` and
    ``outputs["pairwise"]``."""
    write_csv(summary_table(per_test, group, statistics), outputs["summary"])
    write_csv(pairwise_table(per_test, group, statistics), outputs["pairwise"])


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
    return pd.DataFrame(rows, columns=["engine", group, "n_tests", "n_runs",
                                       *[f"{fig}{end}" for fig in shown for end in ("", "_low", "_high")]])


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
            for b in engines[i + 1:]:
                for fig in ("error_angular", "error_linear"):
                    if (fig, a) not in wide or (fig, b) not in wide:
                        continue
                    t = realmetrics.paired_test(wide[(fig, a)], wide[(fig, b)], run_of.reindex(wide.index).to_numpy(),
                                                min_runs, level)
                    verdict = {"a": f"{b} closer", "b": f"{a} closer"}.get(t["verdict"], t["verdict"])
                    if verdict == "too few runs":
                        verdict = f"too few runs ({t['n_runs']} < {min_runs})"
                    pairs.append({group: cls, "figure": fig, "engine_a": a, "engine_b": b,
                                  "mean_a_minus_b": t["mean"], "low": t["low"], "high": t["high"],
                                  "p_value": t["p_value"], "n_runs": t["n_runs"], "verdict": verdict})
    return pd.DataFrame(pairs, columns=[group, "figure", "engine_a", "engine_b", "mean_a_minus_b",
                                        "low", "high", "p_value", "n_runs", "verdict"])


# --- fetching the public dataset ------------------------------------------------------------------

BOREALTC_ARCHIVES = ("https://github.com/norlab-ulaval/BorealTC/archive/refs/heads/main.zip",
                     "https://github.com/norlab-ulaval/BorealTC/archive/refs/heads/master.zip")


def fetch_borealtc(dest: str | Path, timeout: float = 30.0) -> Path:
    """Download the public BorealTC repository and keep its data/borealtc folder at ``dest``.

    Offline (or if the repository moved) this raises an InputError that says how to use a
    local copy instead, rather than a network traceback.
    """
    import io
    import shutil
    import tempfile
    import urllib.error
    import urllib.request
    import zipfile

    dest = Path(dest)
    errors = []
    for url in BOREALTC_ARCHIVES:
        try:
            with urllib.request.urlopen(url, timeout=timeout) as response:  # noqa: S310 - fixed https URLs
                payload = response.read()
            break
        except (urllib.error.URLError, OSError, TimeoutError) as exc:
            errors.append(f"{url}: {exc}")
    else:
        raise InputError("borealtc_dir", "could not download BorealTC (" + "; ".join(errors) + ")",
                         "download the folder data/borealtc of the GitHub repository norlab-ulaval/BorealTC "
                         "on a connected machine, copy it here, and run "
                         "snakemake --cores 2 --config borealtc_dir=PATH/TO/borealtc")
    with tempfile.TemporaryDirectory() as tmp, zipfile.ZipFile(io.BytesIO(payload)) as archive:
        archive.extractall(tmp)
        found = [p for p in Path(tmp).glob("*/data/borealtc") if p.is_dir()]
        if not found:
            raise InputError("borealtc_dir", "the downloaded archive has no data/borealtc folder",
                             "download data/borealtc by hand and pass --config borealtc_dir=PATH")
        if dest.exists():
            shutil.rmtree(dest)
        shutil.copytree(found[0], dest)
    return dest


# --- the user's own logs ------------------------------------------------------------------------

def import_own_job(entry: dict, output: str, track: float) -> None:
    """One of the user's logs (config ``own_logs``: a mapped CSV or a ROS bag) -> canonical form."""
    from simpick.reallogs import write_canonical

    meta = {"dataset": "own", "run_id": entry["name"], "terrain_class": entry["terrain_class"],
            "name": entry["name"]}
    if entry.get("csv"):
        from simpick.reallogs.csvlog import read_csv_log

        mapping = {**entry["mapping"], "meta": {**entry["mapping"].get("meta", {}), **meta}}
        log = read_csv_log(entry["csv"], mapping, commands_path=entry.get("commands_csv"), track=track)
    else:
        from simpick.reallogs.rosbag import read_bag

        bag = entry["rosbag"]
        options = {k: v for k, v in entry.items()
                   if k in ("command_type", "wheel_radius", "left_joints", "right_joints", "frame_z",
                            "imu_rate_hz", "command_rate_hz")}
        log = read_bag(bag, entry["imu_topic"], entry["command_topic"], track=track, meta=meta, **options)
    log.meta.update(meta)
    write_canonical(log, output)
