"""Resampling timestamped samples onto a uniform grid, block by block or all at once.

The grid is ``t0 + k / fs`` for every k whose time does not pass the last
sample. Each channel is linearly interpolated onto it; labels are carried by the
latest original sample at or before each grid time (sample-and-hold).

Down-sampling filters before it decimates (Oppenheim & Schafer, *Discrete-Time
Signal Processing*, 3rd ed., sec. 4.6.1: a rate reduction by an integer factor
``k`` needs a low-pass filter at ``pi / k`` first, or the band above the new
Nyquist frequency folds onto the gait band). When the fastest stretch of the
timestamps runs at ``k >= 2`` times the target rate (:func:`decimation_factor`),
the samples are first interpolated onto the fine grid ``t0 + j / (k fs)``,
filtered there by a linear-phase windowed-sinc FIR low-pass (Hamming window, the
window method of sec. 7.5; cut-off :data:`AA_CUTOFF_FRACTION` of the new Nyquist
frequency, :data:`AA_TAPS_PER_FACTOR` x k + 1 taps, delay compensated, edges
extended by odd reflection as ``scipy.signal.filtfilt`` pads) and every k-th sample is kept. With
``k = 1`` (an ordinary, slightly jittered or up-sampled recording) the grid
values are the plain linear interpolation.

:class:`UniformResampler` does this for consecutive blocks of one long file and
gives what one call on the whole file gives (the last sample and the filter's
history are carried across block boundaries); :func:`resample_uniform` is one
block.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from gaitml.errors import InputError

__all__ = ["resample_uniform", "UniformResampler", "decimation_factor", "AA_CUTOFF_FRACTION", "AA_TAPS_PER_FACTOR"]

#: Resampling never makes more than this many times the original samples (+1000):
#: up-sampling further adds no information and could exhaust memory.
_MAX_UPSAMPLE = 100.0
#: The anti-alias filter's cut-off as a fraction of the new Nyquist frequency ``fs / 2``.
AA_CUTOFF_FRACTION = 0.9
#: Taps of the anti-alias FIR per unit of the decimation factor (plus one: odd, linear phase).
AA_TAPS_PER_FACTOR = 16
#: A stretch faster than the target by less than this fraction is not decimated (timestamp jitter).
_DECIMATE_SLACK = 0.1


def decimation_factor(max_rate_hz: float | None, sampling_rate_hz: float) -> int:
    """The integer factor ``k`` by which the fastest stretch (``max_rate_hz``) is decimated to ``sampling_rate_hz``.

    ``ceil(max_rate_hz / sampling_rate_hz - 0.1)``, at least 1: jitter of a few
    per cent is no decimation; 1.5x and faster is filtered.
    """
    if max_rate_hz is None or not np.isfinite(max_rate_hz) or max_rate_hz <= 0:
        return 1
    return max(1, math.ceil(float(max_rate_hz) / float(sampling_rate_hz) - _DECIMATE_SLACK))


def anti_alias_taps(k: int) -> np.ndarray:
    """The FIR low-pass taps for decimation by ``k`` (see the module docstring)."""
    from scipy.signal import firwin

    return firwin(AA_TAPS_PER_FACTOR * k + 1, AA_CUTOFF_FRACTION / k, window="hamming")


class UniformResampler:
    """Resample consecutive blocks of timestamped samples onto one uniform grid.

    Parameters
    ----------
    t0 : float
        The first timestamp of the whole recording (grid origin).
    t_end : float
        The last timestamp of the whole recording (the grid stops there).
    sampling_rate_hz : float
        The grid's rate.
    max_rate_hz : float, optional
        The fastest local rate of the timestamps (decides the anti-alias filter).

    Feed blocks in time order with :meth:`push` (each returns the grid samples
    it completes) and call :meth:`flush` after the last one.
    """

    def __init__(self, t0: float, t_end: float, sampling_rate_hz: float, *, max_rate_hz: float | None = None):
        self.t0 = float(t0)
        self.fs = float(sampling_rate_hz)
        self.k = decimation_factor(max_rate_hz, self.fs)
        self.fine_fs = self.fs * self.k
        #: number of fine-grid samples of the whole recording
        self.n_fine = int(np.floor((float(t_end) - self.t0) * self.fine_fs + 1e-9)) + 1
        self.taps = anti_alias_taps(self.k) if self.k > 1 else None
        self.half = 0 if self.taps is None else (len(self.taps) - 1) // 2
        self._prev: tuple[float, np.ndarray, Any] | None = None  # last original sample: (t, values, label)
        self._j_next = 0  # next fine-grid index to interpolate
        self._hist: np.ndarray | None = None  # fine samples not yet filtered (with the left context)
        self._hist_j0 = 0  # fine index of _hist[0] (negative for the start padding)
        self._lab_hist: np.ndarray | None = None
        self._out_next = 0  # next fine index whose filtered value is due
        self._width = 0  # number of channels

    def push(self, t: np.ndarray, x: np.ndarray, labels: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray | None]:
        """Add a block (times increasing, after the previous block); return the grid values and labels it completes."""
        t = np.asarray(t, dtype=float)
        x = np.asarray(x, dtype=float)
        lab = None if labels is None else np.asarray(labels)
        self._width = x.shape[1]
        if self._prev is not None:
            t = np.concatenate([[self._prev[0]], t])
            x = np.vstack([self._prev[1][None, :], x])
            if lab is not None:
                lab = np.concatenate([[self._prev[2]], lab])
        if len(t) == 0:
            return self._empty(x, lab)
        j_last = min(self.n_fine - 1, int(np.floor((t[-1] - self.t0) * self.fine_fs + 1e-9)))
        js = np.arange(self._j_next, j_last + 1)
        tf = self.t0 + js / self.fine_fs
        fine = np.column_stack([np.interp(tf, t, x[:, c]) for c in range(x.shape[1])]) if js.size else np.zeros((0, x.shape[1]))
        fine_lab = None
        if lab is not None:
            fine_lab = lab[np.clip(np.searchsorted(t, tf, side="right") - 1, 0, len(t) - 1)]
        self._j_next = j_last + 1
        self._prev = (float(t[-1]), x[-1].copy(), None if lab is None else lab[-1])
        return self._filter(fine, fine_lab, final=False)

    def flush(self) -> tuple[np.ndarray, np.ndarray | None]:
        """The grid samples still held back by the filter (the end of the recording)."""
        return self._filter(
            np.zeros((0, self._width)), None if self._prev is None or self._prev[2] is None else np.zeros(0, dtype=str), final=True
        )

    def _empty(self, x: np.ndarray, lab) -> tuple[np.ndarray, np.ndarray | None]:
        return np.zeros((0, x.shape[1] if x.ndim == 2 else 0)), (None if lab is None else np.asarray(lab)[:0])

    def _filter(self, fine: np.ndarray, fine_lab, *, final: bool) -> tuple[np.ndarray, np.ndarray | None]:
        if self.taps is None:  # k = 1: the fine grid is the grid
            return fine, fine_lab
        if self._hist is None:
            if not len(fine) or final:
                return fine, fine_lab
            self._hist = np.vstack([_odd_pad(fine, self.half, start=True), fine])
            self._hist_j0 = -self.half
            self._lab_hist = None if fine_lab is None else np.concatenate([np.repeat(fine_lab[:1], self.half), fine_lab])
        else:
            self._hist = np.vstack([self._hist, fine])
            if fine_lab is not None and self._lab_hist is not None:
                self._lab_hist = np.concatenate([self._lab_hist, fine_lab])
        if final:
            self._hist = np.vstack([self._hist, _odd_pad(self._hist, self.half, start=False)])
            if self._lab_hist is not None:
                self._lab_hist = np.concatenate([self._lab_hist, np.repeat(self._lab_hist[-1:], self.half)])
        # filtered value at fine index j needs _hist rows j - half .. j + half
        j_hi = self._hist_j0 + len(self._hist) - 1 - self.half  # last fine index with its full right context
        first = self._out_next + (-self._out_next) % self.k  # next multiple of k
        js = np.arange(first, min(j_hi, self.n_fine - 1) + 1, self.k)
        out = np.zeros((len(js), self._hist.shape[1]))
        for c in range(self._hist.shape[1]):
            full = np.convolve(self._hist[:, c], self.taps[::-1], mode="valid")  # full[i] centres on _hist row i + half
            out[:, c] = full[js - self._hist_j0 - self.half] if len(js) else out[:, c]
        out_lab = None
        if self._lab_hist is not None:
            out_lab = self._lab_hist[js - self._hist_j0]
        if len(js):
            self._out_next = int(js[-1]) + 1
        # keep only the context the next output needs: rows from (next output - half)
        keep_from = max(0, self._out_next - self.half - self._hist_j0)
        self._hist = self._hist[keep_from:]
        if self._lab_hist is not None:
            self._lab_hist = self._lab_hist[keep_from:]
        self._hist_j0 += keep_from
        return out, out_lab


def _odd_pad(x: np.ndarray, n: int, *, start: bool) -> np.ndarray:
    """``n`` samples before (``start``) or after ``x`` by odd reflection about its edge sample
    (``2 x[0] - x[n..1]``: a straight-line trend runs on through the edge), or the edge sample
    repeated when ``x`` is shorter than ``n + 1`` samples."""
    if len(x) < n + 1:
        return np.repeat(x[:1] if start else x[-1:], n, axis=0)
    if start:
        return 2 * x[:1] - x[n:0:-1]
    return 2 * x[-1:] - x[-2 : -n - 2 : -1]


def resample_uniform(
    t_s: np.ndarray,
    acc: np.ndarray,
    sampling_rate_hz: float,
    *,
    gyr: np.ndarray | None = None,
    labels: Any = None,
    max_rate_hz: float | None = None,
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """Resample samples at increasing times ``t_s`` onto the uniform grid (see the module docstring).

    ``max_rate_hz`` is the fastest local rate of the timestamps (default: the
    median rate); at ``k >= 2`` times ``sampling_rate_hz`` the anti-alias filter is
    applied before decimation.

    Returns
    -------
    acc, gyr, labels : resampled arrays (gyr and labels None when not given).
    """
    t = np.asarray(t_s, dtype=float)
    n_float = np.floor((t[-1] - t[0]) * sampling_rate_hz + 1e-9) + 1
    if n_float > _MAX_UPSAMPLE * len(t) + 1000:
        raise InputError(
            f"resampling {len(t)} samples at {sampling_rate_hz:g} Hz would make {n_float:.4g} samples "
            f"(more than {_MAX_UPSAMPLE:g}x the original); ask for a lower --sampling-rate-hz."
        )
    if max_rate_hz is None and len(t) > 1:
        max_rate_hz = 1.0 / float(np.median(np.diff(t)))
    x = np.asarray(acc, dtype=float) if gyr is None else np.hstack([np.asarray(acc, dtype=float), np.asarray(gyr, dtype=float)])
    lab = None if labels is None else np.asarray(labels).astype(str)
    rs = UniformResampler(t[0], t[-1], sampling_rate_hz, max_rate_hz=max_rate_hz)
    a, la = rs.push(t, x, lab)
    b, lb = rs.flush()
    out = np.vstack([a, b])
    new_lab = None if lab is None else np.concatenate([la, lb])
    return out[:, :3], (None if gyr is None else out[:, 3:6]), new_lab
