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

Chunking is only how the ordinary reading walks a long file, never a second
reader. :func:`scan_gaitml_csv` is a first streaming pass over the whole file
with the small-file code (:func:`gaitml.io.gaitml_csv.parse_block` for the
columns, numbers, NaN rows and labels; :class:`gaitml.recording.ranges.RangeTally`
for the sensor ranges; the unit judgement on the whole file's magnitudes;
:func:`gaitml.recording.timestamps.judge_timestamps` on the whole file's
timestamps for the rate, quantised clocks, rate changes and gaps). The second
pass resamples the blocks with :class:`gaitml.recording.resampling.UniformResampler`,
the resampler of a file read whole, carrying its state across blocks. So a long
file is refused, warned about and resampled exactly as it would be if read whole.
Other formats are read whole, then sliced.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gaitml.consts import ACC_LIMIT_MS2
from gaitml.errors import InputError
from gaitml.io._common import require_file
from gaitml.io._detect import detect_format, read_recording
from gaitml.io._hold import hold_pattern
from gaitml.io.gaitml_csv import Block, Columns, _read_table, check_columns, parse_block
from gaitml.recording import Recording
from gaitml.recording.container import finish_resampling_meta
from gaitml.recording.ranges import RangeTally
from gaitml.recording.resampling import UniformResampler
from gaitml.recording.timestamps import check_increasing, judge_timestamps
from gaitml.recording.units import acc_magnitude, check_unit_magnitudes, convert_units, gyr_magnitude, note_conversions

__all__ = ["Chunk", "Scan", "iter_chunks", "recording_chunks", "scan_gaitml_csv", "scan_input", "estimate_samples", "LARGE_INPUT_SAMPLES"]

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


@dataclass(frozen=True)
class Scan:
    """What the first pass over a long gaitml-csv found: the grid, the channels and the reading's ``meta``.

    ``meta`` is what a file read whole would carry (``original_rate_hz``,
    ``rate_changes``, ``resampled``, ``resample_method``, ``converted``,
    ``warnings``...).
    """

    path: Path
    sampling_rate_hz: float
    resampled: bool
    max_rate_hz: float
    t0: float
    t_end: float
    n_rows: int
    has_gyr: bool
    has_labels: bool
    meta: dict
    acc_unit: str = "m/s^2"
    gyr_unit: str = "rad/s"

    @property
    def n_samples(self) -> int:
        """Samples of the uniform recording."""
        if not self.resampled:
            return self.n_rows
        return int(np.floor((self.t_end - self.t0) * self.sampling_rate_hz + 1e-9)) + 1

    @property
    def warnings(self) -> list[str]:
        return list(self.meta.get("warnings", []))

    def at_rate(self, sampling_rate_hz: float) -> Scan:
        """The same file read at ``sampling_rate_hz`` (resampled), without reading it again.

        What a requested rate changes in :func:`~gaitml.recording.timestamps.judge_timestamps`:
        the grid, ``resampled`` and the resampling method (the file's own rate was judged
        already, and passed :func:`~gaitml.recording.timestamps.check_rate`).
        """
        from gaitml.recording.timestamps import check_rate, rate_change_warning

        fs = float(sampling_rate_hz)
        check_rate(fs, what="the requested sampling rate")
        meta = {k: v for k, v in self.meta.items() if k not in ("resampled", "resample_method", "warnings")}
        plan = {"fs": fs, "resampled": True, "max_rate_hz": self.max_rate_hz, "warnings": []}
        old = [w for w in self.meta.get("warnings", []) if not w.startswith("the sampling rate changes mid-file")]
        if self.meta.get("rate_changes"):
            plan["warnings"] = [rate_change_warning(self.meta["rate_changes"], self.meta["original_rate_hz"], fs)]
        if old:
            meta["warnings"] = old
        finish_resampling_meta(meta, plan)
        return dataclasses.replace(self, sampling_rate_hz=fs, resampled=True, meta=meta)


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


def _parsed_blocks(p: Path, rows: int) -> Iterator[tuple[Block, int, Columns]]:
    """``(block, offset, columns)`` for consecutive blocks of ``rows`` rows, parsed by the small-file code."""
    cols = None
    offset = 0
    for df in _read_table(p, chunksize=rows):
        if cols is None:
            cols = check_columns(p, list(df.columns))
        if not len(df):
            continue
        yield parse_block(p, df, cols, first_line=offset + 2), offset, cols
        offset += len(df)
    if cols is None:
        raise InputError(f"the file is empty: {p}; record or export the data again.")


class _Growing:
    """A 1-D array filled block by block (capacity grows by half when full): no list of blocks to concatenate."""

    def __init__(self, capacity: int, dtype):
        self.buf = np.empty(capacity, dtype=dtype)
        self.n = 0

    def append(self, x: np.ndarray) -> None:
        if self.n + len(x) > len(self.buf):
            grown = np.empty(max(self.n + len(x), int(len(self.buf) * 1.5)), dtype=self.buf.dtype)
            grown[: self.n] = self.buf[: self.n]
            self.buf = grown
        self.buf[self.n : self.n + len(x)] = x
        self.n += len(x)

    def values(self) -> np.ndarray:
        return self.buf[: self.n]


def _repeats(x: np.ndarray, previous: np.ndarray | None) -> np.ndarray:
    """Whether each row of ``x`` equals the row before it (the previous block's last row for the first)."""
    out = np.zeros(len(x), dtype=bool)
    if len(x) > 1:
        out[1:] = np.all(x[1:] == x[:-1], axis=1)
    if len(x) and previous is not None:
        out[0] = bool(np.all(x[0] == previous))
    return out


def scan_gaitml_csv(
    path: str | os.PathLike,
    *,
    sampling_rate_hz: float | None = None,
    acc_unit: str = "m/s^2",
    gyr_unit: str = "rad/s",
    rows_per_read: int | None = None,
) -> Scan:
    """The first, streaming pass over a long gaitml-csv: every check of a file read whole (see the module docstring).

    Memory: the timestamps and the per-sample |acc| and |gyr| of the whole file
    (24 bytes per sample: 0.2 GB for a day at 100 Hz), never the samples.

    Raises
    ------
    InputError
        What :func:`gaitml.io.read_recording` raises on the same file.
    """
    p = require_file(path)
    rows = int(rows_per_read or _ROWS_PER_READ)
    conv_meta: dict = {}
    note_conversions(conv_meta, acc_unit, gyr_unit == "deg/s")
    tally = RangeTally(conv_meta)
    cap = max(1024, int(estimate_samples(p) * 1.05))
    ts, amag, gmag = _Growing(cap, np.float64), _Growing(cap, np.float32), _Growing(cap, np.float32)
    # repeat masks (row equal to the previous row on every axis) for the sample-and-hold check of gaitml.io._hold
    same_acc, same_gyr = _Growing(cap, np.bool_), _Growing(cap, np.bool_)
    last_acc = last_gyr = None
    nan = Block(np.zeros(0), np.zeros((0, 3)), None, None)
    has_gyr = has_labels = False
    cols_ignored: list[str] = []
    n = 0
    acc_sum, acc_count = np.zeros(3), 0
    for block, offset, cols in _parsed_blocks(p, rows):
        has_gyr, has_labels, cols_ignored = cols.has_gyr, cols.has_labels, cols.ignored
        if block.nan_count:
            nan.nan_count += block.nan_count
            nan.nan_first_line = nan.nan_first_line or block.nan_first_line
        same_acc.append(_repeats(block.acc, last_acc))
        last_acc = block.acc[-1].copy() if len(block.acc) else last_acc
        if block.gyr is not None:
            same_gyr.append(_repeats(block.gyr, last_gyr))
            last_gyr = block.gyr[-1].copy() if len(block.gyr) else last_gyr
        acc, gyr = convert_units(block.acc, block.gyr, acc_unit, gyr_unit)
        ts.append(block.t)
        amag.append(acc_magnitude(acc))
        fin = np.isfinite(acc).all(axis=1)
        acc_sum += np.clip(acc[fin], -ACC_LIMIT_MS2, ACC_LIMIT_MS2).sum(axis=0)
        acc_count += int(fin.sum())
        if gyr is not None:
            gmag.append(gyr_magnitude(gyr))
        tally.add(acc, gyr, offset)
        n = offset + len(block.t)
    if n == 0:
        raise InputError(f"{p.name} has a header but no samples; record or export the data again.")
    nan.raise_nan(p)
    t = ts.values()
    if len(t) < 2:
        raise InputError(f"need at least 2 timestamped samples to find the sampling rate, got {len(t)}; use a longer recording.")
    check_increasing(t)
    for what, same in (("accelerometer", same_acc), ("gyroscope", same_gyr if has_gyr else None)):
        info = None if same is None or (np.diff(t) <= 0).any() else hold_pattern(t, same.values(), what)
        if info:  # a file read whole is re-timed at the updates; the chunked road keeps the row times: refuse, with the rates
            raise InputError(
                f"{p.name}: {info['warning'].replace('; read at', '; it would be read at')}; a file of {len(t)} rows is read in chunks, "
                f"which keep the row times: cut it into files of fewer than {LARGE_INPUT_SAMPLES} rows, or export each sensor at its own rate."
            )
    del same_acc, same_gyr
    meta = {"source": str(p), "format": "gaitml-csv", "id": p.stem, "subject": p.stem, "session": p.stem, "chunked": True}
    if cols_ignored:
        meta["ignored_columns"] = cols_ignored
    note_conversions(meta, acc_unit, has_gyr and gyr_unit == "deg/s")
    plan = judge_timestamps(t, sampling_rate_hz=sampling_rate_hz)
    mean_norm = float(np.linalg.norm(acc_sum / acc_count)) if acc_count else None
    warning = check_unit_magnitudes(amag.values(), gmag.values() if has_gyr else None, meta, acc_mean_norm=mean_norm)
    del amag, gmag
    tally.raise_first()
    meta.update(plan["meta"])
    finish_resampling_meta(meta, plan)
    if warning and warning not in meta.get("warnings", []):
        meta["warnings"] = [*meta.get("warnings", []), warning]
    return Scan(
        path=p,
        sampling_rate_hz=plan["fs"],
        resampled=plan["resampled"],
        max_rate_hz=plan["max_rate_hz"],
        t0=float(t[0]),
        t_end=float(t[-1]),
        n_rows=int(len(t)),
        has_gyr=has_gyr,
        has_labels=has_labels,
        meta=meta,
        acc_unit=acc_unit,
        gyr_unit=gyr_unit,
    )


def scan_input(path: str | os.PathLike, *, format: str | None = None, columns=None, **read_kwargs) -> Scan | None:
    """:func:`scan_gaitml_csv` for a gaitml-csv input; None for other formats (they are read whole)."""
    p = require_file(path)
    fmt = "columns-csv" if columns is not None else (format or detect_format(p))
    if fmt != "gaitml-csv":
        return None
    keep = {k: read_kwargs[k] for k in ("sampling_rate_hz", "acc_unit", "gyr_unit") if read_kwargs.get(k) is not None}
    return scan_gaitml_csv(p, **keep)


def _blocks_gaitml_csv(scan: Scan, rows_per_read: int | None = None):
    """Second pass: yield ``(acc, gyr, labels)`` blocks on the uniform grid the scan chose."""
    rs = UniformResampler(scan.t0, scan.t_end, scan.sampling_rate_hz, max_rate_hz=scan.max_rate_hz) if scan.resampled else None
    for block, _offset, _cols in _parsed_blocks(scan.path, int(rows_per_read or _ROWS_PER_READ)):
        acc, gyr = convert_units(block.acc, block.gyr, scan.acc_unit, scan.gyr_unit)
        x = acc if gyr is None else np.hstack([acc, gyr])
        if rs is None:
            out, lab = x, block.labels
        else:
            out, lab = rs.push(block.t, x, block.labels)
        if len(out):
            yield out[:, :3], (out[:, 3:6] if gyr is not None else None), lab
    if rs is not None:
        out, lab = rs.flush()
        if len(out):
            yield out[:, :3], (out[:, 3:6] if scan.has_gyr else None), lab


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
    scan: Scan | None = None,
    recording: Recording | None = None,
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
    scan : Scan, optional
        The first pass over the file (:func:`scan_gaitml_csv`), when the caller
        already made it (to print its warnings); made here otherwise.
    recording : Recording, optional
        ``path`` already read whole (a format other than gaitml-csv), when the caller
        already read it (to print its warnings): sliced (:func:`recording_chunks`)
        instead of reading ``path`` again.
    """
    p = require_file(path)
    if recording is not None:
        yield from recording_chunks(recording, chunk_s=chunk_s, margin_s=margin_s, align_samples=align_samples)
        return
    fmt = "columns-csv" if read_kwargs.get("columns") is not None else (format or detect_format(p))
    if fmt != "gaitml-csv":
        rec = read_recording(p, format=fmt, sampling_rate_hz=sampling_rate_hz, acc_unit=acc_unit, gyr_unit=gyr_unit, **read_kwargs)
        yield from recording_chunks(rec, chunk_s=chunk_s, margin_s=margin_s, align_samples=align_samples)
        return
    if scan is None:
        scan = scan_gaitml_csv(p, sampling_rate_hz=sampling_rate_hz, acc_unit=acc_unit, gyr_unit=gyr_unit)
    total = scan.n_samples
    blocks = _blocks_gaitml_csv(scan)
    buf_acc: list[np.ndarray] = []
    buf_gyr: list[np.ndarray] = []
    buf_lab: list[np.ndarray] = []
    buf_start = 0  # global index of the first buffered sample
    core_start = 0
    fs = scan.sampling_rate_hz
    meta_base = dict(scan.meta)

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
            meta=meta_base,
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

    margin = int(round(margin_s * fs))
    core_len = max(align_samples, int(round(chunk_s * fs / align_samples)) * align_samples)
    for a, g, lab in blocks:
        buf_acc.append(a)
        if g is not None:
            buf_gyr.append(g)
        if lab is not None:
            buf_lab.append(lab)
        while buf_start + buffered() >= core_start + core_len + margin:
            core_end = core_start + core_len
            yield make(core_start, core_end, last=False)
            core_start = core_end
    if buf_start + buffered() > core_start:
        yield make(core_start, buf_start + buffered(), last=True)


def recording_chunks(rec: Recording, *, chunk_s: float = 600.0, margin_s: float = 30.0, align_samples: int = 1) -> Iterator[Chunk]:
    """The chunks of a recording already in memory (a format read whole), cut as :func:`iter_chunks` cuts a file."""
    align = align_samples
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
