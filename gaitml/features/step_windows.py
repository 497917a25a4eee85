"""Step-synchronous windows: one window per detected step (or stride), features on its own samples.

The time windows of :func:`gaitml.features.make_windows` (paper 003 sec. 3.3: 1.5 s,
fixed length) straddle mode changes and hold two to three steps. Here the step
detectors (and the zero-velocity detectors) are the segmentation front end: every
detected step (``by='steps'``) or stride (``by='strides'``) is one window, classified
on its own samples, so a PDR trajectory gets one mode per step without a
window-to-step lookup.

Spans
-----
``by='steps'`` uses the step *events* of a step detector (:data:`gaitml.steps.DETECTORS`;
every detector reports the acceleration peak at the foot's impact, ``peak``): step
``k`` covers the samples after peak ``k - 1`` up to and including peak ``k``, the
convention of the simulator's labels and of :mod:`gaitml.labels` (``boundary='peak'``),
so consecutive steps tile the walk without gaps or overlaps. The first step reaches
back as far as the second one lasts. A step after a pause would cover the pause:
every span is cut to its last ``max_step_s`` seconds (default 2 s, slower than any
walking cadence).

``by='strides'`` uses a zero-velocity detector (:data:`gaitml.zupt.DETECTORS`) and
:func:`gaitml.zupt.segment_strides`: a stride runs from mid-stance to mid-stance;
strides longer than ``2 * max_step_s`` (across a pause) are dropped. This is meant for
foot-mounted sensors (two steps, one per foot, in a stride).

Labels and features
-------------------
A window's label is the majority label of its samples with its share
(``label_fraction``); windows below ``min_label_fraction`` are dropped and counted, as
for time windows. Spans shorter than :data:`MIN_SPAN_SAMPLES` are dropped (a step
needs 3 samples for the second differences of M4, paper 003 eq. 8).

The 52 features of paper 003 sec. 3.2 are per-window statistics (means, variances,
quantiles, mode, correlations, skewness, kurtosis, M4, f(1)): none needs a fixed
length, so :func:`extract_step_features` computes them on each step's own samples
with the same vectorised extractor as the time windows (steps of equal length are
processed together); a step's features equal those of a time window over the same
samples. Raw-input models (``cnn1d``) need a fixed length: :func:`step_raw_windows`
resamples each span linearly to :data:`RAW_SPAN_SAMPLES` samples (32 for a step,
64 for a stride, about the length of a walking step / stride at 50 Hz).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.errors import InputError

__all__ = [
    "WINDOW_BY",
    "DEFAULT_DETECTORS",
    "MAX_STEP_S",
    "MIN_SPAN_SAMPLES",
    "RAW_SPAN_SAMPLES",
    "check_window_by",
    "spans_from_steps",
    "step_spans",
    "label_spans",
    "make_step_windows",
    "extract_step_features",
    "step_raw_windows",
]

#: Values of the config key ``windows.by``: fixed-length time windows, one window per step, per stride.
WINDOW_BY = ("time", "steps", "strides")
#: Detector used when none is given: a step detector for steps, a zero-velocity detector for strides.
DEFAULT_DETECTORS = {"steps": "single-peak", "strides": "pseudo-std"}
#: Longest step (s); a span after a pause is cut to its last ``MAX_STEP_S`` (strides: twice that, dropped).
MAX_STEP_S = 2.0
#: Shortest span kept (samples): M4 needs second differences.
MIN_SPAN_SAMPLES = 3
#: Fixed length (samples) a span is resampled to for raw-input models.
RAW_SPAN_SAMPLES = {"steps": 32, "strides": 64}


def detector_registry(by: str) -> dict:
    """The registry ``detector`` is looked up in for ``by`` (steps: gaitml.steps, strides: gaitml.zupt)."""
    if by == "steps":
        from gaitml.steps import DETECTORS

        return DETECTORS
    if by == "strides":
        from gaitml.zupt import DETECTORS

        return DETECTORS
    raise InputError(f"windows by {by!r} has no detector; use 'steps' or 'strides'.")


def check_window_by(by: str, detector: str | None) -> str:
    """Check ``by`` and ``detector``; return the detector name (the default one when ``detector`` is empty, '' for time).

    Raises
    ------
    InputError
        ``by`` is not one of :data:`WINDOW_BY`, or ``detector`` is not in the registry
        of ``by`` (a step detector for steps, a zero-velocity detector for strides).
    """
    if by not in WINDOW_BY:
        raise InputError(f"windows by {by!r} is not known; use one of {', '.join(WINDOW_BY)}.")
    if by == "time":
        return ""  # time windows ignore the detector (so a sweep over windows.by can keep one)
    name = detector or DEFAULT_DETECTORS[by]
    reg = detector_registry(by)
    if name not in reg:
        kind = "step detector" if by == "steps" else "zero-velocity detector"
        raise InputError(f"{name!r} is not a {kind} (windows by {by!r}); use one of {', '.join(reg)}.")
    return name


def spans_from_steps(steps: pd.DataFrame, n_samples: int, sampling_rate_hz: float, *, max_step_s: float = MAX_STEP_S) -> pd.DataFrame:
    """Sample spans ``[start, end)`` of the steps of a step table (peak to peak, see the module doc).

    Parameters
    ----------
    steps : DataFrame with ``peak`` (sample index) and ``t_peak_s``, in time order
        (a detector's ``steps_``).
    n_samples : int, the recording's length.
    sampling_rate_hz : float
    max_step_s : float, longest span in s (the span keeps its last ``max_step_s``).

    Returns
    -------
    DataFrame
        One row per step of ``steps`` (same order): ``step`` (row in ``steps``),
        ``start``, ``end`` (samples, end exclusive), ``t_start_s``, ``t_end_s``,
        ``t_event_s`` (the step's peak time).
    """
    if "peak" not in steps:
        raise InputError(f"the step table needs a 'peak' column, got {list(steps.columns)}; pass a step detector's steps_.")
    peak = steps["peak"].to_numpy(dtype=np.int64)
    if len(peak) > 1 and np.any(np.diff(peak) < 0):
        raise InputError("the step table is not in time order; sort it by peak.")
    fs = float(sampling_rate_hz)
    end = np.clip(peak + 1, 1, n_samples)
    cap = max(int(round(max_step_s * fs)), MIN_SPAN_SAMPLES)
    if len(peak) == 0:
        start = np.zeros(0, dtype=np.int64)
    else:
        first = end[0] - (end[1] - end[0] if len(end) > 1 else cap)
        start = np.concatenate([[first], end[:-1]])
        start = np.clip(np.maximum(start, end - cap), 0, n_samples)
    t_event = steps["t_peak_s"].to_numpy(float) if "t_peak_s" in steps else peak / fs
    return pd.DataFrame(
        {"step": np.arange(len(peak)), "start": start, "end": end, "t_start_s": start / fs, "t_end_s": end / fs, "t_event_s": t_event}
    )


def step_spans(recording, by: str = "steps", detector: str | None = None, *, max_step_s: float = MAX_STEP_S) -> pd.DataFrame:
    """Detect the steps (or strides) of ``recording`` and return their sample spans.

    Returns
    -------
    DataFrame
        As :func:`spans_from_steps` (for strides ``t_event_s`` is the stride start);
        ``attrs``: ``by``, ``detector``, ``n_detected``.
    """
    name = check_window_by(by, detector)
    if by == "time":
        raise InputError("step_spans needs by 'steps' or 'strides'; time windows come from gaitml.features.make_windows.")
    fs = float(recording.sampling_rate_hz)
    n = recording.n_samples
    if by == "steps":
        from gaitml.steps import get_detector

        steps = get_detector(name).detect(recording).steps_
        spans = spans_from_steps(steps, n, fs, max_step_s=max_step_s)
    else:
        from gaitml.zupt import get_detector, segment_strides

        recording.require_gyr(
            f"stride windows (zero-velocity detector {name!r})", "use windows by 'steps' for recordings without a gyroscope"
        )
        zupts = get_detector(name).detect(recording).zupts_
        strides = segment_strides(zupts, fs, max_stride_s=2.0 * max_step_s)
        start = np.clip(strides["start"].to_numpy(dtype=np.int64), 0, n)
        end = np.clip(strides["end"].to_numpy(dtype=np.int64), 0, n)
        spans = pd.DataFrame(
            {
                "step": np.arange(len(start)),
                "start": start,
                "end": end,
                "t_start_s": start / fs,
                "t_end_s": end / fs,
                "t_event_s": start / fs,
            }
        )
    spans.attrs.update(by=by, detector=name, n_detected=int(len(spans)))
    return spans


def label_spans(labels, spans: pd.DataFrame) -> tuple[np.ndarray, np.ndarray]:
    """Majority label of every span ``[start, end)`` and its share (ties: the label that sorts first)."""
    lab = np.asarray(labels)
    start = spans["start"].to_numpy(dtype=np.int64)
    end = spans["end"].to_numpy(dtype=np.int64)
    uniq, codes = np.unique(lab.astype(str), return_inverse=True)
    counts = np.empty((len(start), len(uniq)), dtype=np.int64)
    cum = np.zeros(len(lab) + 1, dtype=np.int64)
    for k in range(len(uniq)):
        np.cumsum(codes == k, out=cum[1:])
        counts[:, k] = cum[end] - cum[start]
    best = np.argmax(counts, axis=1) if len(start) else np.zeros(0, dtype=np.int64)
    frac = counts[np.arange(len(best)), best] / np.maximum(end - start, 1) if len(start) else np.zeros(0)
    return uniq[best].astype(object), frac


def make_step_windows(
    recording,
    by: str = "steps",
    detector: str | None = None,
    *,
    min_label_fraction: float = 0.5,
    spans: pd.DataFrame | None = None,
    max_step_s: float = MAX_STEP_S,
) -> pd.DataFrame:
    """One window per detected step (or stride) of ``recording``, with majority labels.

    Parameters
    ----------
    recording : Recording
    by : {'steps', 'strides'}
    detector : str, optional
        Step detector (steps; default ``single-peak``) or zero-velocity detector
        (strides; default ``pseudo-std``).
    min_label_fraction : float
        With per-sample labels, windows whose majority label covers less than this
        share of the span are dropped (and counted); 0 keeps all.
    spans : DataFrame, optional
        Spans already found (:func:`step_spans` / :func:`spans_from_steps`); then no
        detector runs.
    max_step_s : float
        Longest step span in s (see the module doc).

    Returns
    -------
    DataFrame
        One row per kept window: ``step`` (index of the detected step/stride),
        ``start``, ``end`` (samples, end exclusive), ``t_start_s``, ``t_end_s``,
        ``t_event_s``, and with labels ``label``, ``label_fraction``. ``attrs``:
        ``by``, ``detector``, ``n_total``, ``n_dropped`` (weak majority), ``n_short``
        (spans under :data:`MIN_SPAN_SAMPLES`), ``sampling_rate_hz``,
        ``min_label_fraction``.
    """
    if not 0.0 <= float(min_label_fraction) <= 1.0:
        raise InputError(f"`min_label_fraction` must be in [0, 1], got {min_label_fraction}; e.g. 0.5 keeps steps with a clear majority.")
    if spans is None:
        spans = step_spans(recording, by, detector, max_step_s=max_step_s)
    else:
        detector = check_window_by(by, detector) if by != "time" else detector
    w = spans.copy()
    long_enough = (w["end"] - w["start"]).to_numpy() >= MIN_SPAN_SAMPLES
    n_short = int((~long_enough).sum())
    w = w.loc[long_enough].reset_index(drop=True)
    n_total = len(w)
    if recording.labels is not None and len(w):
        lab, frac = label_spans(recording.labels, w)
        w["label"] = lab
        w["label_fraction"] = frac
        w = w.loc[w["label_fraction"].to_numpy() >= float(min_label_fraction)].reset_index(drop=True)
    elif recording.labels is not None:
        w["label"] = pd.Series(dtype=object)
        w["label_fraction"] = pd.Series(dtype=float)
    w.attrs.update(
        by=by,
        detector=spans.attrs.get("detector", detector),
        n_total=int(n_total),
        n_dropped=int(n_total - len(w)),
        n_short=n_short,
        sampling_rate_hz=float(recording.sampling_rate_hz),
        min_label_fraction=float(min_label_fraction),
    )
    return w


def extract_step_features(recording, windows: pd.DataFrame, *, subset: str = "all52") -> pd.DataFrame:
    """Feature table of variable-length windows: the 52 features of each window's own samples.

    Windows of equal length go through :func:`gaitml.features.features_from_arrays`
    together, so a window gets exactly the values a time window over the same
    samples gets (paper 003 sec. 3.2; no feature needs a fixed length).

    Returns
    -------
    DataFrame
        Index = ``windows.index``, columns :func:`gaitml.features.feature_names`.
    """
    from gaitml.features._catalogue import feature_names, resolve_subset, uses_gyro
    from gaitml.features._extract import features_from_arrays

    key = resolve_subset(subset)
    names = feature_names(key)
    gyr = recording.require_gyr(f"feature subset {key!r}") if uses_gyro(key) else None
    starts = windows["start"].to_numpy(dtype=np.int64)
    lengths = windows["end"].to_numpy(dtype=np.int64) - starts
    out = np.zeros((len(starts), len(names)))
    if len(starts) and lengths.min() < MIN_SPAN_SAMPLES:
        raise InputError(
            f"a window has {lengths.min()} samples; step windows need at least {MIN_SPAN_SAMPLES} (make_step_windows drops shorter ones)."
        )
    for length in np.unique(lengths):
        rows = np.flatnonzero(lengths == length)
        out[rows] = features_from_arrays(recording.acc, gyr, recording.sampling_rate_hz, starts[rows], int(length), key)
    df = pd.DataFrame(out, columns=names, index=windows.index)
    df.attrs.update(dict(windows.attrs), subset=key)
    return df


def step_raw_windows(signal: np.ndarray, windows: pd.DataFrame, length_samples: int) -> np.ndarray:
    """Each window's samples of ``signal`` (n, channels) linearly resampled to ``length_samples``.

    The first and last sample of a span are kept; the points in between are equally
    spaced over the span (linear interpolation between neighbouring samples).

    Returns
    -------
    ndarray, shape (n_windows, length_samples, channels)
    """
    sig = np.asarray(signal, dtype=float)
    starts = windows["start"].to_numpy(dtype=np.int64)
    ends = windows["end"].to_numpy(dtype=np.int64)
    if len(starts) == 0:
        return np.zeros((0, int(length_samples), sig.shape[1]))
    pos = starts[:, None] + (ends - 1 - starts)[:, None] * np.linspace(0.0, 1.0, int(length_samples))[None, :]
    lo = np.floor(pos).astype(np.int64)
    hi = np.minimum(lo + 1, len(sig) - 1)
    frac = (pos - lo)[..., None]
    return sig[lo] * (1.0 - frac) + sig[hi] * frac
