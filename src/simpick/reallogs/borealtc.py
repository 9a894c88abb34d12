"""BorealTC (LaRocque et al., IROS 2024; CC0 1.0): a real Husky A200 on five terrains.

Layout: one folder per terrain class (ASPHALT, FLOORING, ICE, SANDY_LOAM, SNOW), each
with ``imu_XX.csv`` (time, wx, wy, wz rad/s, ax, ay, az m/s^2 with gravity, z up,
100 Hz) and ``pro_XX.csv`` (time, curL, curR A, velL, velR wheel speeds m/s, 6.5 Hz),
paired by XX. Both files of a run start at time 0 on the same clock; the canonical log
keeps that clock (zero at the first IMU sample). velL/velR become v_left/v_right and
curL/curR current_left/current_right.

Frame: the reader checks, not assumes: gravity along +z (else an error) and the sign of
the gyro yaw rate against (velR - velL) (result in ``meta["checks"]["yaw"]``; a run that
contradicts is reported there, never flipped).
"""

from __future__ import annotations

import re
from pathlib import Path

from simpick.errors import InputError
from simpick.reallogs import validate as V
from simpick.reallogs.assemble import finish, source_columns
from simpick.reallogs.canonical import DEFAULT_TRACK, RealLog
from simpick.reallogs.csvfile import check_file, file_info, load_csv

DATASET = "BorealTC"
TERRAIN_CLASSES = ("ASPHALT", "FLOORING", "ICE", "SANDY_LOAM", "SNOW")
IMU_RATE_HZ = 100.0
PRO_RATE_HZ = 6.5
IMU_MAP = {"time": "time", "ax": "ax", "ay": "ay", "az": "az", "wx": "wx", "wy": "wy", "wz": "wz"}
PRO_MAP = {"time": "time", "v_left": "velL", "v_right": "velR",
           "current_left": "curL", "current_right": "curR"}
_RUN = re.compile(r"^(imu|pro)_(\w+)\.csv$")


def discover(folder: str | Path) -> list[tuple[str, str, Path, Path]]:
    """(terrain_class, run_id, imu_path, pro_path) for every run, sorted by class and id.

    Every sub-folder holding imu_*.csv / pro_*.csv files is a terrain class; other files
    (README, LICENSE) are ignored. An imu file without its pro partner (or the reverse)
    is an error naming it.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise InputError(str(folder), "BorealTC folder not found",
                         "download data/borealtc from github.com/norlab-ulaval/BorealTC")
    runs = []
    for sub in sorted(p for p in folder.iterdir() if p.is_dir()):
        found: dict[str, dict[str, Path]] = {}
        for f in sorted(sub.iterdir()):
            m = _RUN.match(f.name)
            if m and f.is_file():
                found.setdefault(m.group(2), {})[m.group(1)] = f
        for run_id, pair in sorted(found.items()):
            for have, need in (("imu", "pro"), ("pro", "imu")):
                if have in pair and need not in pair:
                    raise InputError(str(pair[have]), f"has no partner {need}_{run_id}.csv in {sub}",
                                     "restore the missing file or remove this one")
            runs.append((sub.name, run_id, pair["imu"], pair["pro"]))
    if not runs:
        raise InputError(str(folder), "holds no BorealTC runs (no <CLASS>/imu_XX.csv + pro_XX.csv)")
    return runs


def read_run(imu_csv: str | Path, pro_csv: str | Path, terrain_class: str, *,
             track: float = DEFAULT_TRACK, check_rates: bool = True) -> RealLog:
    """One BorealTC run as a validated canonical RealLog."""
    imu_path, pro_path = check_file(imu_csv, "IMU file"), check_file(pro_csv, "wheel (pro) file")
    imu = source_columns(load_csv(imu_path), IMU_MAP, str(imu_path), V.csv_row)
    pro = source_columns(load_csv(pro_path), PRO_MAP, str(pro_path), V.csv_row)
    m = _RUN.match(imu_path.name)
    run_id = m.group(2) if m else imu_path.stem
    return finish(
        imu, pro, imu_where=str(imu_path), cmd_where=str(pro_path),
        imu_names=IMU_MAP, cmd_names=PRO_MAP, imu_row_label=V.csv_row, cmd_row_label=V.csv_row,
        declared_hz={"imu": IMU_RATE_HZ if check_rates else None,
                     "commands": PRO_RATE_HZ if check_rates else None},
        track=track, reader="simpick.reallogs.borealtc",
        meta={"dataset": DATASET, "run_id": run_id, "terrain_class": terrain_class,
              "name": f"{terrain_class}_{run_id}",
              "source_files": {"imu": file_info(imu_path), "commands": file_info(pro_path)},
              "license": "CC0-1.0",
              "source_columns": {"imu": IMU_MAP, "commands": PRO_MAP}},
    )


def read_all(folder: str | Path, **kwargs) -> dict[str, RealLog]:
    """Every run of ``discover(folder)``, keyed "<CLASS>_<XX>"."""
    return {f"{cls}_{run}": read_run(imu, pro, cls, **kwargs) for cls, run, imu, pro in discover(folder)}
