"""simpick benchmark: engine limits, pipeline overhead, rerun and planning costs, memory.

Run from the repository root:  .venv/bin/python bench/run.py   (about 3-4 minutes; --real-data adds the
BorealTC replay and DRIVE step jobs, bench/ENGINE_SPEED.md)
Writes bench/results.csv and bench/RESULTS.md (and the table into docs/benchmark.md between the
bench markers). Every figure is the median of --repeats runs, with min and max.
Separate from the tests on purpose: timings are measured, not asserted.
"""

from __future__ import annotations

import argparse
import copy
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd
import psutil
import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from simpick.engines import get_engine  # noqa: E402
from simpick.engines.base import Scenario  # noqa: E402
from simpick.inputs.jobs import terrain_job  # noqa: E402
from simpick.inputs.motions import constant_commands  # noqa: E402
from simpick.inputs.robot import load_robot  # noqa: E402

TARGETS = {  # what the pipeline is held to, on a 2-core machine
    "job_vs_bare_ratio": (">=", 0.90),
    "job_vs_bare_ratio_cpu": (">=", 0.90),
    # real-time factor of the lab study at 1 kHz, per engine: PyBullet and ODE 30x, MuJoCo 60x,
    # DART 10x
    ("rtf_lab_study", "pybullet"): (">=", 30.0),
    ("rtf_lab_study", "mujoco"): (">=", 60.0),
    ("rtf_lab_study", "ode"): (">=", 30.0),
    ("rtf_lab_study", "dart"): (">=", 10.0),
    # PhysX (SAPIEN, stepped from Python like DART) at DART's 10x; Drake with hydroelastic
    # wheels at real time (its first measured lab runs: 1-2.5x on a loaded machine)
    ("rtf_lab_study", "physx"): (">=", 10.0),
    ("rtf_lab_study", "drake"): (">=", 1.0),
    "default_study_wall_s": ("<=", 60.0),
    "rerun_after_weight_edit_wall_s": ("<=", 5.0),
    "rerun_after_weight_edit_html_s": ("<=", 5.0),
    "dry_run_1000_cases_wall_s": ("<=", 5.0),
    "simulate_job_peak_rss_mb": ("<=", 300.0),
}


def spread(values: list[float]) -> dict:
    return {"median": statistics.median(values), "min": min(values), "max": max(values), "n": len(values)}


def lab_scenarios(
    config: dict,
    engine: str,
    terrains: list[str] | None = None,
    duration: float | None = None,
    overrides: dict | None = None,
):
    """(terrain, scenario, commands) of the straight lab motion on each terrain for ``engine``, its
    config settings updated with ``overrides`` (bench/engine_speed.py tries settings this way)."""
    robot = load_robot(ROOT / config["robot"]["urdf"])
    motion = config["motions"]["straight"]
    dt = config["physics"]["timestep"]
    commands = constant_commands(
        motion["v"], motion["w"], duration or motion["duration"], dt, config["robot"]["track"], robot.wheel_radius
    )
    settings = {**(config["engines"].get(engine) or {}), **(overrides or {})}
    with tempfile.TemporaryDirectory() as tmp:
        for name in terrains or list(config["terrains"]):
            path = Path(tmp) / f"{name}.json"
            terrain_job(str(path), name, config["seed"], config["terrains"][name])
            terrain = yaml.safe_load(path.read_text())
            yield (
                name,
                Scenario(
                    robot=robot,
                    terrain=terrain,
                    ground_friction=config["physics"]["ground_friction"],
                    timestep=dt,
                    max_wheel_torque=config["robot"]["max_wheel_torque"],
                    starts=(tuple(motion["start"]),),
                    settings=settings,
                ),
                commands,
            )


def engine_throughput(config: dict, repeats: int) -> list[dict]:
    rows = []
    for engine_name in config["engines"]:
        engine = get_engine(engine_name)
        for terrain_name, scenario, commands in lab_scenarios(config, engine_name):
            bare = [commands.shape[0] / engine.bare_loop(scenario, commands) for _ in range(repeats)]
            job = []
            for _ in range(repeats):
                record = engine.simulate(scenario, commands)
                job.append(record.steps / record.wall_time)
            b, j = spread(bare), spread(job)
            rows.append({"measure": "steps_per_s_bare", "engine": engine_name, "terrain": terrain_name, **b})
            rows.append({"measure": "steps_per_s_job", "engine": engine_name, "terrain": terrain_name, **j})
            rows.append(
                {
                    "measure": "job_vs_bare_ratio",
                    "engine": engine_name,
                    "terrain": terrain_name,
                    "median": j["median"] / b["median"],
                    "min": j["min"] / b["max"],
                    "max": j["max"] / b["min"],
                    "n": repeats,
                }
            )
    # the table's order: terrain by terrain, the engines in config order within each
    terrains, engines = list(config["terrains"]), list(config["engines"])
    return sorted(rows, key=lambda r: (terrains.index(r["terrain"]), engines.index(r["engine"])))


def real_data_throughput(config: dict, repeats: int) -> list[dict]:
    """The real-data jobs' loop against the bare loop, in process CPU (bench/replay_speed.py, which also
    prints every case): the first 10 s of one BorealTC run per class (the Husky), and one DRIVE step per
    session (the Warthog, config/robots/warthog.yaml). Terrain column: the source."""
    sys.path.insert(0, str(ROOT / "bench"))
    from replay_speed import bare, drive_cases, load_config, replay_cases

    warthog = load_config("config/robots/warthog.yaml")
    rows = []
    for engine_name in config["engines"]:
        engine = get_engine(engine_name)
        sources = {
            "borealtc replay": replay_cases(config, engine_name, 1, 10.0, {}),
            "drive step": drive_cases(warthog, engine_name, 1, {}),
        }
        for source, cases in sources.items():
            bare_cpu, job_cpu, steps = [0.0] * repeats, [0.0] * repeats, 0
            for _, scenario, commands, _ in cases:
                steps += len(commands)
                for r in range(repeats):
                    bare_cpu[r] += bare(engine, scenario, commands)[0]
                    job_cpu[r] += engine.simulate(scenario, commands.reshape(len(commands), 1, -1)).cpu_time
            b, j = spread([steps / t for t in bare_cpu]), spread([steps / t for t in job_cpu])
            ratio = spread([bt / jt for bt, jt in zip(bare_cpu, job_cpu)])
            rows.append({"measure": "steps_per_s_bare_cpu", "engine": engine_name, "terrain": source, **b})
            rows.append({"measure": "steps_per_s_job_cpu", "engine": engine_name, "terrain": source, **j})
            rows.append({"measure": "job_vs_bare_ratio_cpu", "engine": engine_name, "terrain": source, **ratio})
    return rows


def copy_project(dest: Path) -> None:
    files = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout.split()
    for name in files:
        target = dest / name
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, target)
    for name in ("config.yaml",):  # the working copy's config, even if uncommitted
        shutil.copy2(ROOT / name, dest / name)


def snakemake(workdir: Path, *args: str) -> float:
    start = time.perf_counter()
    run = subprocess.run(
        [str(ROOT / ".venv/bin/snakemake"), "--cores", "2", *args], cwd=workdir, capture_output=True, text=True
    )
    wall = time.perf_counter() - start
    if run.returncode != 0:
        raise RuntimeError(f"snakemake {' '.join(args)} failed:\n{run.stderr[-3000:]}")
    return wall


def pipeline(repeats: int) -> list[dict]:
    rows = []
    study, rerun, dry, to_html = [], [], [], []
    job_rows = []
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as tmp:
            work = Path(tmp)
            copy_project(work)
            study.append(snakemake(work))
            config_path = work / "config.yaml"
            config = yaml.safe_load(config_path.read_text())
            config["weights"]["ui"] = config["weights"]["ui"] + 1
            config_path.write_text(yaml.safe_dump(config, sort_keys=False))
            started = time.time()
            rerun.append(snakemake(work))
            # the PDF is its own job: the HTML a user reloads is there before WeasyPrint is done
            to_html.append((work / "results/report/report.html").stat().st_mtime - started)
            bench = list((work / "results/benchmarks/simulate/lab").rglob("*.tsv"))
            runs = pd.read_csv(work / "results/metrics/lab/runs.csv")
            for path in bench:  # a lab job: a terrain's motions on one engine
                engine, terrain = path.relative_to(work / "results/benchmarks/simulate/lab").with_suffix("").parts
                b = pd.read_csv(path, sep="\t").iloc[0]
                stepping = runs[(runs.engine == engine) & (runs.terrain == terrain)].wall_time.sum()
                job_rows.append({"engine": engine, "wall": b["s"], "stepping": stepping, "rss": b["max_rss"]})
            sweep = copy.deepcopy(config)
            base_terrain = config["terrains"]["grass"]
            sweep["terrains"] = {f"grass{i}": dict(base_terrain, friction=0.1 + 0.02 * i) for i in range(25)}
            base_motion = config["motions"]["straight"]
            n_motions = 1000 // (len(sweep["engines"]) * 25)
            sweep["motions"] = {f"straight{i}": dict(base_motion, v=0.1 + 0.01 * i) for i in range(n_motions)}
            assert len(sweep["engines"]) * 25 * n_motions == 1000, "the sweep must have 1000 lab cases"
            sweep["cpu_load"].update(terrain="grass0", motion="straight0")
            config_path.write_text(yaml.safe_dump(sweep, sort_keys=False))
            shutil.rmtree(work / "results")
            dry.append(snakemake(work, "-n", "--quiet"))
    rows.append({"measure": "default_study_wall_s", **spread(study)})
    rows.append({"measure": "rerun_after_weight_edit_wall_s", **spread(rerun)})
    rows.append({"measure": "rerun_after_weight_edit_html_s", **spread(to_html)})
    rows.append({"measure": "dry_run_1000_cases_wall_s", **spread(dry)})
    jobs = pd.DataFrame(job_rows)
    for engine, g in jobs.groupby("engine"):
        fixed = (g.wall - g.stepping).tolist()
        rows.append({"measure": "simulate_job_fixed_cost_s", "engine": engine, **spread(fixed)})
        rows.append({"measure": "simulate_job_peak_rss_mb", "engine": engine, **spread(g.rss.tolist())})
    return rows


def lab_rtf(rows: list[dict], config: dict) -> list[dict]:
    """Real-time factor of the lab study per engine, from the job throughput on each terrain."""
    out = []
    job = [r for r in rows if r["measure"] == "steps_per_s_job"]
    dt = config["physics"]["timestep"]
    for engine in config["engines"]:
        rates = [r["median"] for r in job if r["engine"] == engine]
        # every terrain is driven for the same simulated time: harmonic mean of the rates
        rtf = len(rates) / sum(1 / r for r in rates) * dt
        out.append({"measure": "rtf_lab_study", "engine": engine, "median": rtf, "n": len(rates)})
    return out


def verdict(row: dict) -> str:
    target = TARGETS.get((row["measure"], row.get("engine")), TARGETS.get(row["measure"]))
    if target is None or pd.isna(row.get("median")):
        return ""
    op, bound = target
    ok = row["median"] >= bound if op == ">=" else row["median"] <= bound
    return f"{'met' if ok else 'MISSED'} ({op} {bound:g})"


def machine() -> str:
    cpu = platform.processor() or ""
    try:
        cpu = next(line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return (
        f"{cpu}, {psutil.cpu_count()} cores, {psutil.virtual_memory().total / 2**30:.0f} GiB, "
        f"Python {platform.python_version()}, {platform.system()} {platform.release()}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--pipeline-repeats", type=int, default=2)
    parser.add_argument(
        "--real-data",
        action="store_true",
        help="also the BorealTC replay and DRIVE step jobs against the bare loop (process CPU; DART and Drake "
        "make this about 10 minutes longer)",
    )
    parser.add_argument(
        "--only",
        choices=("engines", "pipeline"),
        help="measure one part again, keeping the other part's rows from bench/results.csv",
    )
    args = parser.parse_args()
    config = yaml.safe_load((ROOT / "config.yaml").read_text())
    rows: list[dict] = []
    if args.only != "pipeline":
        rows = engine_throughput(config, args.repeats)
        rows += lab_rtf(rows, config)
        if args.real_data:
            rows += real_data_throughput(config, args.repeats)
    if args.only != "engines":
        rows += pipeline(args.pipeline_repeats)
    if args.only:
        kept = pd.read_csv(ROOT / "bench/results.csv").drop(columns=["target"])
        engine_measures = kept.measure.str.startswith(("steps_per_s", "job_vs_bare", "rtf_lab"))
        kept = kept[~engine_measures] if args.only == "engines" else kept[engine_measures]
        rows = kept.to_dict("records") + rows
        rows = [{k: v for k, v in r.items() if not (isinstance(v, float) and pd.isna(v))} for r in rows]
    table = pd.DataFrame(rows)
    table["target"] = [verdict(r) for r in table.to_dict("records")]
    table.to_csv(ROOT / "bench/results.csv", index=False, float_format="%.4g")

    lines = [
        f"Measured {time.strftime('%Y-%m-%d')} on {machine()}.",
        "",
        "| measure | engine | terrain | median | min | max | n | target |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in table.fillna("").to_dict("records"):
        fmt = lambda v: f"{v:.3g}" if isinstance(v, float) else str(v)  # noqa: E731
        lines.append(
            f"| {r['measure']} | {r.get('engine', '')} | {r.get('terrain', '')} | {fmt(r['median'])} | "
            f"{fmt(r.get('min', ''))} | {fmt(r.get('max', ''))} | {fmt(r.get('n', ''))} | {r['target']} |"
        )
    text = "\n".join(lines) + "\n"
    (ROOT / "bench/RESULTS.md").write_text("# simpick benchmark\n\n" + text)
    page = ROOT / "docs/benchmark.md"  # its "The last `make bench` table" section
    body = page.read_text()
    if "<!-- bench:start -->" in body:
        body = re.sub(
            r"<!-- bench:start -->.*<!-- bench:end -->",
            lambda _: "<!-- bench:start -->\n" + text + "<!-- bench:end -->",
            body,
            flags=re.S,
        )
        page.write_text(body)
    print(text)


if __name__ == "__main__":
    main()
