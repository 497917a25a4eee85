"""Reader for Sensor Logger exports (Kelvin Choi's iOS/Android app, "zipped CSV" export).

The export is a zip archive (or the folder it unpacks to) with one CSV per
sensor, each with the columns ``time`` (ns since the UNIX epoch, one clock for
all sensors), ``seconds_elapsed`` (s since the recording started; absent from
older exports, whose tables are ``time, z, y, x``) and ``z, y, x``
(the app's column order), plus ``Metadata.csv`` (``platform`` iOS or Android,
``device name``, ...). Documented units and frames (awesome-sensor-logger
UNITS.md, CROSSPLATFORM.md):

- ``Accelerometer.csv``: acceleration *without* gravity, m/s^2 (user motion);
- ``TotalAcceleration.csv`` (Android): acceleration *with* gravity, m/s^2;
- ``Gravity.csv``: the gravity vector, m/s^2;
- ``AccelerometerUncalibrated.csv``: raw accelerometer, in g on iOS (unless the
  app's "Standardise Units & Frames" is on), m/s^2 on Android;
- ``Gyroscope.csv``: rad/s on both platforms;
- iOS and Android acceleration and gravity differ by a sign on all three axes
  (flat on a table, gravity is +z on Android, -z on iOS); with "Standardise
  Units & Frames" on, iOS follows Android.

gaitml needs the accelerometer *with* gravity as specific force (+g up when the
phone lies flat, the Android convention). The reader takes, in this order:

1. ``TotalAcceleration.csv`` as it is;
2. ``Accelerometer.csv`` + ``Gravity.csv`` (gravity linearly interpolated onto
   the accelerometer times, overlap only); negated for iOS unless standardised;
3. ``AccelerometerUncalibrated.csv``, converted from g on iOS (unless
   standardised) and negated for iOS.

Without ``Metadata.csv`` the platform is unknown: the Android convention is
assumed and, for the uncalibrated table, the unit is taken from the median
magnitude (about 1 -> g); ``meta['frame']`` says so. The gyroscope
(``Gyroscope.csv``) is merged onto the accelerometer's times by
:func:`gaitml.io._merge.merge_clocks` and reported in ``meta['clock_merge']``.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.io._common import require_file
from gaitml.io._export import ExportContainer, open_export, read_table
from gaitml.io._hold import dehold, note_hold
from gaitml.io._merge import check_times, merge_clocks, override_units
from gaitml.recording import Recording

__all__ = ["read_sensor_logger", "is_sensor_logger", "is_sensor_logger_header", "SENSOR_LOGGER_TABLES"]

#: The motion tables gaitml reads (lower-case file names).
SENSOR_LOGGER_TABLES = (
    "totalacceleration.csv",
    "accelerometer.csv",
    "gravity.csv",
    "accelerometeruncalibrated.csv",
    "gyroscope.csv",
)
_XYZ = ("x", "y", "z")


def is_sensor_logger_header(line: str) -> bool:
    """Whether a CSV header line is a Sensor Logger motion table (time, seconds_elapsed, z, y, x)."""
    cols = [c.strip().strip('"') for c in line.split(",")]
    if "seconds_elapsed" in cols and all(a in cols for a in _XYZ):
        return True
    # older exports (before seconds_elapsed was added): exactly time, z, y, x
    return sorted(cols) == ["time", "x", "y", "z"]


def is_sensor_logger(path: str | os.PathLike) -> bool:
    """Whether ``path`` (export folder, zip, or one of its motion tables) is a Sensor Logger export; never raises."""
    try:
        p = Path(path)
        if p.is_file() and p.suffix.lower() == ".csv":
            with open(p, "rb") as fh:
                line = fh.read(512).decode("utf-8-sig", errors="replace").splitlines()
            return bool(line) and p.name.lower() in SENSOR_LOGGER_TABLES and is_sensor_logger_header(line[0])
        if p.is_file() and p.suffix.lower() != ".zip":
            return False
        with open_export(p) as box:
            top = box.top_level()
            for low in SENSOR_LOGGER_TABLES:
                if low in top:
                    lines = box.head(top[low]).splitlines()
                    if lines and is_sensor_logger_header(lines[0]):
                        return True
    except (InputError, OSError, ValueError):
        return False
    return False


def _metadata(box: ExportContainer) -> dict:
    top = box.top_level()
    if "metadata.csv" not in top:
        return {}
    try:
        df = read_table(box, top["metadata.csv"])
    except InputError:
        return {}
    row = {str(k).strip().lower(): v for k, v in df.iloc[0].items()}
    out = {}
    if isinstance(row.get("platform"), str):
        out["platform"] = row["platform"].strip()
    if "device name" in row and isinstance(row["device name"], str):
        out["device"] = row["device name"].strip()
    for k, v in row.items():
        if "standardis" in k or "standardiz" in k:
            out["standardised"] = str(v).strip().lower() in ("true", "1", "yes", "on")
    return out


def _table(box: ExportContainer, low: str, name: str) -> tuple[np.ndarray, np.ndarray, str]:
    """(time ns or s, xyz, time column) of one motion table."""
    key = box.top_level()[low]
    df = read_table(box, key)
    where = f"{key} of {name}"
    missing = [c for c in _XYZ if c not in df.columns]
    if missing or not ({"time", "seconds_elapsed"} & set(df.columns)):
        raise InputError(f"{where} is not a Sensor Logger table (columns {list(df.columns)[:6]}); expected time, seconds_elapsed, z, y, x.")
    tcol = "time" if "time" in df.columns else "seconds_elapsed"
    vals = df[list(_XYZ)].apply(pd.to_numeric, errors="coerce")
    bad = vals.isna().any(axis=1).to_numpy()
    if bad.any():
        raise InputError(f"{where}: row {int(np.flatnonzero(bad)[0]) + 2} has a missing or non-numeric x, y or z; fix or remove that row.")
    if tcol == "time":
        t = pd.to_numeric(df[tcol], errors="coerce")
        if t.isna().any():
            raise InputError(f"{where}: row {int(np.flatnonzero(t.isna().to_numpy())[0]) + 2} has no time; fix or remove that row.")
        traw = t.to_numpy(dtype=np.int64) if (t % 1 == 0).all() else t.to_numpy(dtype=float)
    else:
        traw = df[tcol].to_numpy(dtype=float)
    return traw, vals.to_numpy(dtype=float), tcol


def read_sensor_logger(
    path: str | os.PathLike,
    *,
    sampling_rate_hz: float | None = None,
    meta: dict | None = None,
    acc_unit: str | None = None,
    gyr_unit: str | None = None,
) -> Recording:
    """Read a Sensor Logger export (zip, its folder, or one motion table of the folder).

    A motion table given alone (e.g. ``TotalAcceleration.csv``) reads the
    export folder it lies in, so the gyroscope and gravity tables beside it are
    used.

    Parameters
    ----------
    path : file or folder
    sampling_rate_hz : float, optional
        Resample to this uniform rate (default: the accelerometer's median rate).
    meta : dict, optional
        Extra metadata.

    Returns
    -------
    Recording
        acc (m/s^2 with gravity, Android frame), gyr (rad/s) when
        ``Gyroscope.csv`` is there; ``meta['acc_source']``, ``meta['frame']``,
        ``meta['platform']`` and ``meta['clock_merge']`` say what was done.

    Raises
    ------
    InputError
        No table with gravity (only ``Accelerometer.csv``), empty tables,
        clocks that do not overlap.
    """
    p = require_file(path)
    if p.is_file() and p.suffix.lower() == ".csv":
        p = p.parent
    name = p.stem if p.suffix.lower() == ".zip" else p.name
    with open_export(p) as box:
        top = box.top_level()
        info = _metadata(box)
        platform = info.get("platform", "").lower()
        ios = platform == "ios" and not info.get("standardised", False)
        m: dict = {"source": str(p), "format": "sensor-logger", "id": name, "subject": name, "session": name}
        if info.get("platform"):
            m["platform"] = info["platform"]
        if info.get("device"):
            m["device"] = info["device"]
        acc_override, gyr_override = acc_unit, gyr_unit
        acc_unit = "m/s^2"
        if "totalacceleration.csv" in top:
            t_acc, acc, tcol = _table(box, "totalacceleration.csv", name)
            m["acc_source"] = top["totalacceleration.csv"]
            sign = 1.0
        elif "accelerometer.csv" in top and "gravity.csv" in top:
            t_acc, user, tcol = _table(box, "accelerometer.csv", name)
            t_grav, grav, tcol_g = _table(box, "gravity.csv", name)
            if tcol_g != tcol:
                raise InputError(
                    f"Accelerometer.csv and Gravity.csv of {name} have different time columns; export both from the same recording."
                )
            t0 = min(t_acc[0], t_grav[0])
            ta, tg = _seconds(t_acc, t0, tcol), _seconds(t_grav, t0, tcol)
            ta_kept, user_kept, grav_on, grav_merge = merge_clocks(
                ta, user, tg, grav, what=f"{name} (Accelerometer.csv + Gravity.csv)", names=("accelerometer", "gravity sensor")
            )
            m["gravity_merge"] = grav_merge
            if grav_merge["warning"]:
                m.setdefault("warnings", []).append(grav_merge["warning"])
            acc = user_kept + grav_on
            t_acc = ta_kept if tcol == "seconds_elapsed" else (np.round(ta_kept * 1e9).astype(np.int64) + t0)
            m["acc_source"] = "Accelerometer.csv + Gravity.csv (gravity interpolated onto the accelerometer times)"
            sign = -1.0 if ios else 1.0
        elif "accelerometeruncalibrated.csv" in top:
            t_acc, acc, tcol = _table(box, "accelerometeruncalibrated.csv", name)
            m["acc_source"] = top["accelerometeruncalibrated.csv"]
            sign = -1.0 if ios else 1.0
            med = float(np.median(np.linalg.norm(acc, axis=1)))
            if ios or (not platform and 0.5 <= med <= 2.0):
                acc_unit = "g"
        elif "accelerometer.csv" in top:
            raise InputError(
                f"{name} has Accelerometer.csv, which Sensor Logger records without gravity, but no TotalAcceleration.csv, Gravity.csv "
                "or AccelerometerUncalibrated.csv; gaitml needs gravity: switch on Gravity (or the uncalibrated accelerometer) in "
                "Sensor Logger and record again."
            )
        else:
            raise InputError(
                f"{name} has no accelerometer table (TotalAcceleration.csv, Accelerometer.csv + Gravity.csv or "
                "AccelerometerUncalibrated.csv); switch on the accelerometer and gravity in Sensor Logger and record again."
            )
        if sign < 0:
            acc = -acc
            m["frame"] = "iOS frame negated to the Android convention (specific force, +z up when flat)"
        elif not platform:
            m["frame"] = "platform unknown (no Metadata.csv): Android convention assumed"
        gyr = None
        t_acc, acc = note_hold(m, "acc", *dehold(t_acc, acc, "accelerometer"))
        t0 = t_acc[0]
        if "gyroscope.csv" in top:
            t_gyr, gyr_raw, tcol_g = _table(box, "gyroscope.csv", name)
            t_gyr, gyr_raw = note_hold(m, "gyr", *dehold(t_gyr, gyr_raw, "gyroscope"))
            if tcol_g != tcol:
                raise InputError(
                    f"the accelerometer and Gyroscope.csv of {name} have different time columns; export both from the same recording."
                )
            t0 = min(t_acc[0], t_gyr[0])
            t, acc, gyr, merge = merge_clocks(_seconds(t_acc, t0, tcol), acc, _seconds(t_gyr, t0, tcol), gyr_raw, what=name)
            m["clock_merge"] = merge
            if merge["warning"]:
                m.setdefault("warnings", []).append(merge["warning"])
        else:
            t = _seconds(t_acc, t0, tcol)
            check_times(t, f"the accelerometer table of {name}")
        if tcol == "time":
            m["t0_epoch_ns"] = int(t0)
    m.update(meta or {})
    acc_unit, gyr_unit = override_units(m, acc_unit, "rad/s", acc_override, gyr_override)
    return Recording.from_timestamps(t, acc, gyr=gyr, sampling_rate_hz=sampling_rate_hz, meta=m, acc_unit=acc_unit, gyr_unit=gyr_unit)


def _seconds(t: np.ndarray, t0, tcol: str) -> np.ndarray:
    """Times in s from ``t0`` (integer ns of the ``time`` column kept exact before the division)."""
    if tcol == "time":
        return (np.asarray(t) - t0).astype(float) / 1e9
    return np.asarray(t, dtype=float) - float(t0)
