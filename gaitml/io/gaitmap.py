"""Reader for the gaitmap example recordings (foot-mounted Shimmer IMUs, MIT licence).

Files have two header rows (``sensor``: left_sensor/right_sensor, ``axis``:
acc_x..gyr_z) and a first column that is either the sample index or the time in
s; the single-sensor patient files have one header row (``index, acc_x ...``).
Acceleration is m/s^2; angular rate is **deg/s** and is converted to rad/s here.
The sampling rate is not in the files: it is taken from the time column where
there is one, else from :data:`GAITMAP_RATES_HZ` (the data set's README), else it
must be given.

For ``imu_sample.csv.gz`` the reference tables beside it are attached for the
chosen foot: ``reference['strides']`` (stride_borders_sample) and
``reference['stride_events']`` (stride_events_sample: ic, tc, min_vel, pre_ic in
samples), and ``reference['min_vel_t_s']``.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.consts import DEG2RAD
from gaitml.errors import InputError
from gaitml.io._common import head_lines, require_file
from gaitml.recording import Recording

__all__ = ["read_gaitmap_csv", "is_gaitmap_header", "GAITMAP_RATES_HZ", "read_gaitmap_table"]

#: Sampling rates of the example files (gaitmap example_data README).
GAITMAP_RATES_HZ = {
    "imu_sample": 204.8,
    "imu_sample_not_rotated": 204.8,
    "imu_sample_healthy_stair_up": 204.8,
    "imu_sample_healthy_stair_down": 204.8,
    "imu_sample_ic_stride": 102.4,
    "imu_sample_ms_left": 102.4,
    "imu_sample_ms_right": 102.4,
}
_AXES = ("acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z")
_REFERENCE_FILES = {
    "imu_sample": ("stride_borders_sample", "stride_events_sample"),
    "imu_sample_not_rotated": ("stride_borders_sample", "stride_events_sample"),
    "imu_sample_ic_stride": ("stride_borders_sample_ic_stride", None),
}
#: Annotation tables of the example folder (not recordings; ``gaitml info`` describes them).
GAITMAP_TABLES = {
    "stride_borders_sample",
    "stride_borders_sample_ic_stride",
    "stride_events_sample",
    "mocap_sample",
    "position_sample",
    "orientation_sample",
}


def _stem(p: Path) -> str:
    return p.name.split(".")[0]


def is_gaitmap_header(lines: list[str]) -> bool:
    """Whether the first lines look like a gaitmap IMU CSV (two- or one-row header)."""
    if len(lines) < 2:
        return False
    first = lines[0].split(",")
    second = lines[1].split(",")
    if any("_sensor" in c for c in first) and all(a in second for a in _AXES):
        return True
    return first[:2] == ["", "index"] and all(a in first for a in _AXES)


def read_gaitmap_csv(
    path: str | os.PathLike,
    *,
    sensor: str = "left",
    sampling_rate_hz: float | None = None,
) -> Recording:
    """Read a gaitmap example IMU CSV for one foot (``sensor='left'|'right'``)."""
    p = require_file(path)
    if sensor not in ("left", "right"):
        raise InputError(f"`sensor` must be 'left' or 'right', got {sensor!r}.")
    lines = head_lines(p, 2)
    if not is_gaitmap_header(lines):
        raise InputError(f"{p.name} is not a gaitmap IMU CSV: expected a header of sensor names and {', '.join(_AXES)}.")
    two_rows = any("_sensor" in c for c in lines[0].split(","))
    try:
        if two_rows:
            df = pd.read_csv(p, header=[0, 1], index_col=0)
            key = f"{sensor}_sensor"
            if key not in df.columns.get_level_values(0):
                raise InputError(f"{p.name} has no {key}; choose --sensor from {sorted(set(df.columns.get_level_values(0)))}.")
            sub = df[key]
            index = df.index.to_numpy(dtype=float)
        else:
            df = pd.read_csv(p, index_col=0)
            sub = df
            index = df["index"].to_numpy(dtype=float) if "index" in df.columns else df.index.to_numpy(dtype=float)
    except (pd.errors.ParserError, EOFError, OSError) as exc:
        raise InputError(f"cannot read {p.name} ({exc}); the file may be truncated.") from exc
    vals = sub[list(_AXES)].apply(pd.to_numeric, errors="coerce").to_numpy(dtype=float)
    if not np.isfinite(vals).all():
        row = int(np.flatnonzero(~np.isfinite(vals).all(axis=1))[0])
        raise InputError(f"{p.name}: missing or non-numeric value at data row {row}; the file may be truncated.")
    stem = _stem(p)
    fs = sampling_rate_hz
    if fs is None:
        step = np.diff(index[:50]) if len(index) > 1 else np.array([1.0])
        if len(step) and np.all(np.abs(step - 1.0) < 1e-9):
            fs = GAITMAP_RATES_HZ.get(stem)
            if fs is None:
                raise InputError(f"{p.name} has no time column and an unknown rate; pass --sampling-rate-hz.")
        else:
            fs = float(np.round(1.0 / np.median(np.diff(index)), 6))
    meta = {
        "source": str(p),
        "format": "gaitmap",
        "id": f"{stem}:{sensor}" if two_rows else stem,
        "subject": stem,
        "session": stem,
        "sensor": sensor if two_rows else stem.rsplit("_", 1)[-1],
        "position": "foot",
        "converted": ["gyr from deg/s"],
    }
    ref: dict = {}
    borders, events = _REFERENCE_FILES.get(stem, (None, None))
    for name, key in ((borders, "strides"), (events, "stride_events")):
        if name is None:
            continue
        f = p.with_name(f"{name}.csv.gz")
        if f.exists():
            tab = pd.read_csv(f)
            tab = tab[tab["foot"] == sensor].reset_index(drop=True)
            ref[key] = tab
    if "stride_events" in ref:
        ref["min_vel_t_s"] = ref["stride_events"]["min_vel"].to_numpy(dtype=float) / fs
    return Recording(
        acc=vals[:, :3],
        gyr=vals[:, 3:] * DEG2RAD,
        sampling_rate_hz=fs,
        meta=meta,
        reference=ref,
    )


def read_gaitmap_table(path: str | os.PathLike) -> dict:
    """Describe a gaitmap annotation table (strides, events, mocap): rows, columns, per-foot counts."""
    p = require_file(path)
    stem = _stem(p)
    if stem == "mocap_sample":
        df = pd.read_csv(p, header=[0, 1], index_col=0)
        markers = sorted(set(df.columns.get_level_values(0)))
        return {"format": "gaitmap-mocap", "rows": len(df), "markers": markers, "sampling_rate_hz": 100.0, "unit": "mm"}
    df = pd.read_csv(p)
    first = df.columns[0]
    out = {"format": "gaitmap-table", "table": stem, "rows": int(len(df)), "columns": [str(c) for c in df.columns]}
    if "foot" in df.columns:
        out["per_foot"] = {str(k): int(v) for k, v in df.groupby("foot").size().items()}
    elif str(first).startswith("Unnamed") or first == "":
        out["per_sensor"] = {str(k): int(v) for k, v in df.iloc[:, 0].value_counts().sort_index().items()}
    return out
