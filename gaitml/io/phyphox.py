"""Reader for phyphox CSV exports (https://phyphox.org, RWTH Aachen).

phyphox exports an experiment's data sets as one CSV table per set, in a zip
archive (or unpacked into a folder) beside a ``meta/`` folder with device and
time information; a single table may also be exported alone. Each table has a
header row naming the quantity and its unit in parentheses:

- ``Time (s)``: seconds since the experiment started, one clock for all the
  sensors of an experiment;
- ``Acceleration x (m/s^2)``, ``... y ...``, ``... z ...`` (and
  ``Absolute acceleration (m/s^2)``): the accelerometer *with* gravity, from the
  "Acceleration with g" experiment;
- ``Linear Acceleration x (m/s^2)`` ...: acceleration *without* gravity, from the
  "Acceleration without g" experiment. gaitml needs gravity (the step and
  mode algorithms use the gravity direction and |acc| around g), so such a
  table alone is refused with the fix;
- ``Gyroscope x (rad/s)`` ...: angular rate in rad/s (table ``Gyroscope.csv``).

A table's file name is the experiment's data-set name (``Accelerometer.csv``,
``Gyroscope.csv`` in phyphox's experiment definitions; ``Raw Data.csv`` is also
accepted); the reader goes by the column headers, so any name works, and the
documented names are only preferred when several tables qualify.

phyphox offers three CSV dialects (comma with decimal point, tab with decimal
point, semicolon with decimal comma); all are read. A table holding several
sensors (a custom experiment) may carry one time column per sensor: each
sensor's columns use the nearest ``Time`` column to their left, and rows where a
shorter sensor has no value are dropped for that sensor.

Accelerometer and gyroscope are merged onto one time base by
:func:`gaitml.io._merge.merge_clocks` (overlap only, gyroscope interpolated onto
the accelerometer times, reported in ``meta['clock_merge']``); then irregular
times are made uniform by :meth:`Recording.from_timestamps`.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.io._common import require_file
from gaitml.io._export import ExportContainer, open_export, read_table, sniff_csv
from gaitml.io._hold import dehold, note_hold
from gaitml.io._merge import check_times, merge_clocks, override_units
from gaitml.recording import Recording

__all__ = ["read_phyphox", "is_phyphox", "is_phyphox_header"]

#: ``Time (s)``; pandas names a repeated one ``Time (s).1``
_TIME = re.compile(r"^\s*time\s*\(\s*s\s*\)(\.\d+)?\s*$", re.IGNORECASE)
_ACC = re.compile(r"^\s*(linear\s+)?acceleration\s+([xyz])\s*\((.+)\)\s*$", re.IGNORECASE)
_GYR = re.compile(r"^\s*gyroscope\s+([xyz])\s*\((.+)\)\s*$", re.IGNORECASE)
#: The simple experiments' bare axes ``X (m/s^2)``, ``Y (rad/s)``.
_BARE = re.compile(r"^\s*([xyz])\s*\((.+)\)\s*$", re.IGNORECASE)

#: Table names of phyphox's acceleration and gyroscope experiments (lower case).
_EXPORT_TABLES = ("accelerometer.csv", "raw data.csv", "gyroscope.csv", "linear accelerometer.csv")
_ACC_UNITS = {"m/s^2": "m/s^2", "m/s²": "m/s^2", "m/s2": "m/s^2", "ms^-2": "m/s^2", "g": "g"}
_GYR_UNITS = {"rad/s": "rad/s", "deg/s": "deg/s", "°/s": "deg/s"}


def _split_header(line: str) -> list[str]:
    sep, _ = sniff_csv(line)
    return [c.strip().strip('"') for c in line.split(sep)]


def _bare_kind(unit: str) -> str | None:
    u = unit.replace(" ", "")
    if u in _ACC_UNITS or u.lower() in _ACC_UNITS:
        return "acc"
    if u in _GYR_UNITS or u.lower() in _GYR_UNITS:
        return "gyr"
    return None


def is_phyphox_header(line: str) -> bool:
    """Whether a CSV header line is a phyphox table with accelerometer or gyroscope columns.

    Both layouts count: the classic experiments' ``Acceleration x (m/s^2)`` /
    ``Gyroscope x (rad/s)`` and the simple experiments' ``X (m/s^2)`` /
    ``X (rad/s)`` (the quantity then comes from the unit and the table name).
    """
    cols = _split_header(line)
    if not any(_TIME.match(c) for c in cols):
        return False
    if any(_ACC.match(c) or _GYR.match(c) for c in cols):
        return True
    return any((m := _BARE.match(c)) and _bare_kind(m.group(2).strip()) for c in cols)


def is_phyphox(path: str | os.PathLike) -> bool:
    """Whether ``path`` (CSV file, export folder or zip) is a phyphox export; never raises."""
    try:
        p = Path(path)
        if p.is_file() and p.suffix.lower() not in (".csv", ".zip"):
            return False
        with open_export(p) as box:
            top = box.top_level()
            # a folder of several separate phyphox tables is a data set, not one export:
            # one export has the documented table names or phyphox's meta/ folder
            one = len(top) == 1 or any(k.startswith("meta/") for k in box.members) or bool(set(top) & set(_EXPORT_TABLES))
            if not one:
                return False
            for key in top.values():
                lines = box.head(key).splitlines()
                if lines and is_phyphox_header(lines[0]):
                    return True
    except (InputError, OSError, ValueError):
        return False
    return False


def _bare_groups(columns: list[str], table: str) -> dict[str, dict]:
    """The simple experiments' ``Time (s), X (unit), Y (unit), Z (unit)``: the unit says acceleration or
    angular rate, the table name says whether the acceleration is linear (``Linear Accelerometer.csv``)."""
    axes: dict[str, tuple[int, str, str]] = {}
    for i, c in enumerate(columns):
        m = _BARE.match(c)
        if m and _bare_kind(m.group(2).strip()):
            axes.setdefault(m.group(1).lower(), (i, c, m.group(2).strip()))
    if not axes:
        return {}
    units = {u for _, _, u in axes.values()}
    unit = units.pop() if len(units) == 1 else "mixed"
    kind = _bare_kind(unit) if unit != "mixed" else "acc"
    if kind == "acc" and "linear" in table.lower().replace("_", " ").replace("-", " "):
        kind = "lin"
    if set(axes) != {"x", "y", "z"}:
        raise InputError(f"the phyphox table {table} has only the {sorted(axes)} axes of {_NAMES[kind]}; export all of x, y, z.")
    first = min(i for i, _, _ in axes.values())
    times = [i for i, c in enumerate(columns) if _TIME.match(c) and i < first]
    if not times:
        raise InputError(f"the phyphox table {table} has no 'Time (s)' column before its axes; export the table with its time.")
    return {kind: {"time": columns[times[-1]], "cols": [axes[a][1] for a in "xyz"], "unit": unit, "bare": True}}


def _groups(columns: list[str], table: str = "") -> dict[str, dict]:
    """Find sensor column groups: kind -> {'time': col, 'cols': [x, y, z], 'unit': str}."""
    found: dict[str, dict] = {}
    if not any(_ACC.match(c) or _GYR.match(c) for c in columns):
        return _bare_groups(columns, table)
    for kind, pattern in (("acc", _ACC), ("lin", _ACC), ("gyr", _GYR)):
        axes: dict[str, tuple[int, str, str]] = {}
        for i, c in enumerate(columns):
            m = pattern.match(c)
            if not m:
                continue
            if pattern is _ACC:
                linear = bool(m.group(1))
                if linear != (kind == "lin"):
                    continue
                axis, unit = m.group(2).lower(), m.group(3).strip()
            else:
                axis, unit = m.group(1).lower(), m.group(2).strip()
            axes.setdefault(axis, (i, c, unit))
        if not axes:
            continue
        if set(axes) != {"x", "y", "z"}:
            raise InputError(f"the phyphox table has only the {sorted(axes)} axes of {_NAMES[kind]}; export all of x, y, z.")
        first = min(i for i, _, _ in axes.values())
        times = [i for i, c in enumerate(columns) if _TIME.match(c) and i < first]
        if not times:
            raise InputError(
                f"the phyphox table has no 'Time (s)' column before its {_NAMES[kind]} columns; export the table with its time."
            )
        units = {u for _, _, u in axes.values()}
        found[kind] = {"time": columns[times[-1]], "cols": [axes[a][1] for a in "xyz"], "unit": units.pop() if len(units) == 1 else "mixed"}
    return found


_NAMES = {"acc": "the acceleration (with g)", "lin": "the linear acceleration", "gyr": "the gyroscope"}


def _unit(kind: str, unit: str, where: str) -> str:
    table = _GYR_UNITS if kind == "gyr" else _ACC_UNITS
    u = table.get(unit.replace(" ", ""), table.get(unit.replace(" ", "").lower()))
    if u is None:
        raise InputError(
            f"{where}: unknown unit {unit!r} for {_NAMES[kind]}; export with phyphox's default units ({'rad/s' if kind == 'gyr' else 'm/s^2'})."
        )
    return u


def _take(df: pd.DataFrame, group: dict, where: str) -> tuple[np.ndarray, np.ndarray]:
    cols = [group["time"], *group["cols"]]
    sub = df[cols].apply(pd.to_numeric, errors="coerce")
    ok = sub.notna().all(axis=1).to_numpy()
    # a shorter sensor in a shared table leaves empty trailing cells: drop those rows only
    partial = sub.notna().any(axis=1).to_numpy() & ~ok
    if partial.any():
        i = int(np.flatnonzero(partial)[0])
        raise InputError(f"{where}: row {i + 2} has a missing or non-numeric value in {cols}; fix or remove that row.")
    t = sub[group["time"]].to_numpy(dtype=float)[ok]
    x = sub[group["cols"]].to_numpy(dtype=float)[ok]
    check_times(t, where)
    return t, x


def read_phyphox(
    path: str | os.PathLike,
    *,
    sampling_rate_hz: float | None = None,
    meta: dict | None = None,
    acc_unit: str | None = None,
    gyr_unit: str | None = None,
) -> Recording:
    """Read a phyphox export (one CSV table, the exported folder, or its zip).

    Parameters
    ----------
    path : file or folder
        A phyphox CSV table, the folder of an unpacked export, or the export zip.
    sampling_rate_hz : float, optional
        Resample to this uniform rate (default: the accelerometer's median rate).
    meta : dict, optional
        Extra metadata (subject, session, ...).

    Returns
    -------
    Recording
        acc (m/s^2, with gravity), gyr (rad/s) when the export has a gyroscope
        table; ``meta['clock_merge']`` describes the merge of the two clocks.

    Raises
    ------
    InputError
        No accelerometer with gravity (only linear acceleration, or only a
        gyroscope), empty tables, clocks that do not overlap, bad units.
    """
    p = require_file(path)
    acc_override, gyr_override = acc_unit, gyr_unit
    name = p.stem if p.suffix.lower() in (".zip", ".csv") else p.name
    with open_export(p) as box:
        acc_src, gyr_src, lin_src = _find_tables(box)
        if acc_src is None:
            if lin_src is not None:
                raise InputError(
                    f"{p.name} has only linear acceleration (without g) in {lin_src[0]}"
                    + (f" ({lin_src[2]['note']})" if lin_src[2].get("note") else "")
                    + "; gaitml needs gravity: "
                    "record with phyphox's 'Acceleration with g' experiment (with the Gyroscope experiment or a combined one)."
                )
            raise InputError(
                f"{p.name} has no accelerometer table (columns 'Time (s)', 'Acceleration x (m/s^2)', ...); "
                "export phyphox's 'Acceleration with g' experiment (the gyroscope alone is not enough)."
            )
        key_a, df_a, grp_a = acc_src
        where_a = f"{key_a} of {p.name}" if key_a != p.name else p.name
        t_acc, acc = _take(df_a, grp_a, where_a)
        acc_unit = _unit("acc", grp_a["unit"], where_a)
        m: dict = {"source": str(p), "format": "phyphox", "id": name, "subject": name, "session": name, "tables": [key_a]}
        t_acc, acc = note_hold(m, "acc", *dehold(t_acc, acc, "accelerometer"))
        if grp_a.get("note"):
            m["acc_source"] = grp_a["note"]
        gyr = None
        gyr_unit = "rad/s"
        t = t_acc
        if gyr_src is not None:
            key_g, df_g, grp_g = gyr_src
            where_g = f"{key_g} of {p.name}" if key_g != p.name else p.name
            t_gyr, gyr_raw = _take(df_g, grp_g, where_g)
            gyr_unit = _unit("gyr", grp_g["unit"], where_g)
            t_gyr, gyr_raw = note_hold(m, "gyr", *dehold(t_gyr, gyr_raw, "gyroscope"))
            t, acc, gyr, info = merge_clocks(t_acc, acc, t_gyr, gyr_raw, what=p.name)
            m["clock_merge"] = info
            if info["warning"]:
                m.setdefault("warnings", []).append(info["warning"])
            if key_g not in m["tables"]:
                m["tables"].append(key_g)
    m.update(meta or {})
    acc_unit, gyr_unit = override_units(m, acc_unit, gyr_unit, acc_override, gyr_override)
    return Recording.from_timestamps(t, acc, gyr=gyr, sampling_rate_hz=sampling_rate_hz, meta=m, acc_unit=acc_unit, gyr_unit=gyr_unit)


def _find_tables(box: ExportContainer):
    """The tables holding acceleration with g, the gyroscope and linear acceleration, as (key, df, group)."""
    acc = gyr = lin = None
    tables = box.top_level()
    # the documented names first, then any table with the right columns
    order = sorted(tables, key=lambda k: (k not in _EXPORT_TABLES, k))
    for low in order:
        key = tables[low]
        lines = box.head(key).splitlines()
        if not lines and low in _EXPORT_TABLES:
            raise InputError(
                f"{key} of {box.path.name} is empty; record again with this sensor switched on, or export the experiment again."
            )
        if not lines or not is_phyphox_header(lines[0]):
            continue
        df = read_table(box, key)
        groups = _recheck_gravity(_groups(list(df.columns), key), df, key)
        if acc is None and "acc" in groups:
            acc = (key, df, groups["acc"])
        if gyr is None and "gyr" in groups:
            gyr = (key, df, groups["gyr"])
        if lin is None and "lin" in groups:
            lin = (key, df, groups["lin"])
    return acc, gyr, lin


#: Median |acc| (m/s^2) between these bounds means gravity is included, below the lower one that it is not.
GRAVITY_BAND_MS2 = (6.5, 13.0)


def _recheck_gravity(groups: dict, df: pd.DataFrame, key: str) -> dict:
    """Decide "with g" or "linear" from the data, not only from the column and table names.

    Custom experiments name their columns freely (a table of acceleration *with*
    gravity may be called "Linear Acceleration"), and the simple experiments'
    bare ``X (m/s^2)`` columns do not say it at all. The median magnitude
    decides: inside :data:`GRAVITY_BAND_MS2` the table includes gravity; below
    its lower bound it is linear acceleration; the name is kept otherwise. A
    relabelled group carries a ``note``.
    """
    out = dict(groups)
    for kind in ("acc", "lin"):
        grp = out.get(kind)
        if grp is None or grp.get("unit") not in ("m/s^2", "m/s²", "m/s2", "ms^-2"):
            continue
        vals = df[grp["cols"]].apply(pd.to_numeric, errors="coerce").to_numpy(float)
        vals = vals[np.isfinite(vals).all(axis=1)]
        if not len(vals):
            continue
        med = float(np.median(np.linalg.norm(vals, axis=1)))
        lo, hi = GRAVITY_BAND_MS2
        if kind == "lin" and lo <= med <= hi and "acc" not in out:
            del out["lin"]
            out["acc"] = {
                **grp,
                "note": f"{key}: named linear acceleration but its median |a| is {med:.2f} m/s^2: gravity included, read as acceleration with g",
            }
        elif kind == "acc" and med < lo and "lin" not in out:
            del out["acc"]
            out["lin"] = {**grp, "note": f"{key}: median |a| is {med:.2f} m/s^2: no gravity (linear acceleration)"}
    return out
