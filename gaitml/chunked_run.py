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
  learn thresholds (``fsm-selflearn``) restart learning in every chunk's left
  margin, which the 30 s margin covers; ``adaptive``'s chunks start on its cadence
  grid (:func:`long_steps`), so its per-window cadence, and the step period it places
  the steps with, are the whole file's; its bout rules (a bout's weak
  edges judged against the bout, its size, a short bout's regularity) see only
  the part of a bout inside the chunk, so on a walk longer than the margin a few
  steps of a bout can differ from a whole-file run's (at most one chunk's bouts
  per chunk edge; nothing else in it depends on the whole recording);
- the gait-evidence test of the steps (``adaptive``'s own, or ``gait_check`` of :func:`long_steps`)
  runs on each chunk's steps, as on a whole recording, and its account is summed over the steps
  anchored in the cores: equal to a whole-file run's for bouts shorter than the margin. The
  test's opt-in short-bout rule (``confirm_bout_steps`` of
  :func:`~gaitml.steps._gait_evidence.gait_check`) is Python-only, applied to a step table of a
  recording read whole: no chunked run applies it (:func:`long_steps` refuses its settings);
- dead reckoning (:func:`long_pdr`) starts from the gyroscope bias of the whole file's still
  stretches (a first pass, :func:`long_still_bias`), carries the attitude across chunks and
  corrects the heading over all steps: the whole-file run's trajectory (within a millimetre)
  wherever the step detector gives the same steps.
"""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np
import pandas as pd
from sklearn.base import clone

from gaitml.consts import DEFAULT_STEP_DETECTOR
from gaitml.io.chunked import Chunk, iter_chunks, recording_chunks, scan_input

__all__ = ["long_steps", "long_zupts", "long_features", "long_predict", "long_pdr", "long_still_bias", "progress_chunks"]

DEFAULT_CHUNK_S = 600.0
DEFAULT_MARGIN_S = 30.0
#: the settings of the gait check's opt-in short-bout rule, Python-only (not applied in chunked runs)
SHORT_BOUT_SETTINGS = ("confirm_bout_steps", "context_s", "context_steps")


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


def _core_steps(
    rec, ch: Chunk, detector: str, detector_params: dict | None, gait_check: bool | None
) -> tuple[pd.DataFrame, dict | None, object]:
    """A chunk's steps anchored in its core (chunk-local indices), with the gait-evidence test its
    record of the core's steps (:func:`_gait_account`; None without the test), and the fitted
    detector (for its per-window ``cadence_``, :func:`_core_cadence`).

    The test runs on the chunk's whole step table, as on a whole recording: a detector with a
    ``gait_check`` parameter (``adaptive``) runs its own (its stage 5b adds steps after it; the
    account reads ``unchecked_steps_``, the table the check read); other detectors'
    steps pass :func:`~gaitml.steps._gait_evidence.gait_check_recording` (tested at ``adaptive``'s
    cadence, as ``gaitml steps --gait-check`` does). ``gait_check`` None: the detector's own default
    (on for ``adaptive``, off for the others).
    """
    from gaitml.steps import get_detector
    from gaitml.steps._gait_evidence import gait_check_recording

    params = dict(detector_params or {})
    det = get_detector(detector, **params)
    own = "gait_check" in det.get_params()
    gait = (bool(det.get_params()["gait_check"]) if own else False) if gait_check is None else bool(gait_check)
    if own:
        # adaptive runs its own check (its stage 5b adds steps after it); the account reads the table the check read
        det.set_params(gait_check=gait).detect(rec)
        checked = det.steps_
        raw = det.unchecked_steps_ if gait else checked
    else:
        raw = det.detect(rec).steps_
        checked = gait_check_recording(raw, rec) if gait else raw
    account = _gait_account(raw, checked, rec, ch) if gait else None
    core = checked[_in_core(checked, ch)].reset_index(drop=True)
    core.attrs = {k: v for k, v in checked.attrs.items() if k != "gait_check"}
    bouts = getattr(det, "octave_bouts_", None)
    if bouts is not None and "octave" in core.attrs:
        # adaptive's stage 5a: the decisions on the bouts that start in the core (each bout of the file once)
        from gaitml.steps.adaptive import octave_counts

        first = bouts["first_peak"].to_numpy(np.int64) + ch.offset
        core.attrs["octave"] = octave_counts(bouts["octave"].to_numpy()[(first >= ch.core_start) & (first < ch.core_end)])
    rhythm = getattr(det, "rhythm_peaks_", None)
    if rhythm is not None and "rhythm" in core.attrs:
        # adaptive's periodicity-floor relief: the peaks it judged in the core (each peak of the file once)
        at = rhythm["peak"].to_numpy(np.int64) + ch.offset
        inside = (at >= ch.core_start) & (at < ch.core_end)
        relieved = rhythm["relieved"].to_numpy(bool)
        core.attrs["rhythm"] = {**core.attrs["rhythm"], "candidates": int(inside.sum()), "peaks": int((inside & relieved).sum())}
    return core, account, det


def _sum_rhythm(parts: list[dict]) -> dict:
    """adaptive's periodicity-floor relief account of the whole file (``attrs['rhythm']``) from the chunks' core counts."""
    return {"ran": any(bool(p["ran"]) for p in parts), **{k: int(sum(p[k] for p in parts)) for k in ("candidates", "peaks")}}


def _sum_octave(parts: list[dict]) -> dict:
    """adaptive's stage 5a decisions of the whole file (``attrs['octave']``) from the chunks' core counts."""
    return {k: int(sum(p[k] for p in parts)) for k in parts[0]}


def _core_cadence(det, ch: Chunk, fs: float) -> pd.DataFrame | None:
    """The detector's per-window cadence (``cadence_``, ``adaptive``) of the windows centred in the
    chunk's core, at whole-file times; None for a detector without one.

    The chunk must start at a multiple of the detector's cadence hop in samples
    (:meth:`~gaitml.steps.adaptive.AdaptiveStepDetector.cadence_hop_samples`; :func:`long_steps` cuts
    its chunks so): its windows are then the whole-file run's windows
    (centres ``k * hop + window / 2``). A window belongs to the chunk whose core holds its centre
    sample, so every window of the file is given once, at its global centre sample over the rate, as
    a whole-file run gives it.
    """
    cad = getattr(det, "cadence_", None)
    if cad is None:
        return None
    centre = np.rint(cad["t_s"].to_numpy(dtype=float) * fs).astype(np.int64) + ch.offset
    keep = (centre >= ch.core_start) & (centre < ch.core_end)
    out = cad[keep].reset_index(drop=True)
    out["t_s"] = centre[keep] / fs
    return out


def _gait_account(raw: pd.DataFrame, checked: pd.DataFrame, rec, ch: Chunk) -> dict:
    """The gait-evidence record of one chunk: the steps of ``raw`` anchored in its core, at whole-file
    times (``t_s``, the step event), with their ``period_s`` (None when the detector gives none) and
    whether the test kept them (``kept``: in ``checked``). :func:`_sum_accounts` groups the records of
    all chunks into the whole file's bouts.
    """
    account = {"tested": rec.gyr is not None, "t_s": np.zeros(0), "period_s": np.zeros(0), "kept": np.zeros(0, dtype=bool)}
    if not len(raw):
        return account
    anchor = "end" if raw.attrs.get("event") == "t_end_s" else "peak"
    event = raw.attrs.get("event", "t_peak_s")
    kept = np.isin(raw[anchor].to_numpy(np.int64), checked[anchor].to_numpy(np.int64))
    core = _in_core(raw, ch)
    account["t_s"] = raw[event].to_numpy(dtype=float)[core] + ch.offset / rec.sampling_rate_hz
    account["period_s"] = raw["period_s"].to_numpy(dtype=float)[core] if "period_s" in raw.columns else None
    account["kept"] = kept[core]
    return account


def _sum_accounts(accounts: list[dict]) -> dict:
    """The whole file's gait-evidence account (the keys of :func:`~gaitml.steps._gait_evidence.gait_check`'s)
    from the chunks' records (:func:`_gait_account`).

    The core steps of all chunks (every step of the file once) are grouped into bouts as
    :func:`~gaitml.steps._gait_evidence.step_bouts` groups a whole recording's steps, so a bout that runs
    over a chunk edge is one bout. A bout is rejected when the test left out any of its steps: on a
    whole file the test keeps or leaves out a bout whole, and a bout longer than a chunk margin, tested
    on each chunk's part, can be kept in one chunk and left out in the next.
    """
    from gaitml.steps._gait_evidence import step_bouts

    t = np.concatenate([a["t_s"] for a in accounts]) if accounts else np.zeros(0)
    kept = np.concatenate([a["kept"] for a in accounts]) if accounts else np.zeros(0, dtype=bool)
    periods = [a["period_s"] for a in accounts]
    period = None if any(p is None for p in periods) or not periods else np.concatenate(periods)
    order = np.argsort(t, kind="stable")
    t, kept = t[order], kept[order]
    period = None if period is None else period[order]
    bout = step_bouts(t, period)
    return {
        "tested": all(a["tested"] for a in accounts) if accounts else True,
        "n_bouts": int(bout[-1]) + 1 if len(bout) else 0,
        "n_bouts_rejected": int(np.unique(bout[~kept]).size),
        "n_steps_rejected": int((~kept).sum()),
        "rejected_t_s": t[~kept].tolist(),
    }


def long_steps(
    path: str | os.PathLike,
    detector: str = DEFAULT_STEP_DETECTOR,
    *,
    chunk_s: float | None = None,
    margin_s: float | None = None,
    progress: bool = True,
    detector_params: dict | None = None,
    count_also: str | None = None,
    gait_check: bool | None = None,
    keep_cadence: bool = False,
    **read_kwargs,
) -> pd.DataFrame:
    """Detect steps in a long recording chunk by chunk; returns one global step table.

    ``keep_cadence``: keep the detector's per-window cadence (``cadence_`` of ``adaptive``; nothing
    for a detector without one) of the windows centred in each chunk's core, at whole-file times
    (:func:`_core_cadence`; for such a detector the chunk cores and margins are multiples of its
    cadence hop in samples, the margin rounded up, so that each chunk's windows are the whole file's), in ``attrs["cadence"]`` as a dict of column name to list (one entry per
    window; a dict of lists, not a table, so that the step table's attrs stay comparable).

    ``count_also``: a second detector run on the same chunks (e.g. ``adaptive``, for the
    count cross-check of :mod:`gaitml.steps.crosscheck`). Only its step count is kept, in
    ``attrs["count_also"] = {"detector": name, "n_steps": total}``, counted like the main
    detector's steps (those anchored in each chunk's core), so memory stays bounded by the chunk.

    ``adaptive``'s opt-in stage 5a (``detector_params``): ``attrs["octave"]`` counts its decisions on
    the bouts whose first peak lies in a chunk's core, summed over the chunks (each bout of the file
    once; a bout over a chunk edge is decided on the part of it the chunk reads).

    ``gait_check``: leave out bouts of steps without gait evidence
    (:mod:`gaitml.steps._gait_evidence`), per chunk before the core's steps are kept (see
    :func:`_core_steps`; None: the detector's default, on for ``adaptive``). The account of the
    whole file, summed over the chunks' core steps, is in ``attrs["gait_check"]`` (the keys of
    :func:`~gaitml.steps._gait_evidence.gait_check`'s). A bout within a chunk margin of a chunk edge
    is tested on the same steps as on the whole file; a bout longer than the margin is tested on
    each chunk's part of it. That part spans at least one margin, so it holds the
    :data:`~gaitml.steps._gait_evidence.LONG_BOUT_STEPS` steps that make a bout gait whatever its
    rotation when the cadence is at least ``LONG_BOUT_STEPS / margin_s`` (1 step/s with the 30 s
    margin); a slower bout that turns with its steps can lose the few core steps near a chunk edge
    that a whole-file run keeps. The test's opt-in short-bout rule (``confirm_bout_steps``,
    ``context_s``, ``context_steps`` of :func:`~gaitml.steps._gait_evidence.gait_check`) is
    Python-only, for a recording read whole: it is not available here, and ``detector_params``
    naming one of its settings is refused with an :class:`~gaitml.errors.InputError`.
    Bouts are counted (``n_bouts``, ``n_bouts_rejected``) over the whole file's core steps
    (:func:`_sum_accounts`): a bout over a chunk edge is one bout, rejected when any chunk left out
    any of its steps.

    ``chunk_s`` / ``margin_s``: the chunk core and margin lengths (default
    :data:`DEFAULT_CHUNK_S`, :data:`DEFAULT_MARGIN_S`).
    """
    from gaitml.errors import InputError
    from gaitml.steps import get_detector

    short_bout = sorted(set(detector_params or {}) & set(SHORT_BOUT_SETTINGS))
    if short_bout:
        raise InputError(
            f"{', '.join(short_bout)}: the gait check's opt-in short-bout rule is not available in a chunked run; "
            "read the recording whole and apply gaitml.steps._gait_evidence.gait_check(steps, gyr, fs, acc=acc, "
            "confirm_bout_steps=10) to adaptive's steps (gait_check=False)."
        )
    chunk_s = DEFAULT_CHUNK_S if chunk_s is None else chunk_s
    margin_s = DEFAULT_MARGIN_S if margin_s is None else margin_s
    align, margin_read_s = _step_chunking(detector, detector_params, path, read_kwargs, margin_s, count_also)
    parts = []
    fs = None
    attrs: dict = {}
    also_counts: list[int] = []
    accounts: list[dict] = []
    octaves: list[dict] = []
    rhythms: list[dict] = []
    cadence_parts: list[pd.DataFrame] = []
    gait = None
    for ch in progress_chunks(
        iter_chunks(path, chunk_s=chunk_s, margin_s=margin_read_s, align_samples=align, **read_kwargs),
        f"steps ({detector})",
        enabled=progress,
    ):
        fs = ch.recording.sampling_rate_hz
        table, account, det = _core_steps(ch.recording, ch, detector, detector_params, gait_check)
        if keep_cadence:
            cad = _core_cadence(det, ch, fs)
            if cad is not None:
                cadence_parts.append(cad)
        gait = account is not None
        if gait:
            accounts.append(account)
        attrs = dict(table.attrs)
        if "octave" in attrs:
            octaves.append(attrs["octave"])
        if "rhythm" in attrs:
            rhythms.append(attrs["rhythm"])
        parts.append(_shift_steps(table, ch.offset, fs))
        if count_also is not None:
            also_counts.append(int(_in_core(get_detector(count_also).detect(ch.recording).steps_, ch).sum()))
    out = pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()
    out.attrs.update(attrs)
    if octaves:
        out.attrs["octave"] = _sum_octave(octaves)
    if rhythms:
        out.attrs["rhythm"] = _sum_rhythm(rhythms)
    out.attrs["chunked"] = {"chunk_s": chunk_s, "margin_s": margin_read_s}
    if gait:
        out.attrs["gait_check"] = _sum_accounts(accounts)
    if count_also is not None:
        out.attrs["count_also"] = {"detector": count_also, "n_steps": int(sum(also_counts))}
    if cadence_parts:
        cad = pd.concat(cadence_parts, ignore_index=True)
        out.attrs["cadence"] = {c: cad[c].tolist() for c in cad.columns}
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


def _probe_rate(path, read_kwargs: dict) -> float:
    """The sampling rate the chunks of ``path`` will have, before they are cut: the given rate, the
    rate of a recording already read (``recording``), or the first pass's (``scan``, made here and
    kept in ``read_kwargs`` for the reading that follows); else that of a first one-second chunk."""
    if read_kwargs.get("recording") is not None:
        return float(read_kwargs["recording"].sampling_rate_hz)
    fs_probe = read_kwargs.get("sampling_rate_hz")
    if fs_probe is None:
        if read_kwargs.get("scan") is None:
            read_kwargs["scan"] = scan_input(path, **read_kwargs)
        if read_kwargs["scan"] is not None:
            fs_probe = read_kwargs["scan"].sampling_rate_hz
        else:
            first = next(iter_chunks(path, chunk_s=1.0, margin_s=0.0, **read_kwargs))
            fs_probe = first.recording.sampling_rate_hz
    return float(fs_probe)


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
    recording=None,
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
    ``recording``: the file already read whole (a format other than gaitml-csv), sliced instead of reading ``path``.
    """
    from gaitml.signal import window_params

    # the hop depends on the rate, known after the first block: peek at it
    fs_probe = recording.sampling_rate_hz if recording is not None else _probe_rate(path, read_kwargs)
    length, hop = window_params(length_s, overlap, fs_probe)
    align = math.lcm(hop * max(1, int(window_grid)), max(1, int(phase_step)))
    margin_samples = math.ceil((math.ceil(length / hop) + max(0, int(extra_windows))) * hop / align) * align
    if recording is not None:
        chunks = recording_chunks(recording, chunk_s=chunk_s, margin_s=margin_samples / fs_probe, align_samples=align)
    else:
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
    run_min_cadence_hz: float | None = None,
    still_step_veto: int | None = None,
    mark_still_unsure: bool = True,
    **read_kwargs,
) -> pd.DataFrame:
    """Per-window motion modes of a long recording with a saved model.

    Features are computed chunk by chunk; the adjacent-window correction runs
    over the whole label sequence afterwards (it needs only the two previous
    windows, and the sequence of labels is small: 115,200 windows per day at
    1.5 s / 50 %). The run-cadence rule (:func:`gaitml.models._predict.run_cadence_rule`,
    ``run_min_cadence_hz``; None: :data:`~gaitml.models._predict.RUN_CADENCE_DEFAULT_HZ`, 0: off)
    reads each chunk's steps (the chunk's windows' ``step_cadence_hz``) and runs again after the correction.
    The still gate's step veto (``still_step_veto``; None: :data:`~gaitml.models._predict.STILL_STEP_VETO_DEFAULT`, 0: off)
    reads each chunk's steps too (:func:`~gaitml.models._predict.veto_steps`, found once per chunk; shared with the
    run-cadence rule where they are the same steps);
    with either on, each chunk reads :data:`DEFAULT_MARGIN_S` of margin on each side for its detector, so that a window's
    steps are the whole-file run's except where a bout or a 5 s cadence window reaches past the margin. ``still``,
    ``still_vetoed``, ``mode``, ``still_unsure`` (:func:`~gaitml.models._predict.still_unsure`: the stride rhythm reads
    the 15 s around a window, inside the margin; the margin is read for it too) and ``window_steps`` (the veto's count
    in each window the statistic reads still, NaN elsewhere: :func:`~gaitml.models._predict.veto_counts`) are then the
    whole-file run's (``mark_still_unsure`` False: no ``still_unsure`` column, its rhythm not computed)
    (a resampled file, whose gate comes after the chunks, reads the statistic of every window from the file as recorded
    first, :func:`_as_recorded_still`, and runs the detector only in a chunk whose core holds a window it reads still).
    """
    from gaitml.models import predict_recording
    from gaitml.models._predict import (
        RUN_MODE,
        RUN_STRIDE_CADENCE_HZ,
        SIDE_MODES,
        run_cadence_threshold,
        side_direction_unsure,
        steps_found_once,
        still_step_veto_threshold,
        window_step_counts,
    )

    run_thr = run_cadence_threshold(run_min_cadence_hz) or 0.0
    veto_n = still_step_veto_threshold(still_step_veto)

    parts, upright = [], []
    fs = float(model.sampling_rate_hz)
    original = {k: v for k, v in read_kwargs.items()}
    recording, own_hz, own_meta = _at_model_rate(path, fs, read_kwargs)
    # the still gate reads the file as recorded when it is resampled (still_statistic's ``recorded``): off in the chunks,
    # applied to the whole table below from a pass over the file at its own rate
    from gaitml.models._predict import STILL_RULE, STILL_THRESHOLDS_MS2, STILL_UNSURE_DEFAULT, stride_rhythm

    gate_after = STILL_RULE == "std_lp" and abs(own_hz - fs) > 1e-9 * fs
    # a domain record with an orientation-dynamics part decides on the median over the last windows of the
    # dynamics of every `every`-th window (which keep every step-th sample): more context before each core,
    # offsets on that sample grid and on that window grid (a chunk's first window is a computed one)
    dom = getattr(model, "domain", None)
    extra, phase, grid = (0, 1, 1) if dom is None else dom.chunk_context(fs)
    if veto_n is not None or run_thr or (STILL_UNSURE_DEFAULT and mark_still_unsure):
        # the step veto and the run-cadence rule read each chunk's steps (the still_unsure mark its 15 s): a margin of DEFAULT_MARGIN_S (as long_steps
        # reads adaptive's chunks with) gives the detector the bouts around the core's windows, and chunks that start
        # on adaptive's cadence grid give it the whole file's cadence windows (long_steps' rule)
        from gaitml.steps.adaptive import cadence_hop_samples

        extra = max(extra, math.ceil(DEFAULT_MARGIN_S / (model.length_s * (1.0 - model.overlap))))
        phase = math.lcm(int(phase), int(cadence_hop_samples(fs)))
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
        recording=recording,
        **read_kwargs,
    )
    read_still = None  # a resampled file: the gate's statistic of every window, read from the file as recorded, first
    if gate_after:
        from gaitml.signal import window_params

        length, hop = window_params(model.length_s, model.overlap, fs)
        read_still = _as_recorded_still(path, fs, own_hz, recording, original, chunk_s, model.length_s, length, hop)
    rng = getattr(model, "acc_range_ms2", None)
    tallies, counted_to = [], 0  # the accelerometer range (gaitml.features._range): every sample counted once over the chunks
    for ch, _length, _hop in chunks:
        rec = ch.recording
        if rng is not None:
            from gaitml.features import acc_range_tally

            new_from = max(counted_to - ch.offset, 0)
            tallies.append(acc_range_tally(rec.acc[new_from:], rng))
            counted_to = max(counted_to, ch.offset + rec.n_samples)
        if rec.n_samples < _length and ch.offset > 0:  # a short tail; a short first chunk is a short file: refused as one
            continue
        found: dict = {}  # the chunk's steps, found once for the run-cadence rule and the veto when they are the same
        table = predict_recording(
            model,
            rec,
            correction=False,
            run_min_cadence_hz=run_thr,
            still_step_veto=veto_n or 0,
            found_steps=found,
            mark_still_unsure=mark_still_unsure and not gate_after,
            **({"still_threshold_ms2": 0.0} if gate_after else {}),
        )
        gstart = table["start"].to_numpy() + ch.offset
        keep = (gstart >= ch.core_start) & (gstart < ch.core_end)
        if gate_after and veto_n is not None and _chunk_reads_still(read_still, gstart[keep] // hop):
            # the gate comes after the chunks (below): the count of the veto's steps in every window of a chunk whose
            # core holds a window the statistic reads still (the chunk's steps found once); no other window is vetoed
            table["window_steps"] = window_step_counts(table, steps_found_once(found, rec, veto=True)).astype(float)
        if gate_after and mark_still_unsure:  # the stride rhythm of the windows the statistic reads still, for the mark after the gate
            rhythm = np.zeros(len(table), dtype=bool)
            if STILL_UNSURE_DEFAULT and rec.has_gyr:
                read = _lookup(read_still, gstart // hop)
                if read.any():
                    rhythm[read] = stride_rhythm(rec, table[read])
            table["_rhythm"] = rhythm
        # the phone held upright in each window (a side step there has an unsure direction), for the corrected modes below
        upright.append(side_direction_unsure(rec, table, np.full(len(table), SIDE_MODES[0]))[keep])
        parts.append(_globalise_windows(table[keep].reset_index(drop=True), ch.offset, rec.sampling_rate_hz))
    out = pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()
    if gate_after and len(out):
        _still_as_recorded(out, _lookup(read_still, out["start"].to_numpy(np.int64) // hop), veto_n)
        if mark_still_unsure:
            out["still_unsure"] = out["still"].to_numpy(dtype=bool) & out.pop("_rhythm").to_numpy(dtype=bool)
    if correction and len(out):
        from gaitml.models._predict import STILL
        from gaitml.postprocess import adjacent_window_correction

        raw = out["mode_raw"].to_numpy().astype(str)
        corrected = np.asarray(adjacent_window_correction(raw)).astype(str)
        if run_thr:  # the run-cadence rule on the corrected modes: a raw run's best other mode is the chunk's answer
            with np.errstate(invalid="ignore"):
                cad = out["step_cadence_hz"].to_numpy(float)
                slow = (corrected == RUN_MODE) & (cad < float(run_thr)) & (cad >= RUN_STRIDE_CADENCE_HZ)
            chunk_mode = out["mode"].to_numpy().astype(str)
            corrected = np.where(slow, np.where(raw == RUN_MODE, chunk_mode, raw), corrected).astype(str)
            out["run_at_walking_cadence"] = slow & ~out["still"].to_numpy(dtype=bool)
        out["mode"] = np.where(out["still"].to_numpy(dtype=bool), STILL, corrected)
        out["side_direction_unsure"] = np.concatenate(upright) & np.isin(out["mode"].to_numpy().astype(str), SIDE_MODES)
    # what a whole-file prediction table says about its rate (predict_recording's attrs)
    out.attrs.update(
        sampling_rate_hz=fs,
        resampled_from_hz=None if abs(own_hz - fs) <= 1e-9 * fs else own_hz,
        correction=bool(correction),
        has_domain=dom is not None,
        acc_range=_sum_tallies(tallies, rng),
        run_cadence={"min_cadence_hz": float(run_thr) if run_thr else None},
    )
    out.attrs["still_gate"] = {"statistic": STILL_RULE, "threshold_ms2": STILL_THRESHOLDS_MS2[STILL_RULE], "step_veto_min_steps": veto_n}
    # the chunks come at the model's rate: the rate check reads the file's own (as predict_recording does)
    from gaitml.models._predict import apply_rate_check, recorded_rate_hz

    return apply_rate_check(out, model, recorded_rate_hz(own_hz, own_meta), own_meta.get("rate_changes"))


def _as_recorded_still(
    path, fs: float, own_hz: float, recording, read_kwargs: dict, chunk_s: float, length_s: float, length: int, hop: int
) -> np.ndarray:
    """Whether the still gate's ``std_lp`` statistic reads each window of the whole file's grid at the model's rate
    ``fs`` still (window ``k``: samples ``[k hop, k hop + length)`` at ``fs``), read from the file at its own rate
    ``own_hz``, as :func:`~gaitml.models.predict_recording` reads a resampled recording (``recorded``). Found before
    the chunks, so that a chunk without a still-read window need not look for the veto's steps.

    ``recording``: the file at ``fs`` already read whole (a format other than gaitml-csv; the file is read whole again at
    its own rate), or None: a gaitml-csv, read again chunk by chunk at its own rate (each window from the first chunk that
    holds all of its samples; a window no chunk holds is not still). Each window reads only its own samples, so the
    statistic is the whole-file run's. The array may be longer or shorter than the windows the chunks give
    (:func:`_lookup`).
    """
    from gaitml.io import read_recording
    from gaitml.models._predict import still_windows

    kw = {k: v for k, v in read_kwargs.items() if k != "recording"}  # a scan given by the caller is the file's own
    if recording is not None:
        made = read_kwargs.get("recording")
        if made is None:
            made = read_recording(path, **{k: v for k, v in kw.items() if k != "scan"})
        starts = np.arange(0, max(recording.n_samples - length + 1, 0), hop, dtype=np.int64)
        return still_windows(recording, pd.DataFrame({"start": starts, "end": starts + length}), recorded=made)
    from gaitml.models._predict import still_statistic

    own_length = int(np.rint(length * own_hz / fs))
    stats: list[np.ndarray] = []
    done = 0  # windows 0 .. done-1 are decided
    for ch in iter_chunks(path, chunk_s=chunk_s, margin_s=2.0 * length_s, **kw):
        n_end = ch.offset + ch.recording.n_samples
        k_hi = int(np.floor((n_end - own_length + 1.5) * fs / (own_hz * hop))) + 1  # past the last window this chunk can hold
        k = np.arange(done, max(k_hi, done), dtype=np.int64)
        a = np.ceil(k * hop * own_hz / fs - 0.5 - 1e-9).astype(np.int64)
        b = a + own_length
        k, a, b = k[b <= n_end], a[b <= n_end], b[b <= n_end]
        stat = np.full(len(k), np.inf)  # a window whose first samples lie before this chunk: no chunk holds it whole
        inside = a >= ch.offset
        if inside.any():
            w = pd.DataFrame({"start": a[inside] - ch.offset, "end": b[inside] - ch.offset})
            stat[inside] = still_statistic(ch.recording, w, "std_lp")
        stats.append(stat)
        done += len(k)
    return _below_gate(np.concatenate(stats) if stats else np.zeros(0))


def _lookup(read_still: np.ndarray, k: np.ndarray) -> np.ndarray:
    """``read_still`` (:func:`_as_recorded_still`) of windows ``k`` of the grid; a window past its end is not still."""
    k = np.asarray(k, dtype=np.int64)
    out = np.zeros(len(k), dtype=bool)
    ok = (k >= 0) & (k < len(read_still))
    out[ok] = read_still[k[ok]]
    return out


def _chunk_reads_still(read_still: np.ndarray, k: np.ndarray) -> bool:
    """Whether some window ``k`` of a chunk's core reads still (:func:`_as_recorded_still`): only then does the veto,
    which acts on those windows alone, need the chunk's steps."""
    return bool(_lookup(read_still, k).any())


def _still_as_recorded(out: pd.DataFrame, still: np.ndarray, veto_n: int | None = None) -> None:
    """The still gate on ``out`` (global windows at the model's rate) from ``still``, the statistic of each as recorded
    (:func:`_as_recorded_still`), as :func:`~gaitml.models.predict_recording` reads a resampled recording: ``still``,
    ``still_vetoed``, ``mode`` (``still`` where the gate fires) and ``run_at_walking_cadence`` (never on a still window)
    are set in place. ``veto_n``: the step veto in force (None: off); ``out``'s ``window_steps`` are then the chunks'
    counts of every window of a chunk with a still-read window, kept afterwards only where the statistic reads the
    window still (:func:`~gaitml.models._predict.veto_counts`).
    """
    from gaitml.models._predict import STILL, veto_counts

    vetoed = np.zeros(len(out), dtype=bool)
    if veto_n is not None and "window_steps" in out:
        counts = np.nan_to_num(out["window_steps"].to_numpy(float), nan=0.0)
        vetoed = still & (counts >= veto_n)
        out["window_steps"] = veto_counts(counts, still)  # the counts the veto decided on, as a whole-file run keeps them
        still = still & ~vetoed
    out["still"] = still
    out["still_vetoed"] = vetoed
    out["mode"] = np.where(still, STILL, out["mode"].to_numpy(dtype=object)).astype(str)
    if "run_at_walking_cadence" in out:
        out["run_at_walking_cadence"] = out["run_at_walking_cadence"].to_numpy(dtype=bool) & ~still


def _below_gate(stat: np.ndarray) -> np.ndarray:
    """Whether the ``std_lp`` statistics ``stat`` fall under the default gate's threshold."""
    from gaitml.models._predict import STILL_THRESHOLDS_MS2

    return np.asarray(stat) < STILL_THRESHOLDS_MS2["std_lp"]


def _sum_tallies(tallies: list[dict], range_ms2: float | None) -> dict | None:
    """The :func:`gaitml.features.acc_range_tally` of a whole file from those of its chunks' new samples."""
    if range_ms2 is None:
        return None
    from gaitml.features import WIDER_RANGE_RATIO

    top = max((t["max_abs_axis_ms2"] for t in tallies), default=0.0)
    return {
        "range_ms2": float(range_ms2),
        "n_samples": sum(t["n_samples"] for t in tallies),
        "n_samples_clipped": sum(t["n_samples_clipped"] for t in tallies),
        "max_abs_axis_ms2": top,
        "wider": bool(top > WIDER_RANGE_RATIO * float(range_ms2)),
    }


def _at_model_rate(path, fs: float, read_kwargs: dict):
    """Make the chunks of ``path`` come at the model's rate ``fs``, as :func:`~gaitml.models.predict_recording`
    resamples a whole recording to it; returns ``(recording, own_hz, meta)`` (``meta``: the file's, as read).

    The file is read as a whole-file run reads it (``read_kwargs``: the user's format and rate, if any;
    a file without a time base, gaitmap or IFSM, at its own known rate, never at the model's), at
    ``own_hz``. A gaitml-csv is then read chunk by chunk on the model's grid (its first pass, the scan,
    moved to ``fs``: ``read_kwargs`` is updated; ``recording`` None). Any other format is read whole
    anyway, so it is resampled whole with :func:`~gaitml.models.resample_recording` (the resampling of
    a whole-file prediction) and returned as ``recording``, for :func:`_window_chunks` to slice;
    ``read_kwargs['recording']``, when given, is that file already read whole (taken out of ``read_kwargs``).
    """
    from gaitml.io import read_recording
    from gaitml.models import resample_recording

    whole = read_kwargs.pop("recording", None)
    if whole is not None:
        return resample_recording(whole, fs), float(whole.sampling_rate_hz), dict(whole.meta)
    scan = read_kwargs.pop("scan", None)
    if scan is None:
        scan = scan_input(path, **read_kwargs)
    if scan is not None:
        same = abs(scan.sampling_rate_hz - fs) <= 1e-9 * fs
        read_kwargs["scan"] = scan if same else scan.at_rate(fs)
        read_kwargs["sampling_rate_hz"] = fs
        return None, float(scan.sampling_rate_hz), dict(scan.meta)
    rec = read_recording(path, **read_kwargs)
    return resample_recording(rec, fs), float(rec.sampling_rate_hz), dict(rec.meta)


def _step_chunking(detector: str, detector_params, path, read_kwargs, margin_s: float, also: str | None = None) -> tuple[int, float]:
    """The chunk alignment (samples) and margin (s) for a step detector: for one with a cadence grid
    (``adaptive``), chunk offsets (core start - margin) fall on multiples of the cadence hop, so each
    chunk's cadence windows, and the steps placed with them, are the whole-file run's (:func:`long_steps`
    and :func:`long_pdr` alike); with a second detector ``also`` (the count cross-check) on the least
    common multiple of both grids; otherwise no alignment and the margin as asked."""
    from gaitml.steps import get_detector

    grids = [getattr(get_detector(detector, **dict(detector_params or {})), "cadence_hop_samples", None)]
    if also is not None:
        grids.append(getattr(get_detector(also), "cadence_hop_samples", None))
    grids = [g for g in grids if g is not None]
    if not grids:
        return 1, margin_s
    fs_probe = _probe_rate(path, read_kwargs)
    align = math.lcm(*(int(g(fs_probe)) for g in grids))
    return align, math.ceil(round(margin_s * fs_probe) / align) * align / fs_probe


def long_pdr(
    path: str | os.PathLike,
    *,
    model=None,
    detector: str = DEFAULT_STEP_DETECTOR,
    heading: str = "hde",
    modes: str | None = None,
    mode_boundaries: str = "auto",
    step_length=None,
    initial_heading_rad: float = 0.0,
    chunk_s: float | None = None,
    margin_s: float | None = None,
    progress: bool = True,
    count_also: str | None = None,
    gyro_bias="auto",
    run_min_cadence_hz: float | None = None,
    hde=None,
    gyro_bias_start=None,
    short_run_windows: float | None = None,
    **read_kwargs,
):
    """Dead-reckon a long recording chunk by chunk: :func:`gaitml.pdr.run_pdr` in bounded memory.

    One pass over the file's chunks detects the steps (those anchored in each chunk's core,
    as :func:`long_steps`), computes their step-length features and true-label modes on the
    chunk, and integrates the attitude (paper 003 sec. 4.2) across the chunks: each chunk
    continues the integration from the attitude (and gyroscope bias, ``gyro_bias`` as
    :class:`~gaitml.pdr.attitude.AttitudeEstimator`'s: with ``'still'`` or ``'auto'`` the first
    chunk starts from the still-stretch bias of the whole file, found in a first pass by
    :func:`long_still_bias`, or from ``gyro_bias_start`` when given (a bias measured elsewhere, as
    :func:`gaitml.pdr.run_pdr`'s), then the bias is carried) of the sample before its core
    (:meth:`~gaitml.pdr.attitude.AttitudeEstimator.estimate_from`), and the samples of its
    left margin keep the previous chunk's headings, so every sample's heading is that of one
    integration over the whole file (the complementary filter's zero-phase gravity low-pass
    is computed per chunk; the margins keep its edge effects out of the cores). Only per-step
    values are kept, so memory grows with the steps (a few hundred bytes each), not the samples.

    The heading correction then runs on the whole step sequence, as on a whole recording: HDE
    (paper 003 sec. 4.2, with its drift rate fitted and its structure guard tested over all steps: one
    decision for the whole file, ``info['heading_check']``) and the raw gyro heading
    need only the per-step gyro headings (``steps_only``). Modes from a model come from
    :func:`long_predict` (identical windows), each step taking the nearest window's mode.

    Not available chunked, each refused with an :class:`~gaitml.errors.InputError`: DW-PCA
    headings (not implemented: they would need each step's navigation-frame acceleration and
    mode inside the chunk loop), step-window
    models and ``mode_boundaries='refine'`` (the refinement reads the samples around every
    mode change); ``'auto'`` becomes ``'nearest'`` with a note.

    ``short_run_windows``: the short-run rule of :func:`gaitml.pdr.run_pdr` (None: its default, 0: off), applied to
    the nearest-window modes of the whole step sequence as on a whole recording.

    ``chunk_s`` / ``margin_s``: the chunk core and margin lengths (default
    :data:`DEFAULT_CHUNK_S`, :data:`DEFAULT_MARGIN_S`). ``hde``: a configured
    :class:`~gaitml.pdr.hde.HeuristicDriftElimination` for ``heading='hde'`` (as :func:`gaitml.pdr.run_pdr`'s;
    default ``HeuristicDriftElimination(reference_rad=initial_heading_rad)``, its structure guard on).

    Returns
    -------
    PdrResult, with ``steps.attrs["count_also"]`` as :func:`long_steps` when ``count_also`` is given
    and ``steps.attrs["recording_name"]`` (the :attr:`~gaitml.recording.Recording.name` of a whole-file read).
    """
    from gaitml.errors import InputError
    from gaitml.pdr.attitude import step_headings
    from gaitml.pdr.pipeline import (
        _heading_source,
        _out_of_domain_steps,
        _resolve_step_length,
        _short_runs,
        _step_reasons,
        assemble_result,
        calibration_detector_check,
        heading_check_record,
        modes_from_labels,
        short_run_setting,
        short_run_unused,
    )
    from gaitml.pdr.step_length import step_length_features
    from gaitml.pdr.step_modes import modes_from_windows, next_step_times
    from gaitml.pdr.update import mode_offsets_rad
    from gaitml.steps import get_detector, rate_record
    from gaitml.steps._table import gait_check_record

    chunk_s = DEFAULT_CHUNK_S if chunk_s is None else chunk_s
    margin_s = DEFAULT_MARGIN_S if margin_s is None else margin_s
    source = _heading_source(
        heading,
        attitude=None,
        hde=hde,
        dwpca=None,
        initial_heading_rad=initial_heading_rad,
        gyro_bias=gyro_bias,
        gyro_bias_start=gyro_bias_start,
    )
    modes, mode_boundaries, notes = check_long_pdr(path, source, model=model, modes=modes, mode_boundaries=mode_boundaries)
    short_w = short_run_setting(short_run_windows)
    slm, sl_source = _resolve_step_length(step_length)
    if slm is None:
        raise InputError(
            "step_length='reference' needs a simulated recording's reference steps, which a file read in chunks does not carry."
        )

    windows = None
    if modes == "model":
        windows = long_predict(
            model,
            path,
            correction=True,
            chunk_s=chunk_s,
            progress=progress,
            run_min_cadence_hz=run_min_cadence_hz,
            mark_still_unsure=False,  # the PDR reads the modes its steps take, never the 'still' the mark qualifies
            **dict(read_kwargs),
        )

    # the still-stretch gyroscope bias of the whole file (a first pass), as a whole-file run starts from;
    # a bias measured elsewhere (the attitude's start_bias) takes its place, as in a whole-file run
    att = source.attitude
    still_bias = None
    if isinstance(att.gyro_bias, str) and att.gyro_bias in ("still", "auto"):
        start = getattr(att, "start_bias", None)
        still_bias = start if start is not None else long_still_bias(path, chunk_s=chunk_s, progress=progress, **dict(read_kwargs))

    parts, feat_parts, gyro_parts, label_parts, bias_parts = [], [], [], [], []
    also_counts: list[int] = []
    accounts: list[dict] = []
    octaves: list[dict] = []
    rhythms: list[dict] = []
    attrs: dict = {}
    fs = None
    carry = None  # attitude of the sample before the next chunk's core
    carry_bias = None  # and the gyroscope bias there
    first_bias = None  # the first chunk's bias record (what was removed at the start)
    prev_heading = None  # per-sample heading of the previous chunk, from global index prev_lo
    prev_lo = 0
    align, margin_read_s = _step_chunking(detector, None, path, read_kwargs, margin_s, count_also)
    for ch in progress_chunks(
        iter_chunks(path, chunk_s=chunk_s, margin_s=margin_read_s, align_samples=align, **read_kwargs),
        f"pdr ({detector})",
        enabled=progress,
    ):
        rec = ch.recording
        fs = rec.sampling_rate_hz
        rec.require_gyr("PDR heading")
        attrs["recording_name"] = rec.name
        if modes is None:
            if rec.labels is not None:
                modes = "true"
                notes.append("no --model; using the recording's own per-sample labels as the motion modes (--modes true).")
            else:
                modes = "forward"
                notes.append("no --model and no labels: every step is treated as a forward walk step (traditional PDR, --modes forward).")
        if modes == "true" and rec.labels is None:
            raise InputError(
                f"--modes true needs per-sample labels but {Path(path).name} has none; pass --model MODEL_DIR or use --modes forward."
            )
        # ---- attitude: continue the integration from the sample before this chunk's core
        k = ch.core_start - ch.offset
        if carry is None:
            run = clone(att).estimate(rec, still_bias=still_bias)
            heading_local = run.heading_rad_
            first = 0
            first_bias = run.gyro_bias_
        else:
            run = clone(att).estimate_from(rec, k - 1, carry, initial_bias_rads=carry_bias)
            first = k - 1
            heading_local = np.concatenate([prev_heading[ch.offset - prev_lo : ch.offset - prev_lo + first], run.heading_rad_])
        last = ch.core_end - 1 - ch.offset  # local index of the core's last sample
        carry = run.rotation_[last - first]
        carry_bias = run.bias_rads_[last - first]
        bias_parts.append(run.bias_rads_[k - first : last - first + 1])
        prev_heading, prev_lo = heading_local, ch.offset
        # ---- steps anchored in the core (the detector's own gait-evidence test, accounted over the cores)
        table, account, _det = _core_steps(rec, ch, detector, None, None)
        if account is not None:
            accounts.append(account)
        attrs.update(table.attrs)
        if "octave" in table.attrs:
            octaves.append(table.attrs["octave"])
        if "rhythm" in table.attrs:
            rhythms.append(table.attrs["rhythm"])
        if count_also is not None:
            also_counts.append(int(_in_core(get_detector(count_also).detect(rec).steps_, ch).sum()))
        start = table["start"].to_numpy(np.int64)
        end = np.maximum(table["end"].to_numpy(np.int64), start + 1)
        gyro_parts.append(step_headings(heading_local, start, end) if len(table) else np.zeros(0))
        feat_parts.append(step_length_features(rec.acc, table, fs))
        if modes == "true":
            label_parts.append(modes_from_labels(rec.labels, start, end) if len(table) else np.zeros(0, dtype=str))
        parts.append(_shift_steps(table, ch.offset, fs))
    if fs is None:
        raise InputError(f"{Path(path).name} has no samples.")
    steps = pd.concat(parts, ignore_index=True)
    steps.attrs.update(attrs)
    if octaves:
        steps.attrs["octave"] = _sum_octave(octaves)
    if rhythms:
        steps.attrs["rhythm"] = _sum_rhythm(rhythms)
    event = steps.attrs.get("event", "t_peak_s")
    if event not in steps:
        event = "t_peak_s"
    steps.attrs["event"] = event
    steps.attrs["chunked"] = {"chunk_s": chunk_s, "margin_s": margin_read_s}
    gait = gait_check_record(_sum_accounts(accounts)) if accounts else None
    if gait is not None:
        steps.attrs["gait_check"] = gait
    if count_also is not None:
        steps.attrs["count_also"] = {"detector": count_also, "n_steps": int(sum(also_counts))}
    feats = pd.concat(feat_parts, ignore_index=True)
    gyro_h = np.concatenate(gyro_parts)
    t_step = steps[event].to_numpy(float)
    n = len(steps)

    # ---- modes per step (as run_pdr)
    step_in_domain = model_modes = step_reasons = short_run_steps = None
    if modes == "true":
        step_modes = np.concatenate(label_parts).astype(str)
    elif modes == "model":
        t_look = 0.5 * (t_step + next_step_times(t_step)) if mode_boundaries == "middle" and n > 1 else t_step
        step_modes = modes_from_windows(windows, t_look) if n else np.zeros(0, dtype=str)
        step_modes, short_run_steps = _short_runs(step_modes, t_step, model, short_w, notes)
        step_in_domain, step_modes, model_modes = _out_of_domain_steps(model, windows, t_look, step_modes)
        step_reasons = _step_reasons(windows, t_look, n)
    else:
        step_modes = np.full(n, "walk", dtype=object)
    if modes != "model":
        short_run_unused(short_w, modes, notes)
    step_modes = np.asarray(step_modes).astype(str)
    update = "forward" if modes == "forward" else "multi"
    offsets = mode_offsets_rad(step_modes, unknown="forward")
    unknown = sorted(set(step_modes) - {"walk", "run", "side_left", "side_right", "backward", "forward"})
    if unknown:
        notes.append(f"modes {unknown} are not motion modes of paper 003; moved along the heading")
    lengths = slm.predict(feats, step_modes)
    lengths = np.where(np.isfinite(lengths), lengths, 0.0)
    heading_steps = steps.assign(mode=step_modes, mode_offset_rad=offsets if update == "multi" else np.zeros(n))
    heading_steps.attrs = dict(steps.attrs)
    source.estimate_steps(heading_steps, gyro_h, fs)
    res = assemble_result(
        steps,
        feats,
        step_modes,
        lengths,
        source.heading_rad_,
        gyro_h,
        update=update,
        start_xy_m=(0.0, 0.0),
        initial_heading_rad=initial_heading_rad,
        step_in_domain=step_in_domain,
        model_modes=model_modes,
        model=model,
        step_reasons=step_reasons,
        outside_fit=slm.outside_fit(feats, step_modes),
        info={
            "detector": detector,
            "heading": heading,
            "modes": modes,
            "mode_boundaries": mode_boundaries if modes == "model" else None,
            "short_run_steps": short_run_steps,
            "update": update,
            "step_length": sl_source,
            "initial_heading_rad": float(initial_heading_rad),
            "gyro_bias": None if first_bias is None else _bias_summary(first_bias, still_bias, bias_parts, fs),
            "heading_check": heading_check_record(source),
            "gait_check": gait,
            "rate_check": rate_record(steps),  # the whole file's (each chunk carries the file's rates and rate changes)
            "step_length_detector": calibration_detector_check(slm, detector),
            "notes": notes,
        },
    )
    res.steps.attrs.update(steps.attrs)
    return res


def _bias_summary(first, still, bias_parts, fs) -> dict:
    """What the chunked attitude removed, as a whole-file run reports it: the start bias (``still``, the
    whole file's still-stretch estimate, when there is one; else the first chunk's) and, when tracked
    online, the median of the tracked bias over the second half of the whole recording."""
    from gaitml.pdr.attitude import _online_summary

    if not first.method.endswith("online"):  # 'online', 'still+online', '<measured elsewhere>+online'
        return first.to_dict()
    if still is not None:
        return _online_summary(still, np.concatenate(bias_parts), fs).to_dict()
    start = first.__class__(
        np.asarray(first.params.get("start_bias_rads", np.zeros(3)), dtype=float),
        "still" if first.method == "still+online" else "none",
        still_s=first.still_s,
        n_still_windows=first.n_still_windows,
        params={k: v for k, v in first.params.items() if k != "start_bias_rads"},
    )
    return _online_summary(start, np.concatenate(bias_parts), fs).to_dict()


def long_still_bias(path: str | os.PathLike, *, chunk_s: float | None = None, progress: bool = True, **read_kwargs):
    """The still-stretch gyroscope bias of a long recording read chunk by chunk: the same
    :class:`~gaitml.signal.GyroBias` as :func:`gaitml.signal.estimate_gyro_bias` of the file read whole.

    Each chunk gives the still test of the windows starting in its core
    (:func:`gaitml.signal.gyro_still_windows` on the whole file's window grid; the chunk margins of two
    still windows hold every core window whole), and one median runs over the windows of all
    chunks (:func:`gaitml.signal.gyro_bias_from_windows`). Memory: a few tens of bytes per window
    (half a still window, 0.5 s), e.g. 7 MB for a day.
    """
    from gaitml.signal import gyro_bias_from_windows, gyro_still_windows
    from gaitml.signal._gyro_bias import STILL_WINDOW_S

    chunk_s = DEFAULT_CHUNK_S if chunk_s is None else chunk_s
    parts = []
    for ch in progress_chunks(
        iter_chunks(path, chunk_s=chunk_s, margin_s=2.0 * STILL_WINDOW_S, **read_kwargs), "gyro bias", enabled=progress
    ):
        rec = ch.recording
        rec.require_gyr("PDR heading")
        parts.append(gyro_still_windows(rec.acc, rec.gyr, rec.sampling_rate_hz, offset=ch.offset).select(ch.core_start, ch.core_end))
    if not parts:
        from gaitml.errors import InputError

        raise InputError(f"{Path(path).name} has no samples.")
    return gyro_bias_from_windows(parts)


def check_long_pdr(
    path, heading, *, model=None, modes: str | None = None, mode_boundaries: str = "auto"
) -> tuple[str | None, str, list[str]]:
    """Refuse what :func:`long_pdr` cannot run chunked (before any reading), one :class:`~gaitml.errors.InputError` each.

    ``heading`` is a heading source name or object. Returns ``(modes, mode_boundaries, notes)``:
    ``modes`` is ``'model'`` with a model and None when it is decided on the first chunk (labels
    or forward); ``'auto'`` boundaries become ``'nearest'``, with a note.
    """
    from gaitml.errors import InputError
    from gaitml.pdr.pipeline import HEADING_SOURCES, MODE_SOURCES

    cls = HEADING_SOURCES.get(heading) if isinstance(heading, str) else type(heading)
    if cls is not None and not cls.steps_only:
        name = heading if isinstance(heading, str) else cls.name or cls.__name__
        raise InputError(
            f"the {name} heading is not available on {Path(path).name}, which is read in chunks (a long file); "
            "use --heading hde or --heading gyro, or split the file (gaitml split)."
        )
    notes: list[str] = []
    if modes is None:
        modes = "model" if model is not None else None
    if modes is not None and modes not in MODE_SOURCES:
        raise InputError(f"unknown mode source {modes!r}; use one of {', '.join(MODE_SOURCES)}.")
    if modes == "model":
        if model is None:
            raise InputError("modes='model' needs a model (--model MODEL_DIR); use modes='true' with labels or 'forward'.")
        if getattr(model, "window_by", "time") != "time":
            raise InputError(
                "a step-window model classifies each step on the whole recording's samples and this file is read in chunks "
                "(a long file); use a time-window model, or split the file (gaitml split)."
            )
        if mode_boundaries == "refine":
            raise InputError(
                "--mode-boundaries refine reads the samples around every mode change and this file is read in chunks "
                "(a long file); use --mode-boundaries nearest or middle, or split the file (gaitml split)."
            )
        if mode_boundaries == "auto":
            mode_boundaries = "nearest"
            notes.append("a long file read in chunks: modes from the nearest window, without boundary refinement")
    return modes, mode_boundaries, notes
