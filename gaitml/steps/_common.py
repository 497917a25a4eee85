"""Helpers shared by the step detectors: input checks, magnitude, rate conversion."""

from __future__ import annotations

import numpy as np

from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.signal import magnitude

__all__ = ["as_recording", "acc_magnitude", "resample_signal", "check_positive", "map_indices"]


def as_recording(recording: Recording, what: str, *, min_duration_s: float = 1.0, min_samples: int = 8) -> Recording:
    """Check ``recording`` is a :class:`Recording` long enough for ``what``.

    Raises
    ------
    InputError
        If it is not a Recording or is shorter than ``min_duration_s`` seconds
        (and ``min_samples`` samples).
    """
    if not isinstance(recording, Recording):
        raise InputError(f"{what} needs a gaitml Recording, got {type(recording).__name__}; read the file with gaitml.io.read_recording.")
    n_min = max(int(min_samples), int(np.ceil(min_duration_s * recording.sampling_rate_hz)))
    recording.require_samples(n_min, what)
    return recording


def acc_magnitude(recording: Recording) -> np.ndarray:
    """|acc| of each sample (m/s^2, gravity included), shape (n,)."""
    return magnitude(recording.acc)


def check_positive(name: str, value: float, *, allow_zero: bool = False) -> float:
    """Return ``float(value)`` or raise InputError naming the parameter."""
    v = float(value)
    if not np.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        raise InputError(f"`{name}` must be a {'non-negative' if allow_zero else 'positive'} number, got {value!r}.")
    return v


def resample_signal(x: np.ndarray, fs_in_hz: float, fs_out_hz: float) -> np.ndarray:
    """Linearly interpolate a 1-D signal sampled at ``fs_in_hz`` onto a ``fs_out_hz`` grid.

    Used by detectors whose parameters are sample counts at a design rate
    (paper 000: 50 Hz): the signal is brought to that rate, the detector runs
    there, and the indices are mapped back with :func:`map_indices`.
    """
    if fs_in_hz == fs_out_hz:
        return np.asarray(x, dtype=float)
    n_in = len(x)
    duration = (n_in - 1) / fs_in_hz
    n_out = int(np.floor(duration * fs_out_hz)) + 1
    t_out = np.arange(n_out) / fs_out_hz
    return np.interp(t_out, np.arange(n_in) / fs_in_hz, x)


def map_indices(idx: np.ndarray, fs_from_hz: float, fs_to_hz: float, n_to: int) -> np.ndarray:
    """Map sample indices from one rate to the nearest sample of another (clipped to ``[0, n_to]``)."""
    idx = np.asarray(idx, dtype=np.int64)
    if fs_from_hz == fs_to_hz:
        return idx
    return np.clip(np.rint(idx * (fs_to_hz / fs_from_hz)).astype(np.int64), 0, n_to)


def segment_argmax(x: np.ndarray, start: np.ndarray, end: np.ndarray, *, minimum: bool = False) -> np.ndarray:
    """Index of the maximum (or minimum) of ``x[start[i]:end[i]]`` for every segment, vectorised.

    The first index wins on ties; an empty segment gives ``start[i]``.
    """
    x = np.asarray(x, dtype=float)
    start = np.asarray(start, dtype=np.int64)
    end = np.asarray(end, dtype=np.int64)
    out = start.copy()
    lengths = np.maximum(end - start, 0)
    nz = np.flatnonzero(lengths > 0)
    if len(nz) == 0:
        return out
    L = lengths[nz]
    offsets = np.cumsum(L) - L
    seg = np.repeat(np.arange(len(nz)), L)
    pos = np.arange(int(L.sum())) - np.repeat(offsets, L) + np.repeat(start[nz], L)
    vals = x[pos]
    if minimum:
        vals = -vals
    best = np.maximum.reduceat(vals, offsets)
    hit = np.flatnonzero(vals == best[seg])
    first = hit[np.concatenate([[True], seg[hit][1:] != seg[hit][:-1]])]
    out[nz] = pos[first]
    return out
