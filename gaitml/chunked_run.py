"""Chunked execution: bounded-memory processing of long recordings (hours to days).

Each function reads the input in overlapping chunks (:func:`gaitml.io.chunked.iter_chunks`),
runs the ordinary whole-recording algorithm on each chunk, keeps the results
anchored in the chunk's core and shifts them to global sample indices. Memory
is bounded by the chunk size (default 10 min of samples plus 2 x 30 s margins),
not by the recording length. A progress bar on stderr follows the chunks.

Equivalence with a whole-file run:

- windowed features and model predictions are identical (chunk cores are
  aligned to the window hop and the margins hold a whole window);
- zero-velocity detectors use centred windows shorter than the margin, so the
  per-sample decision is identical;
- step detectors whose state is local (peaks, zero crossings, FSMs that reset
  every step) give the same steps away from chunk boundaries; detectors that
  learn thresholds (``fsm-selflearn``, ``adaptive``) restart learning in every
  chunk's left margin, which the 30 s margin covers.
"""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Callable, Iterator

import numpy as np
import pandas as pd

from gaitml.io.chunked import Chunk, iter_chunks, scan_input

__all__ = ["long_steps", "long_zupts", "long_features", "long_predict", "progress_chunks"]

DEFAULT_CHUNK_S = 600.0
DEFAULT_MARGIN_S = 30.0


def progress_chunks(chunks: Iterator[Chunk], desc: str, *, enabled: bool = True) -> Iterator[Chunk]:
    """Wrap a chunk iterator in a tqdm progress bar (samples) on stderr, when stderr is a terminal."""
    if not enabled:
        yield from chunks
        return
    from tqdm import tqdm

    bar = None
    try:
        for ch in chunks:
            if bar is None:
                # disable=None: no bar when stderr is not a terminal (a log file, a pipe), so that
                # a refusal stays one line there
                bar = tqdm(
                    total=ch.total_hint or None, unit="samples", unit_scale=True, desc=desc, file=sys.stderr, leave=False, disable=None
                )
            bar.update(ch.core_end - ch.core_start)
            yield ch
    finally:
        if bar is not None:
            bar.close()


def _shift_steps(table: pd.DataFrame, offset: int, fs: float) -> pd.DataFrame:
    t = table.copy()
    for c in ("start", "peak", "end"):
        t[c] = t[c].astype(np.int64) + offset
    for c, s in (("t_start_s", "start"), ("t_peak_s", "peak"), ("t_end_s", "end")):
        t[c] = t[s] / fs
    return t


def long_steps(
    path: str | os.PathLike,
    detector: str = "single-peak",
    *,
    chunk_s: float = DEFAULT_CHUNK_S,
    margin_s: float = DEFAULT_MARGIN_S,
    progress: bool = True,
    detector_params: dict | None = None,
    count_also: str | None = None,
    **read_kwargs,
) -> pd.DataFrame:
    """Detect steps in a long recording chunk by chunk; returns one global step table.

    ``count_also``: a second detector run on the same chunks (e.g. ``adaptive``, for the
    count cross-check of :mod:`gaitml.steps.crosscheck`). Only its step count is kept, in
    ``attrs["count_also"] = {"detector": name, "n_steps": total}``, counted like the main
    detector's steps (those anchored in each chunk's core), so memory stays bounded by the chunk.
    """
    from gaitml.steps import get_detector

    parts = []
    fs = None
    attrs: dict = {}
    also_counts: list[int] = []
    for ch in progress_chunks(
        iter_chunks(path, chunk_s=chunk_s, margin_s=margin_s, **read_kwargs), f"steps ({detector})", enabled=progress
    ):
        fs = ch.recording.sampling_rate_hz
        det = get_detector(detector, **(detector_params or {})).detect(ch.recording)
        table = det.steps_
        attrs = dict(table.attrs)
        parts.append(_shift_steps(table[_in_core(table, ch)], ch.offset, fs))
        if count_also is not None:
            also_counts.append(int(_in_core(get_detector(count_also).detect(ch.recording).steps_, ch).sum()))
    out = pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()
    out.attrs.update(attrs)
    out.attrs["chunked"] = {"chunk_s": chunk_s, "margin_s": margin_s}
    if count_also is not None:
        out.attrs["count_also"] = {"detector": count_also, "n_steps": int(sum(also_counts))}
    return out


def _in_core(table: pd.DataFrame, ch: Chunk) -> np.ndarray:
    """Which steps of a chunk's step table are anchored in the chunk's core (the step's end for
    detectors whose event is the end, else its peak): the steps :func:`long_steps` keeps."""
    if not len(table):
        return np.zeros(0, dtype=bool)
    anchor = "end" if table.attrs.get("event") == "t_end_s" else "peak"
    idx = table[anchor].to_numpy(dtype=np.int64) + ch.offset
    return (idx >= ch.core_start) & (idx < ch.core_end)


def long_zupts(
    path: str | os.PathLike,
    detector: str = "pseudo-std",
    *,
    chunk_s: float = DEFAULT_CHUNK_S,
    margin_s: float = DEFAULT_MARGIN_S,
    progress: bool = True,
    detector_params: dict | None = None,
    **read_kwargs,
) -> tuple[np.ndarray, pd.DataFrame, float]:
    """Zero-velocity detection chunk by chunk: ``(per_sample_mask, intervals, fs)``.

    The per-sample mask is a compact boolean array (1 byte per sample: 86 MB
    for a day at 1 kHz, 8.6 MB at 100 Hz).
    """
    from gaitml.zupt import get_detector, intervals_table

    masks = []
    fs = None
    for ch in progress_chunks(iter_chunks(path, chunk_s=chunk_s, margin_s=margin_s, **read_kwargs), f"zupt ({detector})", enabled=progress):
        fs = ch.recording.sampling_rate_hz
        det = get_detector(detector, **(detector_params or {})).detect(ch.recording)
        m = np.asarray(det.per_sample_zupts_, dtype=bool)
        masks.append(m[ch.core_start - ch.offset : ch.core_end - ch.offset])
    mask = np.concatenate(masks) if masks else np.zeros(0, dtype=bool)
    return mask, intervals_table(mask, fs), fs


def _window_chunks(
    path,
    length_s,
    overlap,
    chunk_s,
    progress,
    desc,
    *,
    extra_windows: int = 0,
    phase_step: int = 1,
    window_grid: int = 1,
    **read_kwargs,
) -> Iterator[tuple[Chunk, int, int]]:
    """Chunks whose cores and margins are multiples of ``window_grid`` window hops (and of ``phase_step``).

    ``extra_windows`` more hops of context before each core: the windows a per-window
    statistic over the last windows needs (the domain record's span median).
    ``phase_step``: chunk offsets are multiples of it, so a computation that keeps every
    ``phase_step``-th sample of a chunk keeps the same samples as on the whole file.
    ``window_grid``: a chunk's window i is window ``i`` mod ``window_grid`` of the whole
    file too, so a computation on every ``window_grid``-th window (the domain check's
    dynamics) uses the same windows as on the whole file.
    """
    from gaitml.signal import window_params

    # the hop depends on the rate, known after the first block: peek at it
    fs_probe = read_kwargs.get("sampling_rate_hz")
    if fs_probe is None:
        if read_kwargs.get("scan") is None:
            read_kwargs["scan"] = scan_input(path, **read_kwargs)
        if read_kwargs["scan"] is not None:
            fs_probe = read_kwargs["scan"].sampling_rate_hz
        else:
            first = next(iter_chunks(path, chunk_s=1.0, margin_s=0.0, **read_kwargs))
            fs_probe = first.recording.sampling_rate_hz
    length, hop = window_params(length_s, overlap, fs_probe)
    align = math.lcm(hop * max(1, int(window_grid)), max(1, int(phase_step)))
    margin_samples = math.ceil((math.ceil(length / hop) + max(0, int(extra_windows))) * hop / align) * align
    chunks = iter_chunks(
        path,
        chunk_s=chunk_s,
        margin_s=margin_samples / fs_probe,
        align_samples=align,
        **read_kwargs,
    )
    for ch in progress_chunks(chunks, desc, enabled=progress):
        yield ch, length, hop


def long_features(
    path: str | os.PathLike,
    *,
    length_s: float = 1.5,
    overlap: float = 0.5,
    subset: str = "all52",
    chunk_s: float = DEFAULT_CHUNK_S,
    progress: bool = True,
    on_block: Callable[[pd.DataFrame], None] | None = None,
    frame: str = "phone",
    **read_kwargs,
) -> pd.DataFrame | None:
    """Windowed features of a long recording, identical to a whole-file run.

    ``frame`` is the feature frame (:func:`gaitml.features.extract_features`); each
    window's gravity frame depends on its own samples, so chunking does not change it.

    With ``on_block`` every chunk's rows are handed to the callback (e.g. to
    append them to a file) and nothing is accumulated; otherwise the full table
    is returned.
    """
    from gaitml.features import extract_features, make_windows

    parts = []
    for ch, _length, _hop in _window_chunks(path, length_s, overlap, chunk_s, progress, f"features ({subset})", **read_kwargs):
        rec = ch.recording
        if rec.n_samples < _length and ch.offset > 0:  # a short tail; a short first chunk is a short file: refused as one
            continue
        wins = make_windows(rec, length_s, overlap, min_label_fraction=0.0)
        gstart = wins["start"].to_numpy() + ch.offset
        keep = (gstart >= ch.core_start) & (gstart < ch.core_end)
        if not keep.any():
            continue
        wins = wins[keep].reset_index(drop=True)
        feats = extract_features(rec, wins, subset=subset, length_s=length_s, overlap=overlap, frame=frame)
        block = _globalise_windows(wins, ch.offset, rec.sampling_rate_hz)
        block = pd.concat([block, feats.reset_index(drop=True)[[c for c in feats.columns if c not in block.columns]]], axis=1)
        if on_block is not None:
            on_block(block)
        else:
            parts.append(block)
    if on_block is not None:
        return None
    return pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()


def _globalise_windows(wins: pd.DataFrame, offset: int, fs: float) -> pd.DataFrame:
    w = wins.copy()
    w["start"] = w["start"].astype(np.int64) + offset
    w["end"] = w["end"].astype(np.int64) + offset
    w["t_start_s"] = w["start"] / fs
    w["t_end_s"] = w["end"] / fs
    return w


def long_predict(
    model,
    path: str | os.PathLike,
    *,
    correction: bool = True,
    chunk_s: float = DEFAULT_CHUNK_S,
    progress: bool = True,
    **read_kwargs,
) -> pd.DataFrame:
    """Per-window motion modes of a long recording with a saved model.

    Features are computed chunk by chunk; the adjacent-window correction runs
    over the whole label sequence afterwards (it needs only the two previous
    windows, and the sequence of labels is small: 115,200 windows per day at
    1.5 s / 50 %).
    """
    from gaitml.models import predict_recording

    parts = []
    if read_kwargs.get("sampling_rate_hz") is None:
        # read at the model's rate, as predict_recording resamples a whole recording to it
        read_kwargs["sampling_rate_hz"] = model.sampling_rate_hz
        scan = read_kwargs.pop("scan", None)
        if scan is not None:
            same = abs(scan.sampling_rate_hz - model.sampling_rate_hz) <= 1e-9 * model.sampling_rate_hz
            read_kwargs["scan"] = scan if same else scan.at_rate(model.sampling_rate_hz)
    # a domain record with an orientation-dynamics part decides on the median over the last windows of the
    # dynamics of every `every`-th window (which keep every step-th sample): more context before each core,
    # offsets on that sample grid and on that window grid (a chunk's first window is a computed one)
    dom = getattr(model, "domain", None)
    extra, phase, grid = (0, 1, 1) if dom is None else dom.chunk_context(float(read_kwargs["sampling_rate_hz"]))
    chunks = _window_chunks(
        path,
        model.length_s,
        model.overlap,
        chunk_s,
        progress,
        "predict",
        extra_windows=extra,
        phase_step=phase,
        window_grid=grid,
        **read_kwargs,
    )
    for ch, _length, _hop in chunks:
        rec = ch.recording
        if rec.n_samples < _length and ch.offset > 0:  # a short tail; a short first chunk is a short file: refused as one
            continue
        table = predict_recording(model, rec, correction=False)
        gstart = table["start"].to_numpy() + ch.offset
        keep = (gstart >= ch.core_start) & (gstart < ch.core_end)
        parts.append(_globalise_windows(table[keep].reset_index(drop=True), ch.offset, rec.sampling_rate_hz))
    out = pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()
    if correction and len(out):
        from gaitml.models._predict import STILL
        from gaitml.postprocess import adjacent_window_correction

        corrected = np.asarray(adjacent_window_correction(out["mode_raw"].to_numpy())).astype(str)
        out["mode"] = np.where(out["still"].to_numpy(dtype=bool), STILL, corrected)
    return out
