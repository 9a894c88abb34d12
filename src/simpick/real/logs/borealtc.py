"""The BorealTC layout (LaRocque et al., IROS 2024; CC0 1.0), which any dataset folder may use.

Layout (:mod:`simpick.real.datasets`): one folder per terrain class (BorealTC's own: ASPHALT,
FLOORING, ICE, SANDY_LOAM, SNOW), each with ``imu_<run>.csv`` (time s, wx, wy, wz rad/s, ax,
ay, az m/s^2 with gravity, z up) and ``pro_<run>.csv`` (time s, curL, curR A, velL, velR
wheel speeds m/s), paired by run id, whatever the numbering. Both files of a run share one
clock; the canonical log keeps it (zero at the first IMU sample). velL/velR become
v_left/v_right and curL/curR current_left/current_right.

Rates are read from the data (median interval) and must be steady (no gaps, jitter or
duplicated times; :func:`simpick.real.logs.validate.check_rate`). BorealTC itself records the
IMU at 100 Hz and the wheels at about 6.5 Hz (:data:`IMU_RATE_HZ`, :data:`PRO_RATE_HZ`);
another dataset may run at other rates. A caller that knows a dataset's rates declares them
(``imu_rate_hz``, ``command_rate_hz``) and a file that contradicts them is refused.

Frame: the reader checks, not assumes: gravity along +z (else an error) and the sign of
the gyro yaw rate against (velR - velL) (result in ``meta["checks"]["yaw"]``; a run that
contradicts is reported there, never flipped).
"""

from __future__ import annotations

import re
from pathlib import Path

from simpick.real.datasets import find_runs
from simpick.real.logs import validate as V
from simpick.real.logs.assemble import finish, source_columns
from simpick.real.logs.canonical import DEFAULT_TRACK, RealLog
from simpick.real.logs.csvfile import check_file, file_info, load_csv

DATASET = "BorealTC"
TERRAIN_CLASSES = ("ASPHALT", "FLOORING", "ICE", "SANDY_LOAM", "SNOW")
IMU_RATE_HZ = 100.0
PRO_RATE_HZ = 6.5
IMU_MAP = {"time": "time", "ax": "ax", "ay": "ay", "az": "az", "wx": "wx", "wy": "wy", "wz": "wz"}
PRO_MAP = {"time": "time", "v_left": "velL", "v_right": "velR", "current_left": "curL", "current_right": "curR"}
_RUN = re.compile(r"^(imu|pro)_([A-Za-z0-9_-]+)\.csv$")


def discover(folder: str | Path) -> list[tuple[str, str, Path, Path]]:
    """(class folder name, run_id, imu_path, pro_path) of every run, by class and natural run order.

    Every problem of the folder (see :func:`simpick.real.datasets.scan`: not a dataset, an empty
    class folder, an imu file without its pro partner ...) is an InputError naming it.
    """
    return [(r.folder, r.run, r.imu, r.pro) for r in find_runs(folder)]


def read_run(
    imu_csv: str | Path,
    pro_csv: str | Path,
    terrain_class: str,
    *,
    track: float = DEFAULT_TRACK,
    imu_rate_hz: float | None = None,
    command_rate_hz: float | None = None,
    declared_by: str = "the caller",
    dataset: str = DATASET,
) -> RealLog:
    """One run as a validated canonical RealLog; rates declared by ``declared_by`` are checked."""
    imu_path, pro_path = check_file(imu_csv, "IMU file"), check_file(pro_csv, "wheel (pro) file")
    imu = source_columns(load_csv(imu_path), IMU_MAP, str(imu_path), V.csv_row)
    pro = source_columns(load_csv(pro_path), PRO_MAP, str(pro_path), V.csv_row)
    m = _RUN.match(imu_path.name)
    run_id = m.group(2) if m else imu_path.stem
    return finish(
        imu,
        pro,
        imu_where=str(imu_path),
        cmd_where=str(pro_path),
        imu_names=IMU_MAP,
        cmd_names=PRO_MAP,
        imu_row_label=V.csv_row,
        cmd_row_label=V.csv_row,
        declared_hz={"imu": imu_rate_hz, "commands": command_rate_hz},
        declared_by=declared_by,
        steady=True,
        track=track,
        reader="simpick.real.logs.borealtc",
        meta={
            "dataset": dataset,
            "run_id": run_id,
            "terrain_class": terrain_class,
            "name": f"{terrain_class}_{run_id}",
            "source_files": {"imu": file_info(imu_path), "commands": file_info(pro_path)},
            **({"license": "CC0-1.0"} if dataset == DATASET else {}),
            "source_columns": {"imu": IMU_MAP, "commands": PRO_MAP},
        },
    )
