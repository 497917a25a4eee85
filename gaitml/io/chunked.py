"""Chunked reading for long recordings: bounded memory for day-long files.

A 24-hour recording at 100 Hz has 8.6 million samples; holding it (and a
detector's intermediate arrays) in memory at once costs gigabytes. The
functions here read a gaitml-csv file in blocks and hand out overlapping
:class:`Recording` chunks:

``[ margin | core | margin ]``

Each chunk carries ``margin_s`` of signal on both sides of its *core*; the
caller keeps only the results whose anchor sample lies in the core, so every
event is reported once, and filters and detectors see enough context at the
edges. Core boundaries are multiples of ``align_samples`` so that sliding
windows keep the same global grid as a whole-file run.

Irregular timestamps are resampled onto the global grid ``t0 + k / fs`` by
linear interpolation, carrying the last sample of the previous block across the
block boundary, so the result equals the whole-file resampling. Without
``sampling_rate_hz`` the rate is the median rate of the first block (stated in
the chunk's ``meta``). Other formats are small and are read whole, then sliced.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.consts import ACC_COLS, GYR_COLS, LABEL_COL, TIME_COL
from gaitml.errors import InputError
from gaitml.io._common import require_file
from gaitml.io._detect import detect_format, read_recording
from gaitml.recording import Recording, check_acc_unit, check_ranges, convert_units, max_bridge_s

__all__ = ["Chunk", "iter_chunks", "estimate_samples", "LARGE_INPUT_SAMPLES"]

#: Inputs with more samples than this are processed in chunks by the CLI.
LARGE_INPUT_SAMPLES = 2_000_000
_ROWS_PER_READ = 200_000


@dataclass(frozen=True)
class Chunk:
    """One overlapping chunk of a long recording.

    Attributes
    ----------
    recording : Recording
        Samples ``[offset, offset + recording.n_samples)`` of the whole recording.
    offset : int
        Global index of the chunk's first sample.
    core_start, core_end : int
        The chunk's core as *global* sample indices ``[core_start, core_end)``;
        results anchored there belong to this chunk.
    total_hint : int or None
        Estimated number of samples of the whole recording (for progress bars).
    """

    recording: Recording
    offset: int
    core_start: int
    core_end: int
    total_hint: int | None = None


def estimate_samples(path: str | os.PathLike) -> int:
    """A cheap estimate of the number of samples of a file (from its size)."""
    p = require_file(path)
    if p.is_dir():
        return 0
    size = p.stat().st_size
    if p.name.endswith(".gz"):
        size *= 4
    with open(p, "rb") as fh:
        head = fh.read(65536)
    if p.name.endswith(".gz"):
        return size // 60
    lines = head.count(b"\n")
    if lines < 2:
        return 0
    return int(size / (len(head) / lines))


def _guarded(reader, path: Path):
    """Iterate a pandas chunk reader, turning a truncated or corrupt file into an InputError."""
    import gzip
    import zlib

    it = iter(reader)
    while True:
        try:
            df = next(it)
        except StopIteration:
            return
        except (EOFError, zlib.error, gzip.BadGzipFile, pd.errors.ParserError) as exc:
            raise InputError(f"cannot read {path.name}: {exc}; the file is truncated or corrupt.") from exc
        yield df


def _blocks_gaitml_csv(path: Path, sampling_rate_hz: float | None, acc_unit: str, gyr_unit: str):
    """Yield (acc, gyr, labels, meta) blocks on the uniform global grid."""
    reader = pd.read_csv(path, chunksize=_ROWS_PER_READ, skipinitialspace=True)
    fs = sampling_rate_hz
    t0 = None
    prev = None  # last raw row of the previous block: (t, acc, gyr, label)
    k_next = 0
    has_gyr = None
    has_lab = None
    line = 2
    resampled = None
    gap_limit = np.inf
    for df in _guarded(reader, path):
        df.columns = [str(c).strip() for c in df.columns]
        missing = [c for c in (TIME_COL, *ACC_COLS) if c not in df.columns]
        if missing:
            raise InputError(f"{path.name} is not a gaitml-csv: missing columns {missing}; expected t, acc_x, acc_y, acc_z.")
        if has_gyr is None:
            has_gyr = all(c in df.columns for c in GYR_COLS)
            has_lab = LABEL_COL in df.columns
        cols = [TIME_COL, *ACC_COLS, *(GYR_COLS if has_gyr else ())]
        vals = df[cols].apply(pd.to_numeric, errors="coerce").to_numpy(dtype=float)
        bad = ~np.isfinite(vals).all(axis=1)
        if bad.any():
            raise InputError(
                f"{path.name}: NaN/inf or non-numeric value at line {line + int(np.flatnonzero(bad)[0])}; "
                "remove or interpolate those rows before loading."
            )
        t = vals[:, 0]
        acc = vals[:, 1:4]
        gyr = vals[:, 4:7] if has_gyr else None
        lab = df[LABEL_COL].astype(str).to_numpy() if has_lab else None
        acc, gyr = convert_units(acc, gyr, acc_unit, gyr_unit)
        conv = [c for c, on in (("acc from g", acc_unit == "g"), ("gyr from deg/s", gyr_unit == "deg/s")) if on]
        try:
            check_ranges(acc, gyr, {"converted": conv})  # before interpolating: a 1e308 would overflow
        except InputError as exc:
            first = line
            msg = re.sub(r"at sample (\d+)", lambda m, first=first: f"at line {first + int(m.group(1))}", str(exc), count=1)
            raise InputError(f"{path.name}: {msg}") from exc
        if prev is not None:
            t = np.concatenate([[prev[0]], t])
            acc = np.vstack([prev[1], acc])
            gyr = None if gyr is None else np.vstack([prev[2], gyr])
            lab = None if lab is None else np.concatenate([[prev[3]], lab])
        dt = np.diff(t)
        if (dt <= 0).any():
            i = int(np.flatnonzero(dt <= 0)[0])
            what = "duplicate" if dt[i] == 0 else "decreasing"
            raise InputError(
                f"{path.name}: {what} timestamp at line {line + i - (1 if prev is not None else 0) + 1}; "
                "sort the rows by time and remove duplicates."
            )
        if t0 is None:
            t0 = float(t[0])
            check_acc_unit(acc)
            med = float(np.median(dt))
            gap_limit = max_bridge_s(med)
            uniform = bool(np.all(np.abs(dt - med) <= 1e-3 * med))
            if fs is None:
                fs = float(np.round((len(t) - 1) / (t[-1] - t[0]), 6)) if uniform else float(np.round(1.0 / med, 6))
                resampled = not uniform
            else:
                resampled = True
        if (dt > gap_limit).any():
            i = int(np.flatnonzero(dt > gap_limit)[0])
            raise InputError(
                f"{path.name}: a {dt[i]:.6g} s gap in the timestamps before line {line + i - (1 if prev is not None else 0) + 1} "
                f"(t = {t[i] - t0:.6g} s from the start) is too long to bridge by interpolation (> {gap_limit:.3g} s); "
                "cut the file at its gaps with `gaitml split FILE --out DIR` (in Python: gaitml.io.read_segments)."
            )
        start = len(t) - len(df)  # rows of this block (after the carried row)
        if resampled:
            # grid points covered by this block: t0 + k / fs <= t[-1]
            k_last = int(np.floor((t[-1] - t0) * fs + 1e-9))
            ks = np.arange(k_next, k_last + 1)
            if ks.size:
                grid = t0 + ks / fs
                a = np.column_stack([np.interp(grid, t, acc[:, j]) for j in range(3)])
                g = None if gyr is None else np.column_stack([np.interp(grid, t, gyr[:, j]) for j in range(3)])
                li = None if lab is None else lab[np.clip(np.searchsorted(t, grid, side="right") - 1, 0, len(t) - 1)]
                yield a, g, li, {"sampling_rate_hz": fs, "resampled": True}
                k_next = k_last + 1
        else:
            yield (
                acc[start:],
                (None if gyr is None else gyr[start:]),
                (None if lab is None else lab[start:]),
                {
                    "sampling_rate_hz": fs,
                    "resampled": False,
                },
            )
        prev = (t[-1], acc[-1:], None if gyr is None else gyr[-1:], None if lab is None else lab[-1])
        line += len(df)
    if t0 is None:
        raise InputError(f"{path.name} has a header but no samples; record or export the data again.")


def iter_chunks(
    path: str | os.PathLike,
    *,
    chunk_s: float = 600.0,
    margin_s: float = 30.0,
    align_samples: int = 1,
    format: str | None = None,
    sampling_rate_hz: float | None = None,
    acc_unit: str = "m/s^2",
    gyr_unit: str = "rad/s",
    **read_kwargs,
) -> Iterator[Chunk]:
    """Yield overlapping chunks of a recording file (see the module docstring).

    Parameters
    ----------
    chunk_s : float
        Length of each chunk's core in seconds (rounded to ``align_samples``).
    margin_s : float
        Context on each side of the core, in seconds.
    align_samples : int
        Core boundaries are multiples of this (use the window hop for windowed
        features so the window grid is the same as in a whole-file run).
    """
    p = require_file(path)
    fmt = "columns-csv" if read_kwargs.get("columns") is not None else (format or detect_format(p))
    if fmt != "gaitml-csv":
        rec = read_recording(p, format=fmt, sampling_rate_hz=sampling_rate_hz, acc_unit=acc_unit, gyr_unit=gyr_unit, **read_kwargs)
        yield from _chunks_of(rec, chunk_s, margin_s, align_samples)
        return
    total = estimate_samples(p)
    blocks = _blocks_gaitml_csv(p, sampling_rate_hz, acc_unit, gyr_unit)
    buf_acc: list[np.ndarray] = []
    buf_gyr: list[np.ndarray] = []
    buf_lab: list[np.ndarray] = []
    buf_start = 0  # global index of the first buffered sample
    core_start = 0
    fs = None
    meta_base = {"source": str(p), "format": "gaitml-csv", "id": p.stem, "subject": p.stem, "session": p.stem, "chunked": True}

    def buffered() -> int:
        return sum(len(b) for b in buf_acc)

    def make(core_lo: int, core_hi: int, last: bool) -> Chunk:
        nonlocal buf_acc, buf_gyr, buf_lab, buf_start
        acc = np.vstack(buf_acc)
        gyr = np.vstack(buf_gyr) if buf_gyr else None
        lab = np.concatenate(buf_lab) if buf_lab else None
        hi_local = len(acc) if last else min(len(acc), core_hi + margin - buf_start)
        rec = Recording(
            acc=acc[:hi_local],
            gyr=None if gyr is None else gyr[:hi_local],
            labels=None if lab is None else lab[:hi_local],
            sampling_rate_hz=fs,
            meta={**meta_base, **extra},
            check_units=False,
        )
        ch = Chunk(rec, buf_start, core_lo, core_hi if not last else buf_start + len(acc), total)
        # keep only what the next chunk needs: from (core_hi - margin)
        keep_from = max(0, core_hi - margin - buf_start)
        buf_acc = [acc[keep_from:]]
        buf_gyr = [gyr[keep_from:]] if gyr is not None else []
        buf_lab = [lab[keep_from:]] if lab is not None else []
        buf_start += keep_from
        return ch

    extra: dict = {}
    margin = 0
    core_len = 0
    for a, g, lab, info in blocks:
        if fs is None:
            fs = info["sampling_rate_hz"]
            extra = {"resampled": info["resampled"], "sampling_rate_hz_source": "first block" if info["resampled"] else "timestamps"}
            margin = int(round(margin_s * fs))
            core_len = max(align_samples, int(round(chunk_s * fs / align_samples)) * align_samples)
        buf_acc.append(a)
        if g is not None:
            buf_gyr.append(g)
        if lab is not None:
            buf_lab.append(lab)
        while buf_start + buffered() >= core_start + core_len + margin:
            core_end = core_start + core_len
            yield make(core_start, core_end, last=False)
            core_start = core_end
    if fs is not None and buf_start + buffered() > core_start:
        yield make(core_start, buf_start + buffered(), last=True)


def _chunks_of(rec: Recording, chunk_s: float, margin_s: float, align: int) -> Iterator[Chunk]:
    fs = rec.sampling_rate_hz
    margin = int(round(margin_s * fs))
    core_len = max(align, int(round(chunk_s * fs / align)) * align)
    n = rec.n_samples
    core_start = 0
    while core_start < n:
        core_end = min(n, core_start + core_len)
        lo = max(0, core_start - margin)
        hi = min(n, core_end + margin)
        part = rec.slice(lo, hi)
        yield Chunk(part, lo, core_start, core_end, n)
        core_start = core_end
