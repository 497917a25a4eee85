"""Any CSV with a column map: for the apps and loggers gaitml has no reader for.

The map names which column holds what, as ``key=column`` pairs
(CLI ``--columns t=timestamp,acc_x=ax,acc_y=ay,acc_z=az,gyr_x=gx,gyr_y=gy,gyr_z=gz``):

- ``t`` (required): the time column, in ``time_unit`` (s, ms, us or ns; any
  origin, e.g. epoch ms) or date-time text (ISO 8601);
- ``acc_x, acc_y, acc_z`` (required): accelerometer with gravity, in
  ``acc_unit`` (m/s^2 or g);
- ``gyr_x, gyr_y, gyr_z`` (optional, all three): gyroscope in ``gyr_unit``
  (rad/s or deg/s);
- ``t_gyr`` (optional): a separate time column for the gyroscope, when the
  file interleaves two sensors with their own clocks (rows where one sensor has
  no value are skipped for it); both are merged onto the accelerometer's times
  by :func:`gaitml.io._merge.merge_clocks`;
- ``label`` (optional): a per-sample label column.

A column is named by its header text, or by its 0-based position when the
text is a number that is not a header. The separator (comma, tab, semicolon
with decimal comma) is taken from the header line.
"""

from __future__ import annotations

import io
import os
import re
from collections.abc import Mapping

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.io._common import require_file
from gaitml.io._export import sniff_csv
from gaitml.io._hold import dehold
from gaitml.io._merge import check_times, merge_clocks
from gaitml.recording import MIN_RATE_HZ, Recording

__all__ = ["read_columns_csv", "parse_column_map", "TIME_UNITS", "COLUMN_KEYS"]

#: Seconds per unit of the time column.
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}
#: Keys a column map may use.
COLUMN_KEYS = ("t", "acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z", "t_gyr", "label")
_EXAMPLE = "t=timestamp,acc_x=ax,acc_y=ay,acc_z=az[,gyr_x=gx,gyr_y=gy,gyr_z=gz]"


def parse_column_map(spec: str | Mapping[str, str]) -> dict[str, str]:
    """Parse ``'t=time,acc_x=ax,...'`` (or check a mapping) into ``{key: column}``.

    Raises
    ------
    InputError
        Unknown or repeated keys, a pair without ``=``, missing required keys,
        an incomplete gyroscope.
    """
    if isinstance(spec, Mapping):
        pairs = [(str(k).strip(), str(v).strip()) for k, v in spec.items()]
    else:
        pairs = []
        for item in str(spec).split(","):
            if not item.strip():
                continue
            if "=" not in item:
                raise InputError(f"--columns item {item.strip()!r} has no '='; write key=column pairs, e.g. {_EXAMPLE}.")
            k, v = item.split("=", 1)
            pairs.append((k.strip(), v.strip()))
    out: dict[str, str] = {}
    for k, v in pairs:
        if k not in COLUMN_KEYS:
            raise InputError(f"unknown --columns key {k!r}; use {', '.join(COLUMN_KEYS)}.")
        if k in out:
            raise InputError(f"--columns names {k!r} twice; give each key once.")
        if not v:
            raise InputError(f"--columns key {k!r} has no column name; write {k}=<column>.")
        out[k] = v
    missing = [k for k in ("t", "acc_x", "acc_y", "acc_z") if k not in out]
    if missing:
        raise InputError(f"--columns lacks {', '.join(missing)}; give at least {_EXAMPLE}.")
    gyr = [k for k in ("gyr_x", "gyr_y", "gyr_z") if k in out]
    if gyr and len(gyr) != 3:
        raise InputError(f"--columns has only {', '.join(gyr)} of the gyroscope; give gyr_x, gyr_y and gyr_z, or none.")
    if "t_gyr" in out and not gyr:
        raise InputError("--columns has t_gyr but no gyroscope columns; add gyr_x, gyr_y, gyr_z or drop t_gyr.")
    return out


def _resolve(df: pd.DataFrame, name: str, key: str, fname: str) -> str:
    if name in df.columns:
        return name
    if name.isdigit() and int(name) < len(df.columns):
        return str(df.columns[int(name)])
    raise InputError(f"{fname} has no column {name!r} (for {key}); its columns are {list(df.columns)[:10]}; fix --columns.")


def _times(series: pd.Series, unit: str, where: str) -> np.ndarray:
    num = pd.to_numeric(series, errors="coerce")
    if num.notna().all():
        vals = num.to_numpy()
        if np.issubdtype(vals.dtype, np.integer):
            vals = vals - vals[0]  # keep epoch ns exact before scaling
        else:
            vals = vals.astype(float) - float(vals[0])
        return vals.astype(float) * TIME_UNITS[unit]
    clock = series.astype(str).str.strip().str.extract(_CLOCK)
    if len(series) and clock[[1, 2]].notna().all(axis=None):
        secs = _clock_seconds(clock)
        if secs is not None:
            return secs - secs[0]
    try:
        dt = pd.to_datetime(series, utc=True, format="ISO8601")
    except (ValueError, TypeError) as exc:
        bad = int(np.flatnonzero(num.isna().to_numpy())[0])
        raise InputError(
            f"{where}: time {series.iloc[bad]!r} at line {bad + 2} is neither a number nor a date-time; fix the column or --columns t=."
        ) from exc
    return datetime_seconds(dt)


def datetime_seconds(dt: pd.Series) -> np.ndarray:
    """Seconds from the first date-time, whatever resolution pandas parsed it at.

    pandas 2 parses to nanoseconds, pandas 3 to the resolution the text needs
    (microseconds, milliseconds...): the unit is read from the dtype
    (``numpy.datetime_data``), never assumed.
    """
    values = dt.dt.tz_localize(None).to_numpy() if getattr(dt.dt, "tz", None) is not None else dt.to_numpy()
    unit, count = np.datetime_data(values.dtype)
    ticks = values.view("int64")
    per_s = {"s": 1, "ms": 1e3, "us": 1e6, "ns": 1e9}[unit] / count
    return (ticks - ticks[0]).astype(float) / per_s


#: Clock times without a date: ``HH:MM:SS.fff``, ``MM:SS.fff`` or ``HH:MM:SS:fff`` (Physics Toolbox).
_CLOCK = r"^(?:(\d{1,2}):)?(\d{1,2}):(\d{1,2}(?:\.\d+)?)(?::(\d{1,3}))?$"


def _clock_seconds(parts: pd.DataFrame) -> np.ndarray | None:
    """Seconds of clock-time parts (hours optional; a fourth ``:fff`` field is milliseconds); midnight roll-over unwrapped."""
    if parts[[1, 2]].isna().any(axis=None):
        return None
    h = pd.to_numeric(parts[0], errors="coerce").fillna(0).to_numpy(float)
    m = pd.to_numeric(parts[1]).to_numpy(float)
    sec = pd.to_numeric(parts[2]).to_numpy(float)
    ms = pd.to_numeric(parts[3], errors="coerce").fillna(0).to_numpy(float) / 1000.0
    out = h * 3600 + m * 60 + sec + ms
    period = 86400.0 if parts[0].notna().any() else 3600.0
    wraps = np.cumsum(np.r_[0, np.diff(out) < -period / 2])
    return out + wraps * period


def read_columns_csv(
    path: str | os.PathLike,
    columns: str | Mapping[str, str],
    *,
    time_unit: str = "s",
    acc_unit: str = "m/s^2",
    gyr_unit: str = "rad/s",
    sampling_rate_hz: float | None = None,
    meta: dict | None = None,
) -> Recording:
    """Read a CSV whose columns are named by a column map (see the module doc).

    Parameters
    ----------
    path : CSV file
    columns : str or mapping
        ``'t=...,acc_x=...,acc_y=...,acc_z=...'`` or the same as a dict.
    time_unit : {'s', 'ms', 'us', 'ns'}
        Unit of the numeric time column(s).
    acc_unit, gyr_unit : units of the acc / gyr columns, converted to SI.
    sampling_rate_hz : float, optional
        Resample to this rate (default: the median rate of the accelerometer).

    Returns
    -------
    Recording
        ``meta['columns']`` keeps the map; ``meta['clock_merge']`` when a
        separate gyroscope clock was merged.
    """
    cmap = parse_column_map(columns)
    if time_unit not in TIME_UNITS:
        raise InputError(f"unknown time unit {time_unit!r}; choose one of {', '.join(TIME_UNITS)} (CLI: --time-unit).")
    p = require_file(path)
    if p.is_dir():
        raise InputError(f"{p} is a folder; --columns reads one CSV file, pass the file.")
    try:
        raw = p.read_bytes()
        head = raw[:4096].decode("utf-8-sig", errors="replace")
        sep, dec, skip = _dialect(head.splitlines())
        df = pd.read_csv(io.BytesIO(raw), sep=sep, decimal=dec, encoding="utf-8-sig", skipinitialspace=True, skiprows=skip)
    except pd.errors.EmptyDataError as exc:
        raise InputError(f"the file is empty: {p}; record or export the data again.") from exc
    except (pd.errors.ParserError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot parse {p.name} as CSV ({str(exc).splitlines()[0]}); check the file and its separator.") from exc
    df.columns = [str(c).strip() for c in df.columns]
    if len(df) == 0:
        raise InputError(f"{p.name} has a header but no samples; record or export the data again.")
    col = {k: _resolve(df, v, k, p.name) for k, v in cmap.items()}
    acc_cols = [col["acc_x"], col["acc_y"], col["acc_z"]]
    has_gyr = "gyr_x" in col
    gyr_cols = [col["gyr_x"], col["gyr_y"], col["gyr_z"]] if has_gyr else []
    separate = "t_gyr" in col
    acc_rows = _rows(df, [col["t"], *acc_cols], p.name, allow_empty=separate)
    t_acc = _times(df.loc[acc_rows, col["t"]], time_unit, p.name)
    acc = df.loc[acc_rows, acc_cols].apply(pd.to_numeric).to_numpy(dtype=float)
    m: dict = {"source": str(p), "format": "columns-csv", "id": p.stem, "subject": p.stem, "session": p.stem, "columns": dict(cmap)}
    if skip:
        m["dialect"] = f"first line {head.splitlines()[0].strip()!r} (a spreadsheet separator hint) skipped"
    if time_unit != "s":
        m["time_unit"] = time_unit
    labels = None
    if "label" in col:
        # labels as written: "01" stays "01", "NA" and "None" are labels (only an empty field is missing)
        text = pd.read_csv(
            io.BytesIO(raw), sep=sep, decimal=dec, encoding="utf-8-sig", skipinitialspace=True, dtype=str, keep_default_na=False
        )
        lab = text.iloc[:, list(df.columns).index(col["label"])][acc_rows.to_numpy() if hasattr(acc_rows, "to_numpy") else acc_rows]
        empty = lab.str.strip().eq("").to_numpy()
        if empty.any():
            raise InputError(
                f"{p.name}: empty label at line {int(np.flatnonzero(empty)[0]) + 2}; label every sample or drop label= from --columns."
            )
        labels = lab.astype(str).to_numpy()
    gyr = None
    t = t_acc
    if has_gyr and separate:
        gyr_rows = _rows(df, [col["t_gyr"], *gyr_cols], p.name, allow_empty=True)
        t_all = _times(pd.concat([df.loc[acc_rows, col["t"]], df.loc[gyr_rows, col["t_gyr"]]]), time_unit, p.name)
        t_acc, t_gyr = t_all[: int(acc_rows.sum())], t_all[int(acc_rows.sum()) :]
        gyr_raw = df.loc[gyr_rows, gyr_cols].apply(pd.to_numeric).to_numpy(dtype=float)
        check_times(t_gyr, f"the gyroscope of {p.name}")
        t, acc, gyr, info = merge_clocks(t_acc, acc, t_gyr, gyr_raw, what=p.name)
        if labels is not None:
            labels = labels[np.isin(t_acc, t)]
        m["clock_merge"] = info
        if info["warning"]:
            m.setdefault("warnings", []).append(info["warning"])
    elif has_gyr:
        gyr = df.loc[acc_rows, gyr_cols].apply(pd.to_numeric, errors="coerce").to_numpy(dtype=float)
        bad = ~np.isfinite(gyr).all(axis=1)
        if bad.any():
            raise InputError(
                f"{p.name}: a missing or non-numeric gyroscope value at line {int(np.flatnonzero(bad)[0]) + 2}; fix the row, or give t_gyr= if the gyroscope has its own clock."
            )
    t, acc, gyr, labels = dehold_rows(t, acc, gyr, labels, m, p.name)
    _check_row_rate(t, time_unit, p.name)
    m.update(meta or {})
    return Recording.from_timestamps(
        t, acc, gyr=gyr, labels=labels, sampling_rate_hz=sampling_rate_hz, meta=m, acc_unit=acc_unit, gyr_unit=gyr_unit
    )


def _rows(df: pd.DataFrame, cols: list[str], fname: str, *, allow_empty: bool) -> np.ndarray:
    """Rows where all ``cols`` are present (numeric except a time column); partial rows are an error."""
    present = df[cols].notna()
    full = present.all(axis=1).to_numpy()
    partial = present.any(axis=1).to_numpy() & ~full
    if partial.any() or (not allow_empty and not full.all()):
        i = int(np.flatnonzero(partial if partial.any() else ~full)[0])
        raise InputError(f"{fname}: line {i + 2} has an empty cell in {cols}; fix or remove that row.")
    for c in cols[1:]:
        vals = pd.to_numeric(df.loc[full, c], errors="coerce")
        if vals.isna().any():
            i = int(np.flatnonzero(full)[int(np.flatnonzero(vals.isna().to_numpy())[0])])
            raise InputError(f"{fname}: column {c!r} has a non-numeric value at line {i + 2}; fix or remove that row.")
    if full.sum() == 0:
        raise InputError(f"{fname} has no rows with all of {cols}; check --columns.")
    return full


def _dialect(lines: list[str]) -> tuple[str, str, int]:
    """``(separator, decimal, rows to skip)``: a first line ``sep=;`` (AndroSensor, Excel) names the separator.

    With a semicolon separator the decimal mark is taken from the first data rows
    (``1,5`` -> comma; AndroSensor writes points).
    """
    skip = 0
    if lines and lines[0].strip().lower().startswith("sep=") and len(lines[0].strip()) >= 5:
        sep = lines[0].strip()[4]
        skip = 1
        header = lines[1] if len(lines) > 1 else ""
        dec = "."
    else:
        header = lines[0] if lines else ""
        sep, dec = sniff_csv(header)
    if sep == ";":
        rows = [c.strip() for line in lines[skip + 1 : skip + 6] for c in line.split(";")]
        dec = "," if any(re.fullmatch(r"[-+]?\d+,\d+([eE][-+]?\d+)?", c) for c in rows) else "."
    return sep, dec, skip


def dehold_rows(t, acc, gyr, labels, m: dict, name: str):
    """Read sample-and-hold columns at their own update times (gaitml.io._hold), merging the two clocks if needed."""
    t_a, acc_a, info_a = dehold(t, acc, "accelerometer")
    hold: dict = {}
    if info_a:
        hold["acc"] = info_a
    if gyr is not None and "clock_merge" not in m:
        t_g, gyr_g, info_g = dehold(t, gyr, "gyroscope")
        if info_g:
            hold["gyr"] = info_g
        if hold:
            t_new, acc_new, gyr_new, merge = merge_clocks(t_a, acc_a, t_g, gyr_g, what=name)
            m["clock_merge"] = merge
            if merge["warning"]:
                m.setdefault("warnings", []).append(merge["warning"])
            if labels is not None:
                labels = labels[np.searchsorted(t, t_new)]
            t, acc, gyr = t_new, acc_new, gyr_new
    elif info_a:
        if labels is not None:
            labels = labels[np.searchsorted(t, t_a)]
        t, acc = t_a, acc_a
    if hold:
        m["sample_and_hold"] = hold
        m.setdefault("warnings", []).extend(v["warning"] for v in hold.values())
    return t, acc, gyr, labels


def _check_row_rate(t: np.ndarray, time_unit: str, name: str) -> None:
    """Refuse a too-slow time base with a message that knows the --time-unit given."""
    if len(t) < 2:
        return
    d = np.diff(t)
    d = d[d > 0]
    if not len(d):
        return
    rate = 1.0 / float(np.median(d))
    if rate < MIN_RATE_HZ * (1 - 1e-6):
        other = [u for u in TIME_UNITS if u != time_unit]
        raise InputError(
            f"{name}: the samples are {1 / rate:.4g} s apart ({rate:.4g} Hz with the time column read in {time_unit}), too slow for gait "
            f"(>= {MIN_RATE_HZ:g} Hz): if the time column is not in {time_unit} pass --time-unit with one of {', '.join(other)}; "
            "otherwise record with a shorter logging interval (AndroSensor: Settings, recording interval)."
        )
