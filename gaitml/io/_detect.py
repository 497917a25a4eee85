"""Format detection and the two entry points: :func:`read_recording`, :func:`read_dataset`."""

from __future__ import annotations

import os
from pathlib import Path

from gaitml.errors import InputError
from gaitml.io._common import head_bytes, head_lines, require_file
from gaitml.io.columns_csv import read_columns_csv
from gaitml.io.gaitmap import GAITMAP_TABLES, is_gaitmap_header, read_gaitmap_csv
from gaitml.io.gaitml_csv import list_gaitml_files, looks_like_gaitml, read_gaitml_csv, read_gaitml_folder, sniff_dialect
from gaitml.io.getsensordata import is_getsensordata, read_getsensordata
from gaitml.io.ifsm import is_xlsx, read_ifsm_xlsx
from gaitml.io.oxford import is_oxford_folder, list_oxford_folders, read_oxford_folder
from gaitml.io.phyphox import is_phyphox, read_phyphox
from gaitml.io.sensor_logger import is_sensor_logger, read_sensor_logger
from gaitml.io.tyrex import is_tyrex_folder, list_tyrex_folders, read_tyrex
from gaitml.recording import Recording

__all__ = ["FORMATS", "detect_format", "read_recording", "read_segments", "read_dataset", "list_dataset"]

#: Names accepted by ``--format``.
FORMATS = ("gaitml-csv", "ifsm-xlsx", "oxford", "gaitmap", "phyphox", "sensor-logger", "columns-csv", "tyrex", "getsensordata")

_EXPECTED = (
    "expected a gaitml-csv (t, acc_x, acc_y, acc_z[, gyr_*][, label]), an IFSM xlsx, "
    "an Oxford recording folder (accelerometer.csv + stepcounter.csv), a gaitmap IMU CSV, "
    "a phyphox or Sensor Logger export (folder, zip or CSV), a tyrex recording folder (accelerometer.txt + gyroscope log), "
    "a GetSensorData log, or any CSV with --columns t=...,acc_x=...,acc_y=...,acc_z=..."
)


def detect_format(path: str | os.PathLike) -> str:
    """Name the format of a recording file or folder from its content.

    Returns one of :data:`FORMATS`, ``'gaitml-folder'``/``'oxford-set'``/
    ``'tyrex-set'``/``'mixed-folder'`` for data set folders, or ``'gaitmap-table'`` for gaitmap
    annotation tables.
    """
    p = require_file(path)
    if p.is_dir():
        if is_oxford_folder(p):
            return "oxford"
        if is_tyrex_folder(p):
            return "tyrex"
        if is_sensor_logger(p):
            return "sensor-logger"
        if is_phyphox(p):
            return "phyphox"
        if (p / "manifest.csv").exists() or list_gaitml_files_safe(p):
            return "gaitml-folder"
        if list_oxford_folders(p):
            return "oxford-set"
        if list_tyrex_folders(p):
            return "tyrex-set"
        if any(True for _ in _recording_entries(p)):
            return "mixed-folder"
        raise InputError(f"{p} holds no recordings gaitml can read; {_EXPECTED}.")
    if p.name.startswith("accelerometer.csv") and (p.parent / "stepcounter.csv").exists():
        return "oxford"
    if p.name.startswith(("accelerometer.txt", "gyroscope")) and is_tyrex_folder(p.parent):
        return "tyrex"
    head = head_bytes(p, 8)
    if head[:2] == b"PK":
        if is_xlsx(p):
            return "ifsm-xlsx"
        if is_sensor_logger(p):
            return "sensor-logger"
        if is_phyphox(p):
            return "phyphox"
        if p.suffix.lower() in (".xlsx", ".xlsm", ".xls"):  # named as a workbook: say it is not one
            raise InputError(f"{p.name} is a zip archive but not an Excel workbook ({_zip_summary(p)}); {_EXPECTED}.")
        raise InputError(f"{p.name} is a zip archive gaitml does not recognise ({_zip_summary(p)}); {_EXPECTED}.")
    if is_getsensordata(p):
        return "getsensordata"
    lines = head_lines(p, 2)
    if not lines:
        raise InputError(f"the file is empty: {p}; record or export the data again.")
    if sniff_dialect(lines) is not None:
        return "gaitml-csv"
    if is_gaitmap_header(lines):
        return "gaitmap"
    if is_sensor_logger(p):
        return "sensor-logger"
    if is_phyphox(p):
        return "phyphox"
    if p.name.split(".")[0] in GAITMAP_TABLES:
        return "gaitmap-table"
    if looks_like_gaitml(lines):
        return "gaitml-csv"  # its reader names the missing columns
    if lines[0].startswith("# qtm_timestamp"):
        raise InputError(
            f"{p.name} is a tyrex motion-capture file, not an IMU recording; pass the phone's folder "
            f"(android/{p.name.split('.')[0]} or ios/...), and read the capture with gaitml.io.read_tyrex_truth."
        )
    if lines[0].strip().lower().startswith("sep=") and len(lines) > 1:  # AndroSensor / Excel separator hint
        raise InputError(
            f"{p.name[:80]} starts with a separator hint {lines[0].strip()!r} (AndroSensor or a spreadsheet export; header "
            f"{lines[1].strip()[:80]!r}); read it with --columns t=...,acc_x=...,acc_y=...,acc_z=... naming its columns."
        )
    cols = lines[0].strip()[:80]
    raise InputError(f"unknown format for {p.name[:80]} (first line: {cols!r}); {_EXPECTED}; or pass --format.")


def _zip_summary(p: Path) -> str:
    """What a zip holds, for the refusal: its first member names, or why it cannot be opened."""
    import zipfile

    try:
        with zipfile.ZipFile(p) as z:
            names = [n for n in z.namelist() if not n.startswith("__MACOSX/") and not n.endswith("/")]
    except (zipfile.BadZipFile, OSError) as exc:
        return f"cannot be opened: {exc}"
    if not names:
        return "empty"
    shown = ", ".join(names[:6]) + (f", ... ({len(names)} files)" if len(names) > 6 else "")
    csvs = [n for n in names if n.lower().endswith(".csv")]
    why = "no CSV tables" if not csvs else "no phyphox or Sensor Logger accelerometer table among its CSVs"
    return f"{why}; it holds {shown}"


def list_gaitml_files_safe(p: Path) -> list[Path]:
    out = []
    for f in list_gaitml_files(p):
        try:
            lines = head_lines(f, 1)
        except InputError:
            continue
        if sniff_dialect(lines) is not None:
            out.append(f)
    return out


def read_recording(
    path: str | os.PathLike,
    *,
    format: str | None = None,
    sensor: str = "left",
    sampling_rate_hz: float | None = None,
    acc_unit: str = "m/s^2",
    gyr_unit: str = "rad/s",
    columns: str | dict | None = None,
    time_unit: str = "s",
) -> Recording:
    """Read one recording, detecting its format unless ``format`` is given.

    Parameters
    ----------
    path : file or folder
    format : one of :data:`FORMATS`, optional
    sensor : 'left' | 'right'
        Which foot of a two-sensor gaitmap file.
    sampling_rate_hz : float, optional
        Target uniform rate (resampling irregular data) or, for files without a
        time base, the rate they were recorded at. Oxford default: 100 Hz.
    acc_unit, gyr_unit : units of a gaitml-csv's (or columns-csv's) columns, converted to SI.
    columns : str or dict, optional
        Column map of any CSV (``'t=time,acc_x=ax,...'``, see
        :mod:`gaitml.io.columns_csv`); implies ``format='columns-csv'``.
    time_unit : {'s', 'ms', 'us', 'ns'}
        Unit of the time column of a columns-csv.
    """
    if format is not None and format not in FORMATS:
        raise InputError(f"unknown --format {format!r}; choose one of {', '.join(FORMATS)}.")
    p = require_file(path)
    if columns is not None and format not in (None, "columns-csv"):
        raise InputError(f"--columns reads any CSV as format columns-csv, not {format!r}; drop --format or --columns.")
    fmt = "columns-csv" if columns is not None else (format or detect_format(p))
    if fmt == "columns-csv":
        if columns is None:
            raise InputError("--format columns-csv needs --columns t=...,acc_x=...,acc_y=...,acc_z=... naming the CSV's columns.")
        return read_columns_csv(p, columns, time_unit=time_unit, acc_unit=acc_unit, gyr_unit=gyr_unit, sampling_rate_hz=sampling_rate_hz)
    given = {"acc_unit": None if acc_unit == "m/s^2" else acc_unit, "gyr_unit": None if gyr_unit == "rad/s" else gyr_unit}
    _refuse_unit_flags(fmt, given)
    if fmt == "phyphox":
        return read_phyphox(p, sampling_rate_hz=sampling_rate_hz, **given)
    if fmt == "sensor-logger":
        return read_sensor_logger(p, sampling_rate_hz=sampling_rate_hz, **given)
    if fmt == "getsensordata":
        return read_getsensordata(p, sampling_rate_hz=sampling_rate_hz)
    if fmt == "gaitml-csv":
        if p.is_dir():
            raise InputError(f"{p} is a folder; pass one .csv recording of it.")
        return read_gaitml_csv(p, sampling_rate_hz=sampling_rate_hz, acc_unit=acc_unit, gyr_unit=gyr_unit)
    if fmt == "ifsm-xlsx":
        return read_ifsm_xlsx(p) if sampling_rate_hz is None else read_ifsm_xlsx(p, sampling_rate_hz=sampling_rate_hz)
    if fmt == "oxford":
        folder = p if p.is_dir() else p.parent
        return read_oxford_folder(folder) if sampling_rate_hz is None else read_oxford_folder(folder, sampling_rate_hz=sampling_rate_hz)
    if fmt == "gaitmap":
        return read_gaitmap_csv(p, sensor=sensor, sampling_rate_hz=sampling_rate_hz)
    if fmt == "tyrex":
        return read_tyrex(p if p.is_dir() else p.parent, sampling_rate_hz=sampling_rate_hz)
    if fmt == "gaitmap-table":
        raise InputError(
            f"{p.name} is a gaitmap reference table (annotations or motion capture), not an IMU recording; pass the imu_sample*.csv.gz file beside it."
        )
    n = len(list_dataset(p))
    raise InputError(f"{p} is a data set of {n} recordings; pass one recording file or folder of it.")


def read_segments(
    path: str | os.PathLike,
    *,
    format: str | None = None,
    sensor: str = "left",
    sampling_rate_hz: float | None = None,
    acc_unit: str = "m/s^2",
    gyr_unit: str = "rad/s",
    columns: str | dict | None = None,
    time_unit: str = "s",
) -> list[Recording]:
    """Read one recording as a list of segments, cut at every gap too long to bridge.

    :func:`read_recording` refuses a timestamp gap longer than
    :func:`gaitml.recording.max_bridge_s` (the longer of 1 s and ten sampling
    intervals); this reads each stretch between such gaps as its own recording,
    with ``meta['segment']`` (index, count, first and last original sample, start
    and end in s) and ``meta['id']`` suffixed ``#k`` when there is more than one.
    Formats without timestamps (IFSM xlsx, gaitmap) have no gaps: one segment; the
    phone-app formats and column-mapped CSVs are read whole (``columns`` and
    ``time_unit`` as in :func:`read_recording`), so a long gap in them is refused
    with the reader's message.
    """
    if format is not None and format not in FORMATS:
        raise InputError(f"unknown --format {format!r}; choose one of {', '.join(FORMATS)}.")
    p = require_file(path)
    fmt = "columns-csv" if columns is not None else (format or detect_format(p))
    _refuse_unit_flags(fmt, {"acc_unit": None if acc_unit == "m/s^2" else acc_unit, "gyr_unit": None if gyr_unit == "rad/s" else gyr_unit})
    if fmt == "gaitml-csv" and p.is_file():
        return read_gaitml_csv(p, sampling_rate_hz=sampling_rate_hz, acc_unit=acc_unit, gyr_unit=gyr_unit, segments=True)
    if fmt == "oxford":
        folder = p if p.is_dir() else p.parent
        kw = {} if sampling_rate_hz is None else {"sampling_rate_hz": sampling_rate_hz}
        return read_oxford_folder(folder, segments=True, **kw)
    if fmt == "tyrex":
        return read_tyrex(p if p.is_dir() else p.parent, sampling_rate_hz=sampling_rate_hz, segments=True)
    return [
        read_recording(
            p,
            format=None if columns is not None else fmt,
            sensor=sensor,
            sampling_rate_hz=sampling_rate_hz,
            acc_unit=acc_unit,
            gyr_unit=gyr_unit,
            columns=columns,
            time_unit=time_unit,
        )
    ]


def _recording_entries(folder: Path):
    for f in sorted(folder.iterdir()):
        if f.name.startswith(".") or f.name.lower().startswith(("readme", "license")):
            continue
        if f.is_dir():
            if is_oxford_folder(f):
                yield f, "oxford"
            elif is_tyrex_folder(f):
                yield f, "tyrex"
            elif is_sensor_logger(f):
                yield f, "sensor-logger"
            elif is_phyphox(f):
                yield f, "phyphox"
            continue
        try:
            fmt = detect_format(f)
        except InputError:
            continue
        if fmt in FORMATS:
            yield f, fmt


def list_dataset(path: str | os.PathLike) -> list[tuple[Path, str]]:
    """The recordings of a file or folder as ``(path, format)`` pairs, without reading them."""
    p = require_file(path)
    fmt = detect_format(p)
    if fmt in FORMATS:
        return [(p, fmt)]
    if fmt == "gaitml-folder":
        return [(p, fmt)]
    if fmt == "oxford-set":
        return [(d, "oxford") for d in list_oxford_folders(p)]
    if fmt == "tyrex-set":
        return [(d, "tyrex") for d in list_tyrex_folders(p)]
    if fmt == "mixed-folder":
        return list(_recording_entries(p))
    raise InputError(f"{p} is not a recording or data set; {_EXPECTED}.")


def read_dataset(path: str | os.PathLike, **kwargs) -> list[Recording]:
    """Read every recording of a file or data set folder.

    gaitml-csv folders (with or without ``manifest.csv``), Oxford data set roots
    (``optimisation/``, its ``data/`` or any folder of recording folders), tyrex
    roots (``tyrex-attitude/`` with ``android/`` and ``ios/``, or either of them), and
    folders mixing supported files are all accepted. A tyrex recording with a gap
    too long to bridge (a sensor that stopped logging) is read as its stretches
    between the gaps (``meta['segment']``, ``id`` suffixed ``#k``), never bridged.
    """
    p = require_file(path)
    out: list[Recording] = []
    for f, fmt in list_dataset(p):
        if fmt == "gaitml-folder":
            keep = {k: v for k, v in kwargs.items() if k in ("sampling_rate_hz", "acc_unit", "gyr_unit")}
            out.extend(read_gaitml_folder(f, **keep))
        elif fmt == "tyrex":
            out.extend(read_tyrex(f, sampling_rate_hz=kwargs.get("sampling_rate_hz"), segments=True))
        else:
            out.append(read_recording(f, format=fmt, **kwargs))
    return out


#: Formats whose units are documented by the format itself: --acc-unit / --gyr-unit do not apply.
FIXED_UNIT_FORMATS = ("ifsm-xlsx", "oxford", "gaitmap", "getsensordata", "tyrex", "tyrex-set")


def _refuse_unit_flags(fmt: str, given: dict) -> None:
    """InputError when a unit flag was given for a format with documented units (it would change nothing)."""
    if any(given.values()) and fmt in FIXED_UNIT_FORMATS:
        flag = "--acc-unit" if given["acc_unit"] else "--gyr-unit"
        raise InputError(
            f"{flag} applies to gaitml-csv, columns-csv, phyphox and Sensor Logger files; a {fmt} recording has its documented units: drop {flag}."
        )
