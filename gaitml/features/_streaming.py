"""Streaming feature extraction: samples in as they arrive, one feature row per completed window."""

from __future__ import annotations

import numpy as np

from gaitml.errors import InputError
from gaitml.features._catalogue import feature_names, resolve_subset, uses_forward, uses_gyro
from gaitml.features._extract import features_from_arrays
from gaitml.features._forward import check_forward_window
from gaitml.features._frame import check_frame
from gaitml.features._range import acc_range_tally, check_acc_range, clip_acc
from gaitml.features._windows import WINDOW_LENGTH_S, WINDOW_OVERLAP
from gaitml.signal import window_params

__all__ = ["StreamingFeatureExtractor"]


def _chunk(name: str, x) -> np.ndarray:
    arr = np.asarray(x, dtype=float)
    if arr.ndim == 1 and arr.shape == (3,):
        arr = arr.reshape(1, 3)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise InputError(f"`{name}` chunk must have shape (k, 3) or (3,), got {arr.shape}.")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"`{name}` chunk has NaN/inf values; interpolate or drop them before pushing.")
    return arr


class StreamingFeatureExtractor:
    """Feature rows of consecutive windows computed while samples arrive.

    The windows are those of :func:`gaitml.features.make_windows` with the same
    ``length_s``/``overlap`` (starts 0, hop, 2 hop, ...) and each row equals the
    batch :func:`gaitml.features.extract_features` row (the same vectorised code
    runs on the buffered samples; a window's features depend on its own samples
    only, see :mod:`gaitml.features._catalogue`). Only the samples of windows not
    yet completed are kept (at most ``length`` + chunk size).

    Parameters
    ----------
    sampling_rate_hz : float
    length_s : float
        Window length in s (paper 003 sec. 3.3: 1.5 s).
    overlap : float
        Fraction shared by consecutive windows, in [0, 1).
    subset : str
        ``'all52'``, ``'paper34'``, ``'all52+gyro'`` (then ``push`` needs gyro chunks), or the
        opt-in ``'all52+fwd'`` / ``'all52+gyro+fwd'`` (the forward vector of each window, from its own samples).
    frame : {'phone', 'gravity'}
        Feature frame, as in :func:`gaitml.features.extract_features` (the gravity
        frame of a window depends on the window's own samples, so the rows still
        equal the batch rows).
    acc_range_ms2 : float, optional
        The accelerometer range the model reads every phone through
        (:mod:`gaitml.features._range`; a model's ``acc_range_ms2``): each pushed
        acceleration sample is clipped to +-this per axis before its features, as the
        whole-file path does. None (default) or 0: no range. :meth:`for_model` sets it.

    Attributes
    ----------
    feature_names_ : list of str
    length_samples_, hop_samples_ : int
    n_samples_ : int
        Samples pushed so far.
    n_windows_ : int
        Rows emitted so far.
    last_starts_ : ndarray of int
        Start sample indices (from the first pushed sample) of the rows returned
        by the latest ``push``.
    n_clipped_ : int
        Pushed samples with an axis beyond ``acc_range_ms2`` (0 without a range).
    """

    def __init__(
        self,
        sampling_rate_hz: float,
        length_s: float = WINDOW_LENGTH_S,
        overlap: float = WINDOW_OVERLAP,
        subset: str = "all52",
        frame: str = "phone",
        acc_range_ms2: float | None = None,
    ):
        self.sampling_rate_hz = sampling_rate_hz
        self.length_s = length_s
        self.overlap = overlap
        self.subset = subset
        self.frame = frame
        self.acc_range_ms2 = acc_range_ms2
        self._range = check_acc_range(acc_range_ms2)
        self._subset = resolve_subset(subset)
        check_frame(frame)
        self.length_samples_, self.hop_samples_ = window_params(length_s, overlap, float(sampling_rate_hz))
        if uses_forward(self._subset):  # as extract_features: a window too short for the forward vector's band is refused
            check_forward_window(self.length_samples_, float(sampling_rate_hz))
        self.feature_names_ = feature_names(self._subset)
        self.rate_reason_: str | None = None  # the model's rate check (for_model with recorded_hz)
        self.reset()

    @classmethod
    def for_model(cls, model, recorded_hz: float | None = None) -> StreamingFeatureExtractor:
        """The extractor of a saved time-window feature model: its rate, window, feature set, frame and accelerometer range.

        ``recorded_hz``: the rate the stream's phone records at (its samples are resampled to the
        model's rate before they are pushed). ``rate_reason_`` is then the model's rate check
        (``model.rate_reason``, :func:`gaitml.models.rate_reason`): a reason string when the phone records below the
        rates the model was trained at (every window of the stream is then out of domain, as
        ``gaitml predict`` marks them), ``""`` when not, None when not checked (no rate given, or a
        model without the record).
        """
        ext = cls(
            model.sampling_rate_hz,
            model.length_s,
            model.overlap,
            model.feature_set,
            frame=getattr(model, "frame", "phone"),
            acc_range_ms2=getattr(model, "acc_range_ms2", None),
        )
        # the model's own method (gaitml.models.TrainedModel.rate_reason): this layer does not import the models
        check = getattr(model, "rate_reason", None)
        ext.rate_reason_ = check(recorded_hz) if callable(check) and recorded_hz is not None else None
        return ext

    @classmethod
    def for_domain(cls, model) -> StreamingFeatureExtractor:
        """The extractor of a saved time-window model's domain check: its rate and window, the domain record's feature set and frame,
        and the accelerometer range the record reads through (its own ``acc_range_ms2``, else the model's).

        Its rows (with :func:`gaitml.models.domain.feature_gravity` of them) are what
        ``model.domain.check`` reads for a stream; they equal :meth:`for_model`'s rows when the record
        reads the model's own features through the model's range.
        """
        dom = getattr(model, "domain", None)
        if dom is None:
            raise InputError("this model has no domain record (it was saved without one); a stream cannot check its domain.")
        r = getattr(dom, "acc_range_ms2", None)
        return cls(
            model.sampling_rate_hz,
            model.length_s,
            model.overlap,
            dom.feature_set,
            frame=dom.frame,
            acc_range_ms2=r if r is not None else getattr(model, "acc_range_ms2", None),
        )

    def reset(self) -> StreamingFeatureExtractor:
        """Forget all buffered samples; the next push starts a new stream."""
        self._acc = np.zeros((0, 3))
        self._gyr = np.zeros((0, 3))
        self._buf_start = 0  # absolute index of self._acc[0]
        self._next_start = 0  # absolute start of the next window to emit
        self.n_samples_ = 0
        self.n_windows_ = 0
        self.last_starts_ = np.zeros(0, dtype=np.int64)
        self.n_clipped_ = 0
        return self

    def push(self, acc_chunk, gyr_chunk=None) -> np.ndarray:
        """Append samples; return the feature rows of the windows they complete.

        Parameters
        ----------
        acc_chunk : array, shape (k, 3) or (3,)
            New acceleration samples in m/s^2 (k may be 0).
        gyr_chunk : array, shape (k, 3), optional
            New angular-rate samples in rad/s; required for ``'all52+gyro'`` and ``'all52+gyro+fwd'``.

        Returns
        -------
        ndarray, shape (n_completed, n_features)
            Possibly zero rows.
        """
        acc = _chunk("acc", acc_chunk)
        if self._range is not None:
            self.n_clipped_ += acc_range_tally(acc, self._range)["n_samples_clipped"]
            acc = clip_acc(acc, self._range)
        need_gyr = uses_gyro(self._subset)
        if need_gyr:
            if gyr_chunk is None:
                raise InputError(
                    f"feature subset {self._subset!r} needs a gyroscope; pass gyr_chunk with each acc_chunk or use subset 'all52'."
                )
            gyr = _chunk("gyr", gyr_chunk)
            if len(gyr) != len(acc):
                raise InputError(f"gyr_chunk has {len(gyr)} samples but acc_chunk has {len(acc)}; they must match.")
            self._gyr = np.concatenate([self._gyr, gyr]) if len(self._gyr) else gyr
        self._acc = np.concatenate([self._acc, acc]) if len(self._acc) else acc
        self.n_samples_ += len(acc)
        length, hop = self.length_samples_, self.hop_samples_
        end = self._buf_start + len(self._acc)
        n_new = 0 if end < self._next_start + length else (end - length - self._next_start) // hop + 1
        if n_new <= 0:
            self.last_starts_ = np.zeros(0, dtype=np.int64)
            return np.zeros((0, len(self.feature_names_)))
        abs_starts = self._next_start + hop * np.arange(n_new, dtype=np.int64)
        rel = abs_starts - self._buf_start
        rows = features_from_arrays(
            self._acc, self._gyr if need_gyr else None, self.sampling_rate_hz, rel, length, self._subset, self.frame
        )
        self._next_start = int(abs_starts[-1] + hop)
        drop = min(self._next_start - self._buf_start, len(self._acc))
        self._acc = self._acc[drop:].copy()
        if need_gyr:
            self._gyr = self._gyr[drop:].copy()
        self._buf_start += drop
        self.n_windows_ += n_new
        self.last_starts_ = abs_starts
        return rows
