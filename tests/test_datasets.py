"""Dataset folders of any numbering, class names and sample rates: what is accepted, what is
refused before any job (one `simpick:` line each), and what the readers measure."""

import numpy as np
import pytest
import yaml

from conftest import (
    SHARED,
    planned_jobs,
    snakemake,
    study_config,
    synthetic_run,
    tiny_config,
    write_config,
    write_dataset,
)
from simpick.errors import InputError
from simpick.real.datasets import DatasetProblems, dataset_name, find_runs, open_dataset, run_key
from simpick.real.logs import borealtc
from simpick.simulate.imu import ImuModel, model_at_rate

BOREALTC = SHARED / "data" / "borealtc"
CONFIG = study_config()
CLASSES = CONFIG["real_data"]["classes"]
needs_borealtc = pytest.mark.skipif(not BOREALTC.is_dir(), reason=f"BorealTC logs not found at {BOREALTC}")


def problems(folder, classes=CLASSES, **kwargs) -> list[str]:
    with pytest.raises(DatasetProblems) as info:
        open_dataset(folder, classes=classes, **kwargs)
    return [str(p) for p in info.value.problems]


# ---------------------------------------------------------------- layout


def test_any_run_numbering_in_natural_order(tmp_path):
    write_dataset(tmp_path / "yard", {"ICE": ["12", "1", "7", "01"], "SNOW": ["3"]}, seconds=2.0)
    runs = find_runs(tmp_path / "yard")
    assert [(r.terrain_class, r.run) for r in runs] == [
        ("ice", "01"),
        ("ice", "1"),
        ("ice", "7"),
        ("ice", "12"),
        ("snow", "3"),
    ]
    assert runs[0].folder == "ICE" and runs[0].imu.name == "imu_01.csv" and runs[0].pro.name == "pro_01.csv"
    assert sorted(["10", "9", "b", "2a"], key=run_key) == ["2a", "9", "10", "b"]


def test_other_files_and_hidden_folders_are_ignored(tmp_path):
    root = write_dataset(tmp_path / "yard", {"ICE": ["1"]}, seconds=2.0)
    (root / "README.md").write_text("notes")
    (root / "ICE" / "notes.txt").write_text("windy")
    (root / ".git").mkdir()
    assert [(r.terrain_class, r.run) for r in find_runs(root)] == [("ice", "1")]


def test_unknown_class_names_class_folder_and_config_key(tmp_path):
    root = write_dataset(tmp_path / "yard", {"CONCRETE": ["1"], "DIRT_ROAD": ["2"], "ICE": ["3"]}, seconds=2.0)
    lines = problems(root)
    assert len(lines) == 2
    assert lines[0].startswith(f"{root / 'CONCRETE'}: terrain class 'concrete' has no ground model")
    assert "real_data.classes" in lines[0] and "--configfile" in lines[0]
    assert "{concrete: {friction: 0.6, source:" in lines[0]
    assert "'dirt_road'" in lines[1] and str(root / "DIRT_ROAD") in lines[1]
    known = {**CLASSES, "concrete": {"friction": 0.7, "source": "test"}, "dirt_road": {"friction": 0.6, "source": "t"}}
    assert open_dataset(root, classes=known).classes == ["concrete", "dirt_road", "ice"]


def test_unpaired_file_is_named_with_its_missing_partner(tmp_path):
    root = write_dataset(tmp_path / "yard", {"ICE": ["1", "2"]}, seconds=2.0)
    (root / "ICE" / "pro_2.csv").unlink()
    (root / "ICE" / "pro_9.csv").write_text("time\n0\n")
    lines = problems(root)
    assert lines == [
        f"{root / 'ICE' / 'imu_2.csv'}: has no partner pro_2.csv in {root / 'ICE'} "
        "(fix: restore the missing file or remove this one)",
        f"{root / 'ICE' / 'pro_9.csv'}: has no partner imu_9.csv in {root / 'ICE'} "
        "(fix: restore the missing file or remove this one)",
    ]


def test_empty_class_folder_is_refused(tmp_path):
    root = write_dataset(tmp_path / "yard", {"ICE": ["1"]}, seconds=2.0)
    (root / "SNOW").mkdir()
    (root / "SNOW" / "README").write_text("to do")
    assert problems(root) == [
        f"{root / 'SNOW'}: terrain-class folder holds no imu_<run>.csv / pro_<run>.csv "
        "pair (fix: add its runs or remove the folder)"
    ]


@pytest.mark.parametrize(
    "case, words",
    [
        ("missing", "dataset folder not found"),
        ("empty", "is empty: no terrain-class sub-folders"),
        ("not_a_dataset", "is not a dataset folder: none of its 2 sub-folder(s) holds"),
        ("class_folder", "it looks like one terrain-class folder, not a dataset (fix: pass its parent folder"),
        (
            "bad_class_name",
            "terrain-class folder name 'Dirt Road' may hold only letters, digits and '_' "
            "(fix: rename the folder, e.g. to DIRT_ROAD)",
        ),
        ("bad_run_id", "run id 'run 3' may hold only letters"),
        ("same_class_twice", "terrain class 'ice' appears twice"),
    ],
)
def test_folders_that_are_not_datasets(tmp_path, case, words):
    root = tmp_path / "data"
    if case == "empty":
        root.mkdir()
    elif case == "not_a_dataset":
        (root / "src").mkdir(parents=True)
        (root / "docs").mkdir()
        (root / "src" / "main.py").write_text("")
    elif case == "class_folder":
        write_dataset(tmp_path, {"data": ["1"]}, seconds=2.0)
    elif case == "bad_class_name":
        write_dataset(root, {"Dirt Road": ["1"]}, seconds=2.0)
    elif case == "bad_run_id":
        write_dataset(root, {"ICE": ["1", "run 3"]}, seconds=2.0)
    elif case == "same_class_twice":
        write_dataset(root, {"ICE": ["1"], "Ice": ["2"]}, seconds=2.0)
    lines = problems(root)
    assert len(lines) >= 1 and words in lines[0], lines


def test_dataset_name_from_folder_or_given(tmp_path):
    assert dataset_name(tmp_path / "BorealTC Other") == "borealtc_other"
    assert dataset_name(tmp_path / "x", "yard-2024") == "yard-2024"
    with pytest.raises(InputError, match="reserved"):
        dataset_name(tmp_path / "own")
    with pytest.raises(InputError, match="may hold only"):
        dataset_name(tmp_path / "x", "a/b")


def test_a_second_folder_of_the_same_name_is_refused(tmp_path):
    first = write_dataset(tmp_path / "a" / "yard", {"ICE": ["1"]}, seconds=2.0)
    second = write_dataset(tmp_path / "b" / "yard", {"ICE": ["1"]}, seconds=2.0)
    results = tmp_path / "results" / "real"
    (results / "yard").mkdir(parents=True)
    (results / "yard" / "dataset.yaml").write_text(yaml.safe_dump({"folder": str(first.resolve())}))
    assert open_dataset(first, classes=CLASSES, results=results).name == "yard"
    lines = problems(second, results=results)
    assert f"holds the results of dataset folder {first.resolve()}" in lines[0]
    assert "--config real_dataset=OTHER_NAME" in lines[0]
    assert open_dataset(second, classes=CLASSES, results=results, name="yard_b").name == "yard_b"


@needs_borealtc
def test_the_shared_borealtc_folder_is_a_dataset():
    dataset = open_dataset(BOREALTC, classes=CLASSES, results="/nonexistent")
    assert dataset.name == "borealtc" and dataset.classes == ["asphalt", "flooring", "ice", "sandy_loam", "snow"]
    assert len(dataset.runs) == len(list(BOREALTC.glob("*/imu_*.csv"))) == 29
    log = borealtc.read_run(
        dataset.runs[0].imu, dataset.runs[0].pro, dataset.runs[0].folder, imu_rate_hz=100, command_rate_hz=6.5
    )
    assert log.meta["rates"]["imu"]["median_hz"] == pytest.approx(100.0)
    assert log.meta["rates"]["commands"]["median_hz"] == pytest.approx(6.5)


# ---------------------------------------------------------------- rates


def write_pair(folder, imu, pro, run="1"):
    folder.mkdir(parents=True, exist_ok=True)
    imu.to_csv(folder / f"imu_{run}.csv", index=False)
    pro.to_csv(folder / f"pro_{run}.csv", index=False)
    return folder / f"imu_{run}.csv", folder / f"pro_{run}.csv"


def test_50_hz_imu_and_15_hz_commands_are_measured_not_assumed(tmp_path):
    imu, pro = write_pair(tmp_path / "CONCRETE", *synthetic_run(imu_hz=50.0, cmd_hz=15.0))
    log = borealtc.read_run(imu, pro, "CONCRETE", dataset="yard")
    assert log.meta["rates"]["imu"]["median_hz"] == pytest.approx(50.0)
    assert log.meta["rates"]["commands"]["median_hz"] == pytest.approx(15.0)
    assert log.meta["dataset"] == "yard" and "license" not in log.meta
    declared = borealtc.read_run(imu, pro, "CONCRETE", imu_rate_hz=50, command_rate_hz=15)
    assert declared.meta["rates"]["declared_hz"] == {"imu": 50, "commands": 15}


def test_a_declared_rate_the_data_contradict_is_refused(tmp_path):
    imu, pro = write_pair(tmp_path / "CONCRETE", *synthetic_run(imu_hz=50.0, cmd_hz=15.0))
    by = "real_data.datasets.yard in the config"
    with pytest.raises(InputError) as info:
        borealtc.read_run(imu, pro, "CONCRETE", imu_rate_hz=100, declared_by=by)
    assert str(info.value) == (
        f"{imu}: column 'time': measured IMU sample rate 50 Hz (median interval 0.02 s) "
        f"contradicts the declared 100 Hz of {by} (-50 %) "
        "(fix: correct the declared rate, or check the time unit (s, ms, ns))"
    )
    with pytest.raises(
        InputError,
        match=r"pro_1\.csv: column 'time': measured command sample rate 15 Hz .*"
        r"declared 6\.5 Hz",
    ):
        borealtc.read_run(imu, pro, "CONCRETE", command_rate_hz=6.5, declared_by=by)


def test_gaps_jitter_and_duplicates_name_the_rows(tmp_path):
    imu, pro = synthetic_run(imu_hz=50.0, cmd_hz=15.0)
    gap = imu[(imu.time < 3.0) | (imu.time >= 5.0)]  # 2 s missing
    with pytest.raises(
        InputError,
        match=r"imu_1\.csv: column 'time': the IMU stream stops for 2\.02 s "
        r"\(101 median intervals\) between row 150 \(line 151\) \(time 2\.98\) "
        r"and row 151 \(line 152\) \(time 5\)",
    ):
        borealtc.read_run(*write_pair(tmp_path / "A", gap, pro), "A")
    jitter = pro.copy()
    jitter["time"] = np.cumsum(np.random.default_rng(1).choice([0.02, 0.1], len(pro)))
    with pytest.raises(
        InputError,
        match=r"pro_1\.csv: column 'time': the command stream has no steady rate: "
        r"\d+ % of its sample intervals",
    ):
        borealtc.read_run(*write_pair(tmp_path / "B", imu, jitter), "B")
    dup = imu.copy()
    dup.loc[10, "time"] = dup.loc[9, "time"]
    with pytest.raises(
        InputError,
        match=r"imu_1\.csv: column 'time': time is not strictly increasing: "
        r"0\.18 at row 11 \(line 12\) duplicates",
    ):
        borealtc.read_run(*write_pair(tmp_path / "C", dup, pro), "C")
    few = imu.drop(index=range(20, 24))  # 0.1 s: a harmless hole, interpolated over
    borealtc.read_run(*write_pair(tmp_path / "D", few, pro), "D")


def test_the_simulated_imu_is_read_out_at_the_real_rate():
    settings = {k: v for k, v in CONFIG["imu"].items()}
    assert model_at_rate(settings, 100.0, 0.001) == ImuModel(**settings)
    at50 = model_at_rate(settings, 49.97, 0.001)  # measured: a hair off 50 Hz
    assert at50.rate_hz == pytest.approx(50.0)
    assert at50.accel_noise_std == pytest.approx(settings["accel_noise_std"] * np.sqrt(0.5))
    assert at50.gyro_noise_std == pytest.approx(settings["gyro_noise_std"] * np.sqrt(0.5))
    assert model_at_rate(settings, 30.0, 0.001).rate_hz == pytest.approx(1000 / 33)  # whole steps per sample


# ---------------------------------------------------------------- before any job (Snakemake)


@pytest.mark.workflow
@pytest.mark.parametrize(
    "case, expected",
    [
        ("unknown_class", "terrain class 'concrete' has no ground model (fix: add it under real_data.classes"),
        ("unpaired", "imu_7.csv: has no partner pro_7.csv in"),
        ("empty_class_folder", "terrain-class folder holds no imu_<run>.csv / pro_<run>.csv pair"),
        ("not_a_dataset", "is not a dataset folder: none of its 1 sub-folder(s)"),
        ("maintain_other_dataset", "segments.csv, the table of dataset 'borealtc', but"),
    ],
)
def test_bad_dataset_folder_stops_the_run_before_any_job(tmp_path, case, expected):
    folder = tmp_path / "yard"
    if case == "unknown_class":
        write_dataset(folder, {"CONCRETE": ["1"]}, seconds=2.0)
    elif case == "unpaired":
        write_dataset(folder, {"ICE": ["1", "7"]}, seconds=2.0)
        (folder / "ICE" / "pro_7.csv").unlink()
    elif case == "empty_class_folder":
        write_dataset(folder, {"ICE": ["1"]}, seconds=2.0)
        (folder / "SNOW").mkdir()
    elif case == "not_a_dataset":
        (folder / "photos").mkdir(parents=True)
        (folder / "photos" / "a.jpg").write_text("")
    else:  # a fine dataset, but not the one the committed table comes from
        write_dataset(folder, {"ICE": ["1"]}, seconds=2.0)
    config = tiny_config(tmp_path)
    config["borealtc_dir"] = str(folder)
    write_config(tmp_path, config)
    run = snakemake(tmp_path, "-n", *(["maintain_segments"] if case.startswith("maintain") else []))
    assert run.returncode != 0
    text = run.stdout + run.stderr
    lines = [line for line in text.splitlines() if line.startswith("simpick:")]
    assert len(lines) == 1 and expected in lines[0], text[-2000:]
    assert "Traceback" not in text and "Exception" not in text
    assert not (tmp_path / "results").exists()  # no job ran


@pytest.mark.workflow
def test_the_committed_tables_own_folder_is_not_simulated_a_second_time(tmp_path):
    """The shared BorealTC folder's derived segment table is the committed one (tests/test_realdata.py
    checks a fresh derivation against it): replaying that folder derives the table (a result) but
    simulates no source "<dataset>-segments" beside "segments", which holds the same cases."""
    config = tiny_config(tmp_path)
    config["borealtc_dir"] = str(SHARED / "data" / "borealtc")
    write_config(tmp_path, config)
    jobs = planned_jobs(tmp_path)
    dry = snakemake(tmp_path, "-n")
    assert "real_segments" in dry.stdout + dry.stderr  # the folder's own table is still derived (a checkpoint)
    # its runs are replayed, a job per model and terrain class (simpick.plan.sources.BATCHED_KINDS)
    assert {rule for rule, _ in jobs if rule.startswith("simulate_borealtc_")} == {
        f"simulate_borealtc_{c}" for c in ("asphalt", "flooring", "ice", "sandy_loam", "snow")
    }
    assert not [w for _, w in jobs if "borealtc-segments" in w]
