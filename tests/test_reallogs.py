"""Real-log readers: BorealTC, generic CSV with a mapping, the canonical Parquet file, and
the validation that turns every malformed input into an InputError naming file, column, row."""

from __future__ import annotations

import json
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from simpick.errors import InputError
from simpick.real.logs import RealLog, body_to_wheels, borealtc, csvlog, read_canonical, wheels_to_body, write_canonical
from simpick.real.logs.canonical import METADATA_KEY, SCHEMA

ROOT = Path(__file__).resolve().parents[1]
BOREALTC = ROOT.parent / "shared" / "data" / "borealtc"
needs_borealtc = pytest.mark.skipif(
    not BOREALTC.is_dir(),
    reason=f"BorealTC data not present at {BOREALTC} (download data/borealtc from "
    "github.com/norlab-ulaval/BorealTC to run these tests)",
)


# ---------------------------------------------------------------- synthetic runs


def synthetic(
    seconds: float = 12.0, turn: tuple[float, float] = (0.1, 0.4), gain: float = 0.6, seed: int = 0
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """A BorealTC-shaped run: 100 Hz IMU, 6.5 Hz wheels; straight, then a left turn."""
    rng = np.random.default_rng(seed)
    tp = np.arange(0, seconds, 1 / 6.5)
    half = tp >= seconds / 2
    vel_l = np.where(half, turn[0], 0.3)
    vel_r = np.where(half, turn[1], 0.3)
    pro = pd.DataFrame(
        {"time": tp, "curL": 5 + rng.random(len(tp)), "curR": 5 + rng.random(len(tp)), "velL": vel_l, "velR": vel_r}
    )
    ti = np.arange(0, int(seconds * 100)) / 100.0
    yaw_cmd = np.interp(ti, tp, (vel_r - vel_l) / 0.555)
    n = len(ti)
    imu = pd.DataFrame(
        {
            "time": ti,
            "wx": 0.01 * rng.standard_normal(n),
            "wy": 0.01 * rng.standard_normal(n),
            "wz": gain * yaw_cmd + 0.01 * rng.standard_normal(n),
            "ax": 0.2 * rng.standard_normal(n),
            "ay": 0.2 * rng.standard_normal(n),
            "az": 9.81 + 0.2 * rng.standard_normal(n),
        }
    )
    return imu, pro


def write_run(
    folder: Path, imu: pd.DataFrame | str | None = None, pro: pd.DataFrame | str | None = None, run: str = "00"
) -> tuple[Path, Path]:
    folder.mkdir(parents=True, exist_ok=True)
    good_imu, good_pro = synthetic()
    paths = []
    for name, value, default in (("imu", imu, good_imu), ("pro", pro, good_pro)):
        path = folder / f"{name}_{run}.csv"
        value = default if value is None else value
        if isinstance(value, str):
            path.write_text(value)
        else:
            value.to_csv(path, index=False)
        paths.append(path)
    return paths[0], paths[1]


def expect_error(
    imu=None,
    pro=None,
    *,
    tmp: Path,
    file: str,
    column: str | None = None,
    row: str | None = None,
    words: tuple[str, ...] = (),
    **options,
) -> InputError:
    imu_path, pro_path = write_run(tmp / "ASPHALT", imu, pro)
    with pytest.raises(InputError) as info:
        borealtc.read_run(imu_path, pro_path, "ASPHALT", **options)
    message = str(info.value)
    path = imu_path if file == "imu" else pro_path
    assert str(path) in message, message
    if column is not None:
        assert f"'{column}'" in message, message
    if row is not None:
        assert row in message, message
    for word in words:
        assert word in message, message
    return info.value


# ---------------------------------------------------------------- BorealTC (real data)


@needs_borealtc
def test_discover_finds_every_run_of_the_five_classes():
    runs = borealtc.discover(BOREALTC)
    classes = {cls for cls, *_ in runs}
    assert classes == set(borealtc.TERRAIN_CLASSES)
    on_disk = sorted(BOREALTC.glob("*/imu_*.csv"))
    assert len(runs) == len(on_disk) > 5
    for cls, run_id, imu, pro in runs:
        assert imu.parent.name == pro.parent.name == cls
        assert imu.name == f"imu_{run_id}.csv" and pro.name == f"pro_{run_id}.csv"
        assert imu.is_file() and pro.is_file()


@needs_borealtc
def test_asphalt_00_rates_gravity_and_yaw_sign():
    log = borealtc.read_run(BOREALTC / "ASPHALT" / "imu_00.csv", BOREALTC / "ASPHALT" / "pro_00.csv", "ASPHALT")
    assert list(log.imu.columns) == ["time", "ax", "ay", "az", "wx", "wy", "wz"]
    assert list(log.commands.columns)[:3] == ["time", "v_left", "v_right"]
    assert log.command_kind == "wheels"
    dt_imu = np.median(np.diff(log.imu["time"]))
    dt_cmd = np.median(np.diff(log.commands["time"]))
    assert 1 / dt_imu == pytest.approx(100.0, rel=0.01)
    assert 1 / dt_cmd == pytest.approx(6.5, rel=0.02)
    assert log.imu["az"].mean() == pytest.approx(9.8, abs=0.5)
    assert log.imu["time"].iloc[0] == 0.0 and log.commands["time"].iloc[0] == pytest.approx(0.0, abs=1e-9)
    assert log.meta["terrain_class"] == "ASPHALT" and log.meta["run_id"] == "00"
    assert log.meta["dataset"] == "BorealTC"
    assert log.meta["units"]["az"] == "m/s^2" and log.meta["units"]["wz"] == "rad/s"
    assert log.meta["rates"]["imu"]["median_hz"] == pytest.approx(100.0, rel=0.01)
    yaw = log.meta["checks"]["yaw"]
    assert yaw["verdict"] == "consistent"
    assert 0.0 < yaw["yaw_gain"] < 1.0  # skid-steer slip: measured yaw below commanded
    assert log.meta["source_files"]["imu"]["sha256"]


@needs_borealtc
def test_every_borealtc_run_reads_and_none_contradicts_the_frame():
    for cls, run_id, imu, pro in borealtc.discover(BOREALTC):
        log = borealtc.read_run(imu, pro, cls)
        assert log.meta["checks"]["yaw"]["verdict"] in ("consistent", "undetermined"), (cls, run_id)
        assert 9.3 < log.meta["checks"]["imu"]["gravity_estimate"] < 10.3


@needs_borealtc
def test_canonical_round_trip_of_real_run(tmp_path):
    log = borealtc.read_run(BOREALTC / "ASPHALT" / "imu_00.csv", BOREALTC / "ASPHALT" / "pro_00.csv", "ASPHALT")
    path = write_canonical(log, tmp_path / "ASPHALT_00.parquet")
    assert [p.name for p in tmp_path.iterdir()] == ["ASPHALT_00.parquet"]  # no temp file left
    back = read_canonical(path)
    pd.testing.assert_frame_equal(back.imu, log.imu)
    pd.testing.assert_frame_equal(back.commands, log.commands)
    assert back.meta == log.meta
    meta = json.loads(pq.read_schema(path).metadata[METADATA_KEY])
    assert meta["schema"] == SCHEMA and meta["units"]["ax"] == "m/s^2"
    assert meta["meta"]["source_files"]["imu"]["path"].endswith("imu_00.csv")


# ---------------------------------------------------------------- BorealTC layout (synthetic)


def test_synthetic_run_reads(tmp_path):
    imu, pro = write_run(tmp_path / "ICE")
    log = borealtc.read_run(imu, pro, "ICE")
    assert len(log.imu) == 1200 and log.meta["checks"]["yaw"]["verdict"] == "consistent"
    assert log.meta["checks"]["yaw"]["yaw_gain"] == pytest.approx(0.6, abs=0.05)


def test_discover_missing_partner_names_the_file(tmp_path):
    write_run(tmp_path / "SNOW", run="01")
    (tmp_path / "SNOW" / "imu_02.csv").write_text("time,wx\n")
    with pytest.raises(InputError, match=r"imu_02\.csv.*pro_02\.csv"):
        borealtc.discover(tmp_path)
    (tmp_path / "SNOW" / "imu_02.csv").unlink()
    (tmp_path / "ICE").mkdir()
    (tmp_path / "ICE" / "pro_05.csv").write_text("time\n")
    with pytest.raises(InputError, match=r"pro_05\.csv.*imu_05\.csv"):
        borealtc.discover(tmp_path)


def test_discover_missing_folder_and_empty_folder(tmp_path):
    with pytest.raises(InputError, match="not found"):
        borealtc.discover(tmp_path / "nope")
    with pytest.raises(InputError, match="is empty: no terrain-class sub-folders"):
        borealtc.discover(tmp_path)


def test_contradicting_yaw_sign_is_reported_not_flipped(tmp_path):
    imu, pro = synthetic()
    imu["wz"] = -imu["wz"]
    log = borealtc.read_run(*write_run(tmp_path / "ICE", imu, pro), "ICE")
    assert log.meta["checks"]["yaw"]["verdict"] == "contradicts"
    assert (log.imu["wz"].to_numpy() == imu["wz"].to_numpy()).all()


# ---------------------------------------------------------------- malformed logs


def test_missing_file(tmp_path):
    imu, pro = write_run(tmp_path / "ICE")
    with pytest.raises(InputError, match=r"pro_00\.csv.*not found"):
        borealtc.read_run(imu, tmp_path / "ICE" / "nothing" / "pro_00.csv", "ICE")
    with pytest.raises(InputError, match="not found"):
        borealtc.read_run(tmp_path / "imu_77.csv", pro, "ICE")


def test_missing_column(tmp_path):
    imu, _ = synthetic()
    err = expect_error(imu.drop(columns=["wz"]), tmp=tmp_path, file="imu", column="wz", words=("missing",))
    assert "columns present" in err.problem


@pytest.mark.parametrize("mutate, kind", [("dup", "duplicates"), ("back", "goes backwards")])
def test_unsorted_or_duplicated_time_names_the_row(tmp_path, mutate, kind):
    imu, _ = synthetic()
    t = imu["time"].to_numpy().copy()
    if mutate == "dup":
        t[50] = t[49]
    else:
        t[50] = t[48]
    imu["time"] = t
    expect_error(imu, tmp=tmp_path, file="imu", column="time", row="row 51 (line 52)", words=(kind,))


def test_duplicated_time_in_wheel_file(tmp_path):
    _, pro = synthetic()
    pro = pd.concat([pro.iloc[:10], pro.iloc[9:]], ignore_index=True)
    expect_error(pro=pro, tmp=tmp_path, file="pro", column="time", row="row 11 (line 12)")


def test_nan_value_names_column_and_row(tmp_path):
    imu, _ = synthetic()
    imu.loc[100, "ax"] = np.nan
    expect_error(imu, tmp=tmp_path, file="imu", column="ax", row="row 101 (line 102)", words=("NaN",))


def test_empty_cell_names_column_and_row(tmp_path):
    imu, _ = synthetic()
    text = imu.to_csv(index=False).splitlines()
    cells = text[8].split(",")
    cells[3] = ""
    text[8] = ",".join(cells)
    expect_error("\n".join(text) + "\n", tmp=tmp_path, file="imu", column="wz", row="line 9")


def test_infinite_value_names_column_and_row(tmp_path):
    imu, pro = synthetic()
    imu.loc[7, "wy"] = np.inf
    expect_error(imu, tmp=tmp_path, file="imu", column="wy", row="row 8 (line 9)", words=("infinite",))
    pro.loc[3, "velR"] = -np.inf
    expect_error(pro=pro, tmp=tmp_path, file="pro", column="velR", row="row 4 (line 5)")


def test_empty_file_and_header_only(tmp_path):
    expect_error("", tmp=tmp_path, file="imu", words=("empty",))
    expect_error(pro="time,curL,curR,velL,velR\n", tmp=tmp_path, file="pro", words=("no data rows",))
    expect_error("\n\n  \n", tmp=tmp_path, file="imu", words=("empty",))


def test_non_numeric_cell(tmp_path):
    imu, _ = synthetic()
    imu = imu.astype({"az": object})
    imu.loc[20, "az"] = "9.8O"
    expect_error(imu, tmp=tmp_path, file="imu", column="az", row="row 21 (line 22)", words=("non-numeric", "9.8O"))


def test_row_with_extra_fields_names_the_line(tmp_path):
    imu, _ = synthetic()
    lines = imu.to_csv(index=False).splitlines()
    lines[30] += ",1.0"
    expect_error("\n".join(lines) + "\n", tmp=tmp_path, file="imu", words=("line 31",))
    lines = imu.to_csv(index=False).splitlines()
    every = [lines[0]] + [line + ",1.0" for line in lines[1:]]  # pandas would drop it silently
    expect_error("\n".join(every) + "\n", tmp=tmp_path, file="imu", words=("line 2", "8 fields"))


def test_duplicated_header_column(tmp_path):
    imu, _ = synthetic()
    text = imu.to_csv(index=False).replace("time,wx,wy,wz,ax,ay,az", "time,wx,wy,wz,ax,ax,az", 1)
    expect_error(text, tmp=tmp_path, file="imu", column="ax", words=("twice",))


def test_gyro_in_deg_per_s_sustained(tmp_path):
    imu, pro = synthetic(turn=(-0.3, 0.6))  # 1.6 rad/s commanded, ~1 rad/s measured
    for c in ("wx", "wy", "wz"):
        imu[c] = np.rad2deg(imu[c])
    expect_error(imu, pro, tmp=tmp_path, file="imu", column="wz", words=("deg/s", "row"))


def test_gyro_in_deg_per_s_caught_against_the_commands(tmp_path):
    imu, pro = synthetic(turn=(0.2, 0.3), gain=0.5)  # 0.18 rad/s commanded: 5 deg/s measured
    for c in ("wx", "wy", "wz"):
        imu[c] = np.rad2deg(imu[c])
    assert imu["wz"].abs().max() < 20
    expect_error(imu, pro, tmp=tmp_path, file="imu", column="wz", words=("deg/s",))


def test_accelerometer_in_g(tmp_path):
    imu, _ = synthetic()
    for c in ("ax", "ay", "az"):
        imu[c] = imu[c] / 9.80665
    expect_error(imu, tmp=tmp_path, file="imu", column="az", words=("looks like g",))


def test_gravity_removed_or_z_down(tmp_path):
    imu, _ = synthetic()
    imu["az"] = imu["az"] - 9.81
    expect_error(imu, tmp=tmp_path, file="imu", words=("gravity seems removed",))
    imu["az"] = -9.81 - imu["az"]
    expect_error(imu, tmp=tmp_path, file="imu", column="az", words=("z does not point up",))


def test_wheel_speed_not_in_m_per_s(tmp_path):
    _, pro = synthetic()
    pro["velL"] = pro["velL"] * 1000  # mm/s
    expect_error(pro=pro, tmp=tmp_path, file="pro", column="velL", row="row 1 (line 2)", words=("exceeds",))


def test_sample_rate_mismatch(tmp_path):
    declared = {"imu_rate_hz": 100.0, "command_rate_hz": 6.5, "declared_by": "real_data.datasets.x"}
    imu, pro = synthetic()
    imu["time"] = imu["time"] * 1.5  # 66.7 Hz against the declared 100 Hz
    pro["time"] = pro["time"] * 1.5
    expect_error(
        imu,
        pro,
        tmp=tmp_path,
        file="imu",
        column="time",
        words=("measured IMU sample rate 66.67 Hz", "declared 100 Hz of real_data.datasets.x"),
        **declared,
    )
    imu, pro = synthetic()
    pro["time"] = pro["time"] * 0.5  # 13 Hz against 6.5 Hz
    expect_error(imu, pro, tmp=tmp_path, file="pro", column="time", words=("13 Hz", "declared 6.5 Hz"), **declared)
    borealtc.read_run(*write_run(tmp_path / "ICE", imu, pro), "ICE")  # undeclared: measured, not refused


def test_streams_that_do_not_overlap(tmp_path):
    imu, pro = synthetic()
    pro["time"] = pro["time"] + 100.0
    expect_error(imu, pro, tmp=tmp_path, file="pro", column="time", words=("overlap",))


# ---------------------------------------------------------------- property test

_TOKENS = st.sampled_from(
    [
        "time",
        "wx",
        "wy",
        "wz",
        "ax",
        "ay",
        "az",
        "curL",
        "curR",
        "velL",
        "velR",
        "0",
        "0.01",
        "9.81",
        "-1e3",
        "1e400",
        "nan",
        "NaN",
        "inf",
        "-inf",
        "",
        "abc",
        "True",
        '"',
        '"a,b"',
        " ",
        "\t",
        "1,2",
        "0x1f",
        "é",
        "\\",
        "#",
    ]
)
_LINE = st.lists(_TOKENS, min_size=0, max_size=9).map(",".join)
_CSV_TEXT = st.one_of(
    st.lists(_LINE, min_size=0, max_size=12).map("\n".join),
    st.builds(lambda head, rows: "\n".join(["time,wx,wy,wz,ax,ay,az", *rows]), _LINE, st.lists(_LINE, max_size=12)),
    st.text(max_size=200),
)
_MAPPING = {
    "time": {"column": "time", "unit": "s"},
    "ax": "ax",
    "ay": "ay",
    "az": "az",
    "wx": "wx",
    "wy": "wy",
    "wz": "wz",
    "v_left": "velL",
    "v_right": "velR",
}


_VALID = {"imu": synthetic()[0].to_csv(index=False), "pro": synthetic()[1].to_csv(index=False)}
_VALID["csvlog"] = pd.concat([synthetic()[0], synthetic()[1].drop(columns="time")], axis=1).to_csv(index=False)
_EDIT = st.tuples(
    st.integers(0, 10**6),
    st.sampled_from(["", ",", "\n", "x", "nan", "inf", "9", "-", ".", "e", "1e9", '"', "0.01,"]),
    st.integers(0, 30),
)


def _mutate(text: str, edits: list[tuple[int, str, int]]) -> str:
    for pos, new, length in edits:
        p = pos % (len(text) + 1)
        text = text[:p] + new + text[p + length :]
    return text


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data(), which=st.sampled_from(["imu", "pro", "csvlog"]))
def test_random_malformed_csv_only_raises_input_error(data, which):
    """Random CSV-like text, or a valid file with random edits: an InputError or a clean log."""
    text = data.draw(
        st.one_of(_CSV_TEXT, st.lists(_EDIT, min_size=1, max_size=4).map(lambda edits: _mutate(_VALID[which], edits)))
    )
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "SNOW"
        if which == "csvlog":
            path = folder / "log.csv"
            folder.mkdir()
            path.write_text(text, encoding="utf-8")
            call = lambda: csvlog.read_csv_log(path, _MAPPING)  # noqa: E731
        else:
            imu, pro = write_run(folder, **{which: text})
            call = lambda: borealtc.read_run(imu, pro, "SNOW")  # noqa: E731
        try:
            log = call()
        except InputError as err:
            assert err.where and err.problem
        else:  # accepted: then it must be a clean canonical log
            assert np.isfinite(log.imu.to_numpy()).all()
            assert (np.diff(log.imu["time"]) > 0).all()


# ---------------------------------------------------------------- generic CSV with a mapping


def _raw_log(n: int = 600, rate: float = 100.0) -> pd.DataFrame:
    rng = np.random.default_rng(3)
    t = np.arange(n) / rate
    return pd.DataFrame(
        {
            "t_ms": np.round(t * 1000).astype(int),
            "acc_x": 0.02 * rng.standard_normal(n),
            "acc_y": 0.03 + 0.0 * t,
            "acc_z": -1.0 + 0.01 * rng.standard_normal(n),
            "gyro_x": 1.0 + 0 * t,
            "gyro_y": -2.0 + 0 * t,
            "gyro_z": -17.0 + 0 * t,
            "left_mm_s": 100.0 + 0 * t,
            "right_mm_s": 400.0 + 0 * t,
        }
    )


MAPPING = {
    "time": {"column": "t_ms", "unit": "ms"},
    "ax": {"column": "acc_x", "unit": "g"},
    "ay": {"column": "acc_y", "unit": "g"},
    "az": {"column": "acc_z", "unit": "g"},
    "wx": {"column": "gyro_x", "unit": "deg/s"},
    "wy": {"column": "gyro_y", "unit": "deg/s"},
    "wz": {"column": "gyro_z", "unit": "deg/s"},
    "v_left": {"column": "left_mm_s", "unit": "mm/s"},
    "v_right": {"column": "right_mm_s", "unit": "mm/s"},
    "frame": {"z": "down"},
    "rates": {"imu": 100},
    "meta": {"dataset": "bench", "run_id": "r1", "terrain_class": "grass"},
}


def test_csv_mapping_converts_units_and_frame(tmp_path):
    raw = _raw_log()
    raw.to_csv(tmp_path / "log.csv", index=False)
    log = csvlog.read_csv_log(tmp_path / "log.csv", MAPPING)
    g = 9.80665
    np.testing.assert_allclose(log.imu["time"], raw["t_ms"] / 1000.0)
    np.testing.assert_allclose(log.imu["ax"], raw["acc_x"] * g)
    np.testing.assert_allclose(log.imu["ay"], -raw["acc_y"] * g)  # z down -> z up: y and z flip
    np.testing.assert_allclose(log.imu["az"], -raw["acc_z"] * g)
    assert log.imu["az"].mean() == pytest.approx(9.80665, abs=0.05)
    np.testing.assert_allclose(log.imu["wx"], np.deg2rad(raw["gyro_x"]))
    np.testing.assert_allclose(log.imu["wy"], -np.deg2rad(raw["gyro_y"]))
    np.testing.assert_allclose(log.imu["wz"], -np.deg2rad(raw["gyro_z"]))  # +0.297 rad/s: left turn
    np.testing.assert_allclose(log.commands["v_left"], 0.1)
    np.testing.assert_allclose(log.commands["v_right"], 0.4)
    assert log.meta["checks"]["yaw"]["verdict"] == "consistent"
    assert log.meta["run_id"] == "r1" and log.meta["source_frame"] == {"z": "down"}
    assert "180 deg" in log.meta["frame_conversion"]


def test_csv_sparse_commands_in_one_file(tmp_path):
    raw = _raw_log()
    cmd = raw[["left_mm_s", "right_mm_s"]].astype(float)
    cmd.loc[raw.index % 10 != 0] = np.nan
    raw[["left_mm_s", "right_mm_s"]] = cmd
    raw.to_csv(tmp_path / "log.csv", index=False)
    log = csvlog.read_csv_log(tmp_path / "log.csv", {**MAPPING, "rates": {"imu": 100, "commands": 10}})
    assert len(log.commands) == 60
    np.testing.assert_allclose(log.commands["time"], np.arange(60) * 0.1, atol=1e-12)
    # a row with one command value of the pair is an error naming column and row
    raw.loc[15, "right_mm_s"] = 5.0
    raw.to_csv(tmp_path / "log.csv", index=False)
    with pytest.raises(InputError, match=r"log\.csv.*'left_mm_s'.*row 16 \(line 17\)"):
        csvlog.read_csv_log(tmp_path / "log.csv", MAPPING)


def test_csv_two_files_body_twist(tmp_path):
    raw = _raw_log()
    raw.drop(columns=["left_mm_s", "right_mm_s"]).to_csv(tmp_path / "imu.csv", index=False)
    cmd = pd.DataFrame({"stamp": np.arange(0, 6.0, 0.2), "lin": 0.5, "ang": -20.0})
    cmd.to_csv(tmp_path / "cmd.csv", index=False)
    mapping = {k: v for k, v in MAPPING.items() if k not in ("v_left", "v_right")}
    mapping.update(v="lin", w={"column": "ang", "unit": "deg/s"}, commands_time={"column": "stamp", "unit": "s"})
    mapping["frame"] = {"z": "down"}
    log = csvlog.read_csv_log(tmp_path / "imu.csv", mapping, commands_path=tmp_path / "cmd.csv")
    assert log.command_kind == "body"
    np.testing.assert_allclose(log.commands["v"], 0.5)
    np.testing.assert_allclose(log.commands["w"], np.deg2rad(20.0))  # z down: w flips too
    assert log.meta["checks"]["yaw"]["verdict"] == "consistent"
    np.testing.assert_allclose(log.commands["time"], cmd["stamp"])
    assert set(log.meta["source_files"]) == {"imu", "commands"}


def test_csv_mapping_errors_name_the_key(tmp_path):
    _raw_log().to_csv(tmp_path / "log.csv", index=False)
    bad_unit = {**MAPPING, "wz": {"column": "gyro_z", "unit": "rpm"}}
    with pytest.raises(InputError, match=r"mapping key 'wz'.*unknown unit 'rpm'"):
        csvlog.read_csv_log(tmp_path / "log.csv", bad_unit)
    bad_column = {**MAPPING, "ay": {"column": "accel_y", "unit": "g"}}
    with pytest.raises(InputError, match=r"log\.csv: column 'accel_y' \(mapping key 'ay'\).*not in the file"):
        csvlog.read_csv_log(tmp_path / "log.csv", bad_column)
    with pytest.raises(InputError, match=r"mapping key 'a_x'.*unknown key"):
        csvlog.read_csv_log(tmp_path / "log.csv", {**MAPPING, "a_x": "acc_x"})
    no_cmd = {k: v for k, v in MAPPING.items() if k != "v_right"}
    with pytest.raises(InputError, match=r"mapping key 'v_right'.*missing"):
        csvlog.read_csv_log(tmp_path / "log.csv", no_cmd)
    with pytest.raises(InputError, match=r"mapping key 'frame'"):
        csvlog.read_csv_log(tmp_path / "log.csv", {**MAPPING, "frame": {"z": "sideways"}})


def test_csv_wrong_declared_units_are_caught(tmp_path):
    _raw_log().to_csv(tmp_path / "log.csv", index=False)
    as_si = {**MAPPING, "ax": "acc_x", "ay": "acc_y", "az": "acc_z"}  # really g
    with pytest.raises(InputError, match=r"'acc_z' \(mapping key 'az'\).*looks like g"):
        csvlog.read_csv_log(tmp_path / "log.csv", as_si)
    as_s = {**MAPPING, "time": {"column": "t_ms", "unit": "s"}}  # really ms: 0.1 Hz
    with pytest.raises(InputError, match=r"'t_ms' \(mapping key 'time'\).*Hz"):
        csvlog.read_csv_log(tmp_path / "log.csv", as_s)


# ---------------------------------------------------------------- canonical form


def _small_log(kind: str = "wheels") -> RealLog:
    imu, pro = synthetic(seconds=4.0)
    commands = pro.rename(columns={"velL": "v_left", "velR": "v_right"})[["time", "v_left", "v_right"]]
    if kind == "body":
        commands = wheels_to_body(commands)
    return RealLog(
        imu=imu[["time", "ax", "ay", "az", "wx", "wy", "wz"]],
        commands=commands,
        meta={"dataset": "synthetic", "run_id": "x", "numbers": (1, 2)},
    )


def test_track_conversions_round_trip():
    wheels = pd.DataFrame({"time": [0.0, 1.0], "v_left": [0.1, -0.2], "v_right": [0.4, 0.2]})
    body = wheels_to_body(wheels, track=0.5)
    np.testing.assert_allclose(body["v"], [0.25, 0.0])
    np.testing.assert_allclose(body["w"], [0.6, 0.8])
    pd.testing.assert_frame_equal(body_to_wheels(body, track=0.5), wheels)
    np.testing.assert_allclose(wheels_to_body(wheels)["w"], [0.3 / 0.555, 0.4 / 0.555])
    with pytest.raises(InputError):
        wheels_to_body(wheels, track=0.0)


@pytest.mark.parametrize("kind", ["wheels", "body"])
def test_canonical_round_trip_both_command_kinds(tmp_path, kind):
    log = _small_log(kind)
    path = write_canonical(log, tmp_path / "sub" / "log.parquet")
    back = read_canonical(path)
    pd.testing.assert_frame_equal(back.imu, log.imu)
    pd.testing.assert_frame_equal(back.commands, log.commands)
    assert back.meta == {"dataset": "synthetic", "run_id": "x", "numbers": [1, 2]}
    assert back.command_kind == kind
    streams = pq.read_table(path).column("stream").to_pylist()
    assert streams.count("imu") == len(log.imu) and streams.count("commands") == len(log.commands)


def test_read_canonical_refuses_foreign_or_broken_files(tmp_path):
    with pytest.raises(InputError, match="not found"):
        read_canonical(tmp_path / "none.parquet")
    pd.DataFrame({"a": [1.0]}).to_parquet(tmp_path / "foreign.parquet")
    with pytest.raises(InputError, match="no simpick metadata"):
        read_canonical(tmp_path / "foreign.parquet")
    (tmp_path / "junk.parquet").write_bytes(b"not parquet at all")
    with pytest.raises(InputError, match="not a readable Parquet"):
        read_canonical(tmp_path / "junk.parquet")


def test_write_canonical_refuses_an_invalid_log(tmp_path):
    log = _small_log()
    log.imu.loc[5, "time"] = log.imu.loc[4, "time"]
    with pytest.raises(InputError, match=r"\[imu\].*'time'.*row 6"):
        write_canonical(log, tmp_path / "bad.parquet")
    assert not list(tmp_path.iterdir())
