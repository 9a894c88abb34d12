"""The DRIVE reader (simpick.real.logs.drive) and what the Warthog's steps say (simpick.real.drive).

Fixtures are cut at test time from the shared sessions (a few steps, written under tmp_path); no DRIVE
data is committed. Each quirk of DRIVE's files has its test: a flipped gyro, a duplicate, a folder
label that disagrees with its metadata, a missing column, a file that is not a pickle, a session
folder without metadata.yaml.
"""

import pickle
import warnings

import numpy as np
import pandas as pd
import pytest
import yaml

from conftest import ROOT, SHARED, study_config
from simpick.errors import InputError
from simpick.real import drive as D
from simpick.real.datasets import DatasetProblems
from simpick.real.logs.drive import PICKLE, read_drive, read_session

DRIVE = SHARED / "data" / "drive"
CALIB = DRIVE / "calib_data"
ASPHALT = "warthog_wheels_asphalt"
GRAVEL = "warthog_wheels_gravel_2024_8_6_11h37s32"
GRASS = "warthog_wheels_grass_2024_8_8_16h19s23"
pytestmark = pytest.mark.skipif(
    not CALIB.is_dir(), reason=f"DRIVE sessions not present at {CALIB} (the shared data folder; see its README)"
)

# DRIVE's README ("Sessions"): steps, terrain, gyro sign, gain (steps with |w_kin| > 0.2 rad/s)
README = {
    "warthog_wheels_asphalt": (100, "asphalt", 1, 0.578, 82),
    "warthog_wheels_asphalt_2024_8_7_11h30s30": (100, "asphalt", 1, 0.578, 87),
    "warthog_wheels_grass_2024_8_8_16h19s23": (30, "grass", 1, 0.607, 16),
    "warthog_wheels_grass_2024_7_29_14h46s15": (20, "grass", -1, 0.616, 9),
    "warthog_wheels_gravel_2024_8_6_11h37s32": (100, "gravel", -1, 0.594, 89),
}


def cut(root, source=ASPHALT, *, steps=12, name=None, edit=None, metadata=None):
    """A session folder under ``root`` holding the first ``steps`` steps of a shared session."""
    src, dst = CALIB / source, root / (name or source)
    (dst / "model_training_datasets").mkdir(parents=True)
    (dst / "config_file_used").mkdir()
    for f in (src / "config_file_used").iterdir():
        (dst / "config_file_used" / f.name).write_bytes(f.read_bytes())
    md = yaml.safe_load((src / "metadata.yaml").read_text())
    md.update(metadata or {})
    (dst / "metadata.yaml").write_text(yaml.safe_dump(md))
    with warnings.catch_warnings():  # DRIVE's pickles name numpy.core (an older numpy's), which still loads
        warnings.simplefilter("ignore", DeprecationWarning)
        frame = pd.read_pickle(src / PICKLE).iloc[: 3 * steps].copy()
    (edit or (lambda f: f))(frame).to_pickle(dst / PICKLE)
    return dst


def columns(frame, base):
    return [c for c in frame.columns if c.rsplit("_", 1)[0] == base and c.rsplit("_", 1)[1].isdigit()]


@pytest.fixture(scope="module")
def shared():
    return read_drive(CALIB)


@pytest.fixture(scope="module")
def steps(shared):
    return D.step_table(shared)


def test_the_shared_sessions_give_the_readme_gains(shared, steps):
    assert shared.duplicates == ()
    assert {s.name for s in shared.sessions} == set(README)
    table = D.turning_table(steps).set_index(["terrain_class", "session"])
    for s in shared.sessions:
        n, terrain, sign, gain, turning = README[s.name]
        row = table.loc[(terrain, s.name)]
        assert (len(s.steps), s.terrain_class, s.meta["gyro"]["sign"]) == (n, terrain, sign), s.name
        assert (round(row.gain_median, 3), row.turning_steps) == (gain, turning), s.name
        # the lidar agrees with the gyro (sign fixed): the ICP gain within 8 % of the gyro's
        assert row.gain_icp_median == pytest.approx(row.gain_median, rel=0.08), s.name
        assert abs(s.meta["gyro"]["correlation"]) > 0.99
        assert s.meta["gyro_copy_column"] == {"column": "icp_vel_yaw", "equals_imu_yaw": True, "used": False}
    assert table.loc[("asphalt", "all")].steps == 200


def test_the_real_warthog_is_repeatable_between_similar_commands(steps):
    """Steps of similar command turn alike (the floor a model is judged against); the gain's spread over
    all commands is several times wider: it depends on the command."""
    table = D.turning_table(steps).set_index(["terrain_class", "session"])
    for terrain in ("asphalt", "gravel"):
        row = table.loc[(terrain, "all")]
        assert row.similar_pairs >= 10
        assert row.repeat_median_abs_diff < 0.5 * (row.gain_q75 - row.gain_q25)
    pairs = D.similar_pairs(steps[steps.session == ASPHALT])
    both = steps.set_index(["session", "step"])
    for p in pairs.itertuples():
        a, b = both.loc[(p.session_a, p.step_a)], both.loc[(p.session_b, p.step_b)]
        assert abs(a.cmd_left - b.cmd_left) <= D.SIMILAR and abs(a.cmd_right - b.cmd_right) <= D.SIMILAR


def test_the_lidar_speed_is_below_the_kinematic_speed(steps):
    table = D.turning_table(steps).set_index(["terrain_class", "session"])
    for terrain in ("asphalt", "grass", "gravel"):
        row = table.loc[(terrain, "all")]
        assert 0.85 < row.speed_ratio_median < 1.0, terrain  # longitudinal slip: the wheels outrun the robot
        assert row.speed_steps >= 30


def test_an_icp_window_moving_against_the_wheels_is_left_out_of_the_speed(tmp_path, shared):
    """A steady window whose ICP motion runs against the driven wheels (the shared asphalt session's step 18,
    and any window whose ICP translation is turned half a turn) is counted and not used for the step's speed;
    its other steady window gives the speed, and the yaw is untouched."""
    from simpick.real.logs.drive import REVERSED_SPEED

    asphalt = next(s for s in shared.sessions if s.name == ASPHALT)
    st = asphalt.steps.set_index("step")
    assert st.loc[18, "icp_reversed"] == 1 and st.icp_reversed.sum() == 4  # steps 18, 71, 92, 98
    v_kin = 0.3 * (st.loc[18, "wheel_left"] + st.loc[18, "wheel_right"]) / 2
    assert v_kin < -1.0 and st.loc[18, "vx_icp"] < 0  # the remaining window moves with the wheels
    assert any("ICP moves against the wheels" in q and "4 window(s)" in q for q in asphalt.meta["quirks"])
    grass = [s for s in shared.sessions if s.terrain_class == "grass"]
    assert all(s.steps.icp_reversed.sum() == 0 for s in grass)

    # the mechanism on a clean step: turn one steady window's ICP translation by half a turn
    plain = read_session(cut(tmp_path / "a", GRASS, steps=6), gyro_sign=1)
    k = int(plain.steps.loc[1:].assign(v=plain.steps.vx_icp.abs()).v.idxmax())  # the fastest step after step 0
    assert abs(plain.steps.loc[k, "vx_icp"]) > 2 * REVERSED_SPEED

    def turn(f):
        f = f.copy()
        row = 3 * k + 1  # the step's first steady window
        for base in ("icp_x", "icp_y"):
            f.loc[row, columns(f, base)] = -f.loc[row, columns(f, base)].to_numpy()
        return f

    turned = read_session(cut(tmp_path / "b", GRASS, steps=6, edit=turn), gyro_sign=1)
    assert turned.steps.icp_reversed.tolist() == [int(i == k) for i in range(6)]
    assert np.sign(turned.steps.loc[k, "vx_icp"]) == np.sign(plain.steps.loc[k, "vx_icp"])
    assert abs(turned.steps.loc[k, "vx_icp"] - plain.steps.loc[k, "vx_icp"]) < 0.2 * abs(plain.steps.loc[k, "vx_icp"])
    np.testing.assert_array_equal(turned.steps.wz_icp, plain.steps.wz_icp)
    assert not any("ICP moves" in q for q in plain.meta["quirks"])


def test_a_flipped_gyro_is_fixed_and_recorded(tmp_path):
    plain = read_session(cut(tmp_path / "a"))

    def flip(f):
        return f.assign(**{c: -f[c] for c in columns(f, "imu_yaw") + columns(f, "icp_vel_yaw")})

    flipped = read_session(cut(tmp_path / "b", edit=flip))
    assert (plain.meta["gyro"]["sign"], flipped.meta["gyro"]["sign"]) == (1, -1)
    assert flipped.meta["gyro"]["by"] == "the ICP yaw rate"
    np.testing.assert_array_equal(flipped.steps.wz_gyro, plain.steps.wz_gyro)
    np.testing.assert_array_equal(flipped.samples.wz, plain.samples.wz)
    assert any("opposite sign" in q and "negated" in q for q in flipped.meta["quirks"])
    assert not any("opposite sign" in q for q in plain.meta["quirks"])
    # a declared sign the data contradict is refused, naming the column
    with pytest.raises(InputError, match=r"imu_yaw.*declared by.*the data say -1"):
        read_session(cut(tmp_path / "c", edit=flip), gyro_sign=1, declared_by="sessions.x")


def test_a_gyro_sign_the_data_cannot_tell_must_be_declared(tmp_path):
    folder = cut(tmp_path, GRAVEL, steps=2)  # a zero step and one more: too few turns
    with pytest.raises(InputError, match=r"imu_yaw_\*.*cannot be fixed from the data.*declare gyro_sign"):
        read_session(folder)
    session = read_session(folder, gyro_sign=-1, declared_by="real_data.datasets.drive.sessions.x")
    assert session.meta["gyro"]["sign"] == -1 and "declared by" in session.meta["gyro"]["by"]


def test_duplicates_are_found_by_content_and_the_recording_run_is_kept(tmp_path):
    cut(tmp_path, name="warthog_wheels_asphalt_b", metadata={"only_execute_trajectories": False})
    # an execute-only run carrying a copy, saved with another pickle protocol (other bytes, same arrays)
    copy = cut(tmp_path, name="warthog_wheels_asphalt_a", metadata={"only_execute_trajectories": True})
    frame = pd.read_pickle(copy / PICKLE)
    with open(copy / PICKLE, "wb") as f:
        pickle.dump(frame, f, protocol=2)
    cut(tmp_path, GRAVEL, steps=12)
    dataset = read_drive(tmp_path)
    assert [s.name for s in dataset.sessions] == ["warthog_wheels_asphalt_b", GRAVEL]
    (dup,) = dataset.duplicates
    assert (dup["session"], dup["same_as"], dup["labels_agree"]) == (
        "warthog_wheels_asphalt_a",
        "warthog_wheels_asphalt_b",
        True,
    )
    kept = dataset.sessions[0].meta["source"]
    assert kept["git_blob_sha1"] != read_session(copy).meta["source"]["git_blob_sha1"]
    # a copy under a folder labelled with another terrain: still one session, the disagreement reported
    cut(
        tmp_path,
        name="warthog_wheels_gravel_c",
        metadata={"only_execute_trajectories": True, "metadata": {"robot": "warthog", "terrain": "gravel"}},
    )
    dataset = read_drive(tmp_path)
    assert len(dataset.sessions) == 2
    other = next(d for d in dataset.duplicates if d["session"] == "warthog_wheels_gravel_c")
    assert (other["same_as"], other["labels_agree"], other["terrain"]) == ("warthog_wheels_asphalt_b", False, "gravel")


def test_a_drive_checkout_reads_as_its_calib_data(shared):
    assert [s.content_hash for s in read_drive(DRIVE).sessions] == [s.content_hash for s in shared.sessions]


def test_the_terrain_comes_from_metadata_and_a_disagreeing_folder_name_is_reported(tmp_path):
    folder = cut(tmp_path, name="warthog_wheels_grass_2024_9_20_9h9s5")  # asphalt metadata
    session = read_session(folder)
    assert session.terrain_class == "asphalt" and session.meta["folder_names_terrain"] is False
    assert any("does not name the metadata terrain 'asphalt'" in q for q in session.meta["quirks"])
    # the config's word replaces metadata's, and says so
    classes = {"asphalt": {}, "grass": {}}
    declared = {"kind": "drive", "sessions": {folder.name: {"terrain_class": "grass"}}}
    dataset = D.open_drive(tmp_path, declared=declared, classes=classes)
    (s,) = dataset.sessions
    assert s.terrain_class == "grass" and "real_data.datasets.drive.sessions" in s.meta["terrain_source"]
    assert any("replaces metadata's 'asphalt'" in q for q in s.meta["quirks"])
    # a terrain with no ground model is refused, naming the session and the fix
    with pytest.raises(DatasetProblems, match=r"terrain class 'grass'.*no ground model.*real_data.classes"):
        D.open_drive(tmp_path, declared=declared, classes={"asphalt": {}})
    with pytest.raises(InputError, match=r"sessions \['nope'\].*no such session folder"):
        D.open_drive(tmp_path, declared={"sessions": {"nope": {"terrain_class": "grass"}}})


@pytest.mark.parametrize(
    ("edit", "words"),
    [
        (lambda f: f.drop(columns=["icp_yaw_7"]), r"column 'icp_yaw_7': missing"),
        (lambda f: f.drop(columns=columns(f, "imu_yaw")), r"column 'imu_yaw_0': missing"),
        (lambda f: f.drop(columns=["steady_state_mask"]), r"column 'steady_state_mask': missing"),
        (
            lambda f: f.assign(imu_acceleration_x_3=np.where(np.arange(len(f)) == 5, np.nan, f.imu_acceleration_x_3)),
            r"column 'imu_acceleration_x_3'.*not finite at row 5",
        ),
        (lambda f: f.iloc[:-1], r"transitory_state_mask.*step at row 33 differs"),
        (
            lambda f: f.assign(**{c: -f[c] for c in columns(f, "imu_acceleration_z")}),
            r"columns imu_acceleration_\*.*not gravity along \+z",
        ),
        (lambda f: f.iloc[1:], r"transitory_state_mask.*row 0 does not start a step"),
    ],
)
def test_a_broken_dataset_names_the_file_and_the_column(tmp_path, edit, words):
    folder = cut(tmp_path, edit=edit)
    with pytest.raises(InputError, match=words) as info:
        read_session(folder)
    assert str(folder / PICKLE) in str(info.value) and "fix:" in str(info.value)


def test_a_file_that_is_not_a_pickle_is_refused_unread(tmp_path):
    folder = cut(tmp_path)
    (folder / PICKLE).write_text("time,left,right\n0,1,2\n")
    with pytest.raises(InputError, match=r"slip_dataset_all.pkl: is not a pickle file"):
        read_session(folder)
    with open(folder / PICKLE, "wb") as f:
        pickle.dump({"not": "a frame"}, f)
    with pytest.raises(InputError, match=r"holds a dict, not a pandas DataFrame"):
        read_session(folder)
    (folder / PICKLE).write_bytes(b"\x80\x04\x95garbage")
    with pytest.raises(InputError, match=r"cannot be unpickled"):
        read_session(folder)


def test_folders_that_are_not_sessions(tmp_path):
    good = cut(tmp_path)
    bad = cut(tmp_path, name="warthog_wheels_gravel_x")
    (bad / "metadata.yaml").unlink()
    with pytest.raises(DatasetProblems, match=r"warthog_wheels_gravel_x/metadata.yaml: missing.*fix: restore"):
        read_drive(tmp_path)
    (good / PICKLE).unlink()
    with pytest.raises(DatasetProblems) as info:
        read_drive(tmp_path)
    assert len(info.value.problems) == 2
    with pytest.raises(InputError, match=r"holds no DRIVE session"):
        read_drive(tmp_path / "warthog_wheels_asphalt" / "config_file_used")
    with pytest.raises(InputError, match=r"DRIVE folder not found"):
        read_drive(tmp_path / "nowhere")


def test_reading_writes_nothing(tmp_path):
    cut(tmp_path)
    before = {p: p.stat().st_mtime_ns for p in tmp_path.rglob("*")}
    read_drive(tmp_path)
    assert {p: p.stat().st_mtime_ns for p in tmp_path.rglob("*")} == before


def test_a_session_folder_alone_and_its_samples(tmp_path):
    session = read_session(cut(tmp_path))
    (only,) = read_drive(tmp_path / ASPHALT).sessions
    assert only.content_hash == session.content_hash
    s, st = session.samples, session.steps
    assert len(s) == 12 * 120 and list(st.step) == list(range(12))
    assert (s.groupby("step").t_step.agg(["min", "max"]).to_numpy() == [0.0, 5.95]).all()
    assert s[s.steady].t_step.min() == 2.0 and s.time.is_monotonic_increasing
    # the steady means are the samples' means over 2-6 s; the command is the one held there
    steady = s[s.steady].groupby("step")
    np.testing.assert_allclose(st.wz_gyro, steady.wz.mean())
    np.testing.assert_allclose(st.wheel_left, steady.wheel_left.mean())
    assert (st.cmd_left == steady.cmd_left.agg(lambda x: x.mode()[0])).all()
    # the lidar's heading change over the steady part and the gyro's agree (two independent sensors)
    turning = st.wz_icp.abs() > 0.3
    assert turning.sum() >= 4
    ratio = st.heading_icp[turning] / st.heading_gyro[turning]
    assert abs(ratio.median() - 1) < 0.05 and (abs(ratio - 1) < 0.25).all()  # per step, the ICP's is noisier
    np.testing.assert_allclose(st.heading_gyro, steady.wz.sum() * 0.05)
    # the step's replay input is its measured wheel speeds at the rim
    cmd = session.wheel_commands(3)
    np.testing.assert_allclose(cmd.v_left, 0.3 * s[s.step == 3].wheel_left)
    with pytest.raises(InputError, match="has no step 12"):
        session.wheel_commands(12)


def test_replay_cases_start_where_the_previous_step_ended(tmp_path):
    session = read_session(cut(tmp_path))
    cases = D.replay_cases([session])
    assert list(cases.columns) == D.CASE_COLUMNS and cases.case.is_unique and len(cases) == 12
    assert (cases.steady_start == 2.0).all() and (cases.steady_end == 6.0).all()
    s = session.samples
    for k in (1, 5, 11):
        end = s[(s.step == k - 1) & (s.t_step >= 5.5)]
        row = cases.loc[cases.step == k].iloc[0]
        assert row.start_from == "previous step's end"
        assert row.start_wheel_left == pytest.approx(end.wheel_left.mean())
        assert row.start_wz == pytest.approx(end.wz.mean())
        # the start speed is the previous step's last steady ICP speed, near its kinematic speed
        prev = session.steps.iloc[k - 1]
        v_kin = 0.3 * (prev.wheel_left + prev.wheel_right) / 2
        assert row.start_vx == pytest.approx(v_kin, abs=0.25 + 0.2 * abs(v_kin))
    assert cases.iloc[0].start_from.startswith("own first window")


def test_the_config_declares_drive_datasets():
    from simpick.config import problems

    config = study_config()
    assert config["real_data"]["datasets"]["drive"]["kind"] == "drive"
    assert problems(config) == []
    config["real_data"]["datasets"]["borealtc"]["sessions"] = {"x": {"gyro_sign": 1}}
    config["real_data"]["datasets"]["drive"]["sessions"] = {"y": {"terrain_class": "dune"}}
    assert any("borealtc: sessions are overrides of DRIVE sessions" in p for p in problems(config))
    del config["real_data"]["datasets"]["borealtc"]["sessions"]
    assert any(
        "drive.sessions: terrain classes ['dune'] are not under real_data.classes" in p for p in problems(config)
    )


def test_the_tables_of_a_dataset(tmp_path):
    cut(tmp_path / "data", name="warthog_wheels_asphalt_b")
    cut(tmp_path / "data", name="warthog_wheels_asphalt_a", metadata={"only_execute_trajectories": True})
    dataset = read_drive(tmp_path / "data")
    outputs = {k: str(tmp_path / "out" / f"{k}.csv") for k in ("sessions", "steps", "turning", "bins", "cases")}
    D.write_tables(dataset, outputs)
    sessions = pd.read_csv(outputs["sessions"])
    assert list(sessions.kept) == [True, False] and sessions.same_as.iloc[1] == "warthog_wheels_asphalt_b"
    assert sessions.gyro_fixed_by.iloc[0] == "the ICP yaw rate" and sessions.steps.iloc[0] == 12
    assert len(pd.read_csv(outputs["steps"])) == len(pd.read_csv(outputs["cases"])) == 12
    assert list(pd.read_csv(outputs["turning"]).session) == ["warthog_wheels_asphalt_b", "all"]
    bins = pd.read_csv(outputs["bins"])
    turning = D.step_table(dataset).turning.sum()
    assert (bins.groupby("variable").steps.sum() == turning).all() and set(bins.variable) == set(D.BINS)
    with pytest.raises(ValueError, match="unknown DRIVE table"):
        D.write_tables(dataset, {"gains": str(tmp_path / "x.csv")})


def _git_status() -> str:
    import subprocess

    run = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain"], capture_output=True, text=True, check=False)
    if run.returncode != 0:
        pytest.fail(f"this test checks the checkout with git, which failed here: {run.stderr.strip()}")
    return run.stdout


@pytest.mark.workflow
def test_the_workflow_writes_the_drive_tables_of_a_named_folder(tmp_path):
    from conftest import snakemake, tiny_config, write_config

    data = tmp_path / "calib_data"
    cut(data, steps=12)
    cut(data, GRAVEL, steps=12)
    config = tiny_config(tmp_path)  # the Husky: DRIVE's Warthog sessions are refused before any job
    config["drive_dir"] = str(data)
    write_config(tmp_path, config)
    before = _git_status()
    targets = [f"results/drive/drive/{t}.csv" for t in ("sessions", "steps", "turning", "bins", "cases")]
    run = snakemake(tmp_path, "-n", *targets)
    assert run.returncode != 0 and "drive_tables" not in run.stdout
    lines = [line for line in run.stderr.splitlines() if line.startswith("simpick:")]
    assert len(lines) == 2 and all("field 'metadata.robot': is 'warthog'" in line for line in lines), run.stderr
    config["robot"] = {**config["robot"], "urdf": str(ROOT / "resources" / "robot" / "warthog.urdf"), "track": 1.08}
    config["accuracy"] = {**config.get("accuracy", {}), "reference": "paper"}  # BorealTC is a Husky's
    write_config(tmp_path, config)
    run = snakemake(tmp_path, "--cores", "1", *targets)
    assert run.returncode == 0, run.stderr[-3000:]
    turning = pd.read_csv(tmp_path / targets[2])
    assert set(turning.session) == {ASPHALT, GRAVEL, "all"}
    assert len(pd.read_csv(tmp_path / targets[4])) == 24
    # a broken file: the job fails with one line naming it; a folder without metadata: refused before any job
    (data / GRAVEL / PICKLE).write_text("not a pickle\n")
    run = snakemake(tmp_path, "--cores", "1", "--forceall", *targets)
    assert run.returncode != 0 and f"simpick: {data / GRAVEL / PICKLE}: is not a pickle file" in run.stderr
    (data / GRAVEL / "metadata.yaml").unlink()
    run = snakemake(tmp_path, "--cores", "1", *targets)
    assert run.returncode != 0 and f"simpick: {data / GRAVEL / 'metadata.yaml'}: missing" in run.stderr
    assert "drive_tables" not in run.stdout
    assert _git_status() == before


def test_sessions_of_another_robot_on_tracks_or_an_unmodelled_terrain_are_refused_at_planning(tmp_path):
    """simpick.sources.drive reads each session's metadata.yaml only (no pickle): one problem per session, each
    naming the file, the field and the fix."""
    from simpick.config.real import DeclaredDataset
    from simpick.sources.drive import problems as session_problems

    classes = {"asphalt": {}, "gravel": {}, "grass": {}}

    def block(**changed):  # the gravel session's metadata block with some fields changed
        md = yaml.safe_load((CALIB / GRAVEL / "metadata.yaml").read_text())["metadata"]
        return {"metadata": {**md, **changed}}

    folders = [
        cut(tmp_path, ASPHALT, steps=2),
        cut(tmp_path, GRAVEL, steps=2, name="husky_gravel", metadata=block(robot="husky")),
        cut(tmp_path, GRAVEL, steps=2, name="marmotte", metadata=block(traction="tracks")),
        cut(tmp_path, GRAVEL, steps=2, name="on_snow", metadata=block(terrain="snow")),
    ]
    (tmp_path / "husky_gravel" / PICKLE).write_text("never read: planning opens no pickle\n")
    problems = [str(p) for p in session_problems(folders, DeclaredDataset(kind="drive"), classes, "warthog")]
    assert len(problems) == 3, problems
    assert "husky_gravel/metadata.yaml: field 'metadata.robot': is 'husky'" in problems[0]
    assert "real_data.datasets.drive.robot: husky" in problems[0]
    assert "marmotte/metadata.yaml: field 'metadata.traction': is 'tracks'" in problems[1]
    assert "on_snow/metadata.yaml: field 'metadata.terrain'" in problems[2] and "'snow'" in problems[2]
    # declared: the session's terrain and the name DRIVE gives the study's robot
    sessions = {"on_snow": {"terrain_class": "gravel"}}
    declared = DeclaredDataset(kind="drive", robot="husky", sessions=sessions)
    problems = [str(p) for p in session_problems(folders, declared, classes, "warthog")]
    refused = [str(f / "metadata.yaml") for f in (folders[0], folders[2], folders[3])]  # now the other robot's
    assert [p.split(":")[0] for p in problems] == refused
    only_sessions = DeclaredDataset(kind="drive", sessions=sessions)
    assert session_problems([folders[3]], only_sessions, classes, "warthog") == []
    # no declaration: the URDF's robot name, each session's own terrain
    assert len(session_problems(folders, None, classes, "warthog")) == 3


def test_the_config_names_a_drive_folder(tmp_path):
    from simpick.config import problems

    config = study_config()
    config["drive_dir"] = str(tmp_path)
    assert problems(config) == []
    config["drive_dir"] = str(tmp_path / "nowhere")
    assert any("drive_dir" in p and "is not a folder" in p for p in problems(config))
    config.update(drive_dir=str(tmp_path), drive_dataset="borealtc")
    assert any("drive_dataset 'borealtc'" in p and "kind: drive" in p for p in problems(config))
    config.update(drive_dataset="drive", drive_dir=None, borealtc_dir=str(tmp_path), real_dataset="drive")
    assert any("declared kind: drive" in p and "drive_dir instead" in p for p in problems(config))


def test_a_folder_that_is_no_session_is_named_at_planning_with_the_reason(tmp_path, capsys):
    """The source lists the sessions under a folder and names every other sub-folder, with why it is left
    out, instead of skipping it in silence."""
    from simpick.sources.drive import folders

    root = tmp_path / "calib_data"
    cut(root, ASPHALT, steps=2)
    (root / "notes").mkdir()
    (root / "notes" / "readme.txt").write_text("not a session\n")
    (root / ".cache").mkdir()
    assert [p.name for p in folders(root)] == [ASPHALT]
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2, err
    assert err[0].startswith(f"simpick: {root / '.cache'}: left out of the DRIVE dataset: a hidden folder")
    assert err[1].startswith(f"simpick: {root / 'notes'}: left out of the DRIVE dataset: holds neither metadata.yaml")
    # one session folder named itself: nothing else to name
    assert [p.name for p in folders(root / ASPHALT)] == [ASPHALT]
    assert capsys.readouterr().err == ""
