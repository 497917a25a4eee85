"""Reader for the Oxford step counter data set (Salvi et al., CC BY 4.0).

A recording is a folder ``<Phone>_<User>_<Surface>_<Position>_<n>/`` with

- ``accelerometer.csv(.gz)``: no header; ``t_ns`` (Android timestamp, ns),
  ``accuracy``, ``ax, ay, az`` (m/s^2, gravity included), logged at an
  irregular rate (about 100-405 Hz depending on the phone);
- ``stepcounter.csv``: no header; ``t_ns`` on the same clock, then the right and
  left foot-switch states (0/1). Every 0 -> 1 transition in either column is one
  step (this reproduces the 13,740 steps of ``stats.csv`` exactly; a switch
  already closed in the first row is not a step).

The accelerometer is resampled by linear interpolation to a uniform
``sampling_rate_hz`` (default :data:`OXFORD_RATE_HZ` = 100 Hz: the lowest native
rate among the phones, so no phone is up-sampled, and well above the < 5 Hz
band of gait). True step times become ``reference['steps_t_s']`` (s from the
first resampled sample).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.io._common import require_file
from gaitml.recording import Recording

__all__ = ["read_oxford_folder", "is_oxford_folder", "list_oxford_folders", "OXFORD_RATE_HZ", "oxford_step_times_ns"]

#: Uniform rate the irregular Oxford accelerometer logs are resampled to.
OXFORD_RATE_HZ = 100.0
_POSITION_ALIASES = {"armband": "Armband", "backpocket": "BackPocket"}
_NAME = re.compile(r"^(?P<phone>[A-Za-z]+)_(?P<user>[A-Za-z]+)_(?P<surface>[A-Za-z]+)_(?P<position>[A-Za-z]+)_(?P<n>\d+)$")


def _acc_file(folder: Path) -> Path | None:
    for name in ("accelerometer.csv.gz", "accelerometer.csv"):
        if (folder / name).exists():
            return folder / name
    return None


def is_oxford_folder(path: Path) -> bool:
    """Whether ``path`` is one Oxford recording folder."""
    return path.is_dir() and _acc_file(path) is not None and (path / "stepcounter.csv").exists()


def list_oxford_folders(path: Path) -> list[Path]:
    """Oxford recording folders under ``path`` (itself, its children, or ``data/`` below it)."""
    if is_oxford_folder(path):
        return [path]
    for base in (path, path / "data", path / "optimisation" / "data"):
        if base.is_dir():
            found = [d for d in sorted(base.iterdir()) if is_oxford_folder(d)]
            if found:
                return found
    return []


def oxford_step_times_ns(states: np.ndarray) -> np.ndarray:
    """Step times (ns) from a stepcounter table ``[t_ns, right, left]``: every 0 -> 1 transition."""
    t = states[:, 0]
    times = []
    for c in (1, 2):
        x = states[:, c]
        idx = np.flatnonzero((x[1:] == 1) & (x[:-1] == 0)) + 1
        times.append(t[idx])
    return np.sort(np.concatenate(times))


def _read_numeric(path: Path, n_cols: int, what: str) -> np.ndarray:
    try:
        df = pd.read_csv(path, header=None)
    except pd.errors.EmptyDataError as exc:
        raise InputError(f"the file is empty: {path}; the recording is incomplete.") from exc
    except (OSError, EOFError, pd.errors.ParserError) as exc:
        raise InputError(f"cannot read {path} ({exc}); the file may be truncated.") from exc
    if df.shape[1] != n_cols:
        raise InputError(f"{path.name} has {df.shape[1]} columns; an Oxford {what} has {n_cols}.")
    vals = df.apply(pd.to_numeric, errors="coerce").to_numpy(dtype=float)
    if not np.isfinite(vals).all():
        row = int(np.flatnonzero(~np.isfinite(vals).all(axis=1))[0]) + 1
        raise InputError(f"{path.name}: missing or non-numeric value at row {row}; the file may be truncated.")
    return vals


def read_oxford_folder(
    path: str | os.PathLike, *, sampling_rate_hz: float = OXFORD_RATE_HZ, segments: bool = False
) -> Recording | list[Recording]:
    """Read one Oxford recording folder, resampled to ``sampling_rate_hz``.

    ``segments=True`` cuts the log at gaps too long to bridge and returns a list
    (see :meth:`Recording.segments_from_timestamps`); by default they are refused.
    """
    d = require_file(path)
    acc_path = _acc_file(d)
    if acc_path is None or not (d / "stepcounter.csv").exists():
        raise InputError(f"{d} is not an Oxford recording folder: it needs accelerometer.csv(.gz) and stepcounter.csv.")
    acc = _read_numeric(acc_path, 5, "accelerometer log (t_ns, accuracy, ax, ay, az)")
    steps = _read_numeric(d / "stepcounter.csv", 3, "stepcounter (t_ns, right, left)")
    meta: dict = {"source": str(d), "format": "oxford", "id": d.name, "session": d.name}
    m = _NAME.match(d.name)
    if m:
        pos = m["position"]
        meta.update(
            device=m["phone"],
            subject=m["user"],
            user=m["user"],
            surface=m["surface"],
            position=_POSITION_ALIASES.get(pos.lower(), pos),
            trial=int(m["n"]),
        )
    else:
        meta["subject"] = d.name
    meta_file = d / "metadata.txt"
    if meta_file.exists():
        meta["chip"] = meta_file.read_text(errors="replace").strip()
    step_ns = oxford_step_times_ns(steps)
    t_s = acc[:, 0] * 1e-9
    if segments:
        return Recording.segments_from_timestamps(
            t_s, acc[:, 2:5], sampling_rate_hz=sampling_rate_hz, meta=meta, reference={"steps_t_s": step_ns * 1e-9}
        )
    rec = Recording.from_timestamps(
        t_s,
        acc[:, 2:5],
        sampling_rate_hz=sampling_rate_hz,
        meta=meta,
        reference={"steps_t_s": step_ns * 1e-9},
    )
    rec.reference["n_steps_true"] = int(len(step_ns))
    return rec
