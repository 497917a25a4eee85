"""The common API of the zero-velocity detectors (gaitmap-style; see STYLE.md).

A detector stores its parameters in ``__init__``; ``detect(recording)`` sets
``per_sample_zupts_`` (bool, shape (n,)), ``zupts_`` (interval table ``start``,
``end`` exclusive, ``t_start_s``, ``t_end_s``) and ``statistic_`` (the per-sample
test statistic the threshold is applied to, where there is a single one) and
returns ``self``. ``fit(recordings, reference)`` learns the threshold(s) from
labelled zero-velocity samples where the detector has a learnable threshold.
"""

from __future__ import annotations

import numpy as np

from gaitml._base import BaseAlgorithm
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.zupt._intervals import apply_blockwise, half_window_samples, intervals_table

__all__ = [
    "BaseZuptDetector",
    "FixedThresholdZuptDetector",
    "MIN_RECORDING_S",
    "REFERENCE_HALF_WIDTH_S",
    "empirical_upper_threshold",
    "labelled_samples",
    "reference_zupt_mask",
]

#: Half-width of the labelled zero-velocity neighbourhood around a motion-capture
#: ``min_vel`` sample (s). The gaitmap reference marks one mid-stance sample of
#: minimum foot velocity per stride; +-50 ms around it is well inside foot-flat at
#: walking speed (stance lasts about 0.6 s, foot-flat about 0.3 s).
REFERENCE_HALF_WIDTH_S = 0.05

#: Shortest recording a detector accepts (s), besides one full detector window: a
#: zero-velocity interval of a walking foot lasts ~0.1-0.3 s, so shorter input cannot
#: show both motion and rest, and a "100 % stationary" answer on it means nothing.
MIN_RECORDING_S = 0.5


def reference_zupt_mask(recording: Recording, *, half_width_s: float = REFERENCE_HALF_WIDTH_S) -> np.ndarray:
    """Per-sample zero-velocity labels from the recording's reference events.

    Samples within ``half_width_s`` of each ``min_vel`` sample
    (``reference['stride_events']['min_vel']`` or ``reference['min_vel_t_s']``)
    are labelled zero velocity; every other sample is *unlabelled* (False here).
    Use it for ``fit``, not as a full per-sample truth.

    Raises
    ------
    InputError
        If the recording has no ``min_vel`` reference.
    """
    fs = recording.sampling_rate_hz
    ref = recording.reference
    if "stride_events" in ref and "min_vel" in ref["stride_events"]:
        idx = np.asarray(ref["stride_events"]["min_vel"], dtype=float)
    elif "min_vel_t_s" in ref:
        idx = np.asarray(ref["min_vel_t_s"], dtype=float) * fs
    else:
        raise InputError(
            f"recording {recording.name!r} has no zero-velocity reference (reference['stride_events'] or "
            "reference['min_vel_t_s']); pass per-sample labels to fit(recordings, reference=[mask, ...])."
        )
    idx = np.round(idx).astype(np.int64)
    h = max(0, int(round(half_width_s * fs)))
    mask = np.zeros(recording.n_samples, dtype=bool)
    lo = np.clip(idx - h, 0, recording.n_samples)
    hi = np.clip(idx + h + 1, 0, recording.n_samples)
    d = np.zeros(recording.n_samples + 1, dtype=np.int64)
    np.add.at(d, lo, 1)
    np.add.at(d, hi, -1)
    mask |= np.cumsum(d[:-1]) > 0
    return mask


def labelled_samples(recordings, reference) -> list[tuple[Recording, np.ndarray]]:
    """Pair each recording with a boolean zero-velocity label mask (see ``fit``)."""
    if isinstance(recordings, Recording):
        recordings = [recordings]
    recs = list(recordings)
    if not recs:
        raise InputError("fit needs at least one recording; pass a list of Recording objects.")
    if reference is None:
        masks = [reference_zupt_mask(r) for r in recs]
    else:
        if isinstance(reference, np.ndarray) and reference.ndim == 1 and len(recs) == 1:
            reference = [reference]
        masks = [np.asarray(m, dtype=bool) for m in reference]
        if len(masks) != len(recs):
            raise InputError(f"fit got {len(recs)} recordings but {len(masks)} reference masks; pass one mask per recording.")
    for r, m in zip(recs, masks, strict=True):
        if m.shape != (r.n_samples,):
            raise InputError(f"reference mask of {r.name!r} has shape {m.shape}, expected ({r.n_samples},); pass one bool per sample.")
    if sum(int(m.sum()) for m in masks) < 2:
        raise InputError("fit needs at least 2 labelled zero-velocity samples; check the reference masks.")
    return list(zip(recs, masks, strict=True))


class BaseZuptDetector(BaseAlgorithm):
    """Base class: ``detect`` runs ``_mask(recording)`` and builds the interval table (results ``zupts_``, ``per_sample_zupts_``)."""

    _action_method = "detect"
    #: registry name (DESIGN sec. 5)
    name: str = ""

    def _mask(self, recording: Recording) -> tuple[np.ndarray, np.ndarray | None]:  # pragma: no cover - abstract
        raise NotImplementedError

    def _window_samples(self, sampling_rate_hz: float) -> int:
        """Samples of one full detector window (validates the window parameters)."""
        return 1

    def min_samples(self, sampling_rate_hz: float) -> int:
        """Fewest samples ``detect`` accepts: one full window and ``MIN_RECORDING_S``."""
        return max(int(self._window_samples(sampling_rate_hz)), int(np.ceil(MIN_RECORDING_S * sampling_rate_hz - 1e-9)))

    def detect(self, recording: Recording):
        """Detect zero-velocity samples and intervals; returns ``self``.

        Sets ``per_sample_zupts_`` (bool, shape (n,)), ``zupts_`` (DataFrame
        ``start``, ``end`` exclusive, ``t_start_s``, ``t_end_s``), ``statistic_``
        (the thresholded per-sample statistic, or None) and ``sampling_rate_hz_``.
        """
        self._validate_params()
        if not isinstance(recording, Recording):
            raise InputError(f"detect needs a gaitml Recording, got {type(recording).__name__}; read files with gaitml.io.read_recording.")
        n_min = self.min_samples(recording.sampling_rate_hz)
        if recording.n_samples < n_min:
            raise InputError(
                f"the recording is too short for the {self.name or type(self).__name__} detector: {recording.n_samples} samples "
                f"< {n_min} needed (one detector window and at least {MIN_RECORDING_S:g} s); use a longer recording."
            )
        mask, stat = self._mask(recording)
        self.per_sample_zupts_ = np.asarray(mask, dtype=bool)
        self.statistic_ = stat
        self.sampling_rate_hz_ = recording.sampling_rate_hz
        self.zupts_ = intervals_table(self.per_sample_zupts_, recording.sampling_rate_hz)
        return self


class FixedThresholdZuptDetector(BaseZuptDetector):
    """Base of the fixed-threshold detectors (paper 001's methods 1 and 2).

    Their parameters are ``half_window_s`` and the keyword thresholds of a per-sample
    function ``zupts(acc, gyr, s, **thresholds)`` over the centred window ``[i - s, i + s]``.
    """

    _positive = ("half_window_s",)

    def _window_samples(self, sampling_rate_hz: float) -> int:
        return 2 * half_window_samples(self.half_window_s, sampling_rate_hz) + 1

    def _thresholded(self, recording: Recording, needs: str, zupts):
        """``zupts`` over the whole recording (block-wise) with this detector's thresholds, and the gyro.

        ``needs`` names the detector in the error of a recording without a gyroscope.
        """
        gyr = recording.require_gyr(needs)
        thresholds = self.get_params()
        s = half_window_samples(thresholds.pop("half_window_s"), recording.sampling_rate_hz)
        return apply_blockwise(lambda a, w: zupts(a, w, s, **thresholds), (recording.acc, gyr), s), gyr


def empirical_upper_threshold(values: np.ndarray, eps: float) -> float:
    """The ``1 - eps`` quantile of ``values`` (nonparametric Neyman-Pearson threshold)."""
    if not 0 < eps < 1:
        raise InputError(f"`eps` must be in (0, 1), got {eps!r}.")
    return float(np.quantile(np.asarray(values, dtype=float), 1.0 - eps))
