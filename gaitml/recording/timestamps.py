"""Timestamps of a recording: increasing times, a plausible rate, gaps to bridge or cut.

:func:`check_timed_samples` checks shapes, finiteness and strictly increasing
times; :func:`check_rate` refuses a rate no gait recording has;
:func:`max_bridge_s` and :func:`split_points` say which intervals are gaps too
long to bridge by interpolation.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitml.errors import InputError
from gaitml.recording.ranges import as_2d3, check_finite

__all__ = [
    "check_rate",
    "check_timed_samples",
    "check_increasing",
    "judge_rate",
    "judge_timestamps",
    "local_rates",
    "recorded_rate_hz",
    "RATE_TOLERANCE",
    "max_bridge_s",
    "split_points",
    "MIN_RATE_HZ",
    "MAX_RATE_HZ",
    "GAP_FACTOR",
    "MAX_BRIDGE_S",
    "MAX_BRIDGE_FACTOR",
]

#: Plausible uniform sampling rates for gait (steps at up to ~4 Hz need >= 5 Hz).
MIN_RATE_HZ = 5.0
MAX_RATE_HZ = 10_000.0
#: A sampling interval more than this many times the median counts as a gap
#: (reported in ``meta['gaps']``).
GAP_FACTOR = 3.0
#: Gaps are bridged by linear interpolation only up to
#: ``max(MAX_BRIDGE_S, MAX_BRIDGE_FACTOR x median interval)`` (see :func:`max_bridge_s`).
#: 1 s is about one stride (two steps) at a normal cadence, so a bridged gap hides
#: at most one stride of made-up straight-line signal; the relative bound keeps
#: the ordinary jitter of a slow logger (5-20 Hz) from counting as a gap to refuse.
#: A longer gap is refused (or, on request, the recording is cut there): bridging
#: it would invent minutes of signal (and a 10^7 s gap would allocate gigabytes).
MAX_BRIDGE_S = 1.0
MAX_BRIDGE_FACTOR = 10.0
#: The rate is judged on stretches of this many intervals (:func:`local_rates`): long enough
#: to average the rounding of millisecond timestamps, short enough to place a rate change.
RATE_STRETCH_INTERVALS = 1000
#: Timestamps whose intervals take at most this many distinct values (to 1 ns), at most half the
#: median interval apart, are quantised (a clock with a coarse resolution, e.g. whole milliseconds) ...
QUANTISED_LEVELS = 8
#: ... counted among this many intervals spread over the samples at the file's main rate.
QUANTISED_SAMPLE = 100_000
#: ... and when the median interval's rate and the stretch rate then disagree by more than
#: this fraction, the stretch rate is the rate (:func:`judge_rate`). 1 %: a clock in whole ms
#: puts the median interval's rate 2 % off at 60 Hz (17 ms) and 5 % off at 150 Hz (7 ms).
QUANTISED_TOLERANCE = 0.01
#: A part of a file at a faster rate than most of its time sets the file's rate (the rate it is resampled to,
#: so that no part loses its signal) when it lasts at least this share of the file's time (:func:`judge_rate`):
#: a quarter, so that a screen-on burst (a fifth of a day file at twice the rate) does not double every sample.
FAST_PART_MIN_SHARE = 0.25
#: A stretch whose rate differs from the file's by more than this fraction is a rate change ...
RATE_CHANGE_TOLERANCE = 0.2
#: ... when it lasts at least this long (s).
RATE_CHANGE_MIN_S = 1.0


def max_bridge_s(median_interval_s: float) -> float:
    """The longest sampling interval (s) that resampling may bridge by interpolation.

    ``max(MAX_BRIDGE_S, MAX_BRIDGE_FACTOR * median_interval_s)``: one stride, or
    ten of the recording's own sampling intervals when those are longer.
    """
    return max(MAX_BRIDGE_S, MAX_BRIDGE_FACTOR * float(median_interval_s))


def split_points(t_s: np.ndarray, limit_s: float | None = None) -> np.ndarray:
    """Indices ``i`` where the interval ``t_s[i] -> t_s[i + 1]`` is longer than the bridge limit.

    ``limit_s`` defaults to :func:`max_bridge_s` of the median interval.
    """
    t = np.asarray(t_s, dtype=float)
    if len(t) < 2:
        return np.zeros(0, dtype=int)
    dt = np.diff(t)
    lim = max_bridge_s(float(np.median(dt))) if limit_s is None else float(limit_s)
    return np.flatnonzero(dt > lim)


def check_rate(fs: float, *, what: str = "the sampling rate") -> None:
    """Raise InputError unless ``fs`` is a plausible sampling rate (MIN_RATE_HZ..MAX_RATE_HZ)."""
    if not np.isfinite(fs) or fs <= 0:
        raise InputError(f"{what} must be a positive number of Hz, got {fs!r}.")
    if fs < MIN_RATE_HZ * (1 - 1e-6):
        raise InputError(
            f"{what} is {fs:.4g} Hz, too low for gait (>= {MIN_RATE_HZ:g} Hz needed); "
            "if the time column is in ms or ns, convert it to seconds."
        )
    if fs > MAX_RATE_HZ * (1 + 1e-6):
        raise InputError(
            f"{what} is {fs:.4g} Hz, above {MAX_RATE_HZ:g} Hz; if the time column is not in seconds convert it, "
            "or ask for a lower --sampling-rate-hz."
        )


def check_timed_samples(t_s: Any, acc: Any, gyr: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Shapes, finiteness and strictly increasing times of timestamped samples."""
    t = np.asarray(t_s, dtype=float)
    if t.ndim != 1:
        raise InputError(f"timestamps must be 1-D, got shape {t.shape}.")
    acc = as_2d3("acc", acc)
    if len(acc) != len(t):
        raise InputError(f"{len(t)} timestamps but {len(acc)} acc samples; they must match.")
    if len(t) < 2:
        raise InputError(f"need at least 2 timestamped samples to find the sampling rate, got {len(t)}; use a longer recording.")
    check_finite("t", t)
    check_finite("acc", acc)
    gyr_arr = None if gyr is None else as_2d3("gyr", gyr)
    if gyr_arr is not None:
        if len(gyr_arr) != len(t):
            raise InputError(f"{len(t)} timestamps but {len(gyr_arr)} gyr samples; they must match.")
        check_finite("gyr", gyr_arr)
    check_increasing(t)
    return t, acc, gyr_arr


def check_increasing(t: np.ndarray) -> None:
    """Raise InputError on duplicate or decreasing timestamps (first offending sample and a fix)."""
    dt = np.diff(t)
    if (dt == 0).any():
        i = int(np.flatnonzero(dt == 0)[0]) + 1
        raise InputError(
            f"duplicate timestamp {t[i]:.9g} s at sample {i} ({int((dt == 0).sum())} in all); "
            "remove duplicated rows or give each sample its own time."
        )
    if (dt < 0).any():
        i = int(np.flatnonzero(dt < 0)[0]) + 1
        raise InputError(f"timestamps decrease at sample {i} ({t[i - 1]:.9g} -> {t[i]:.9g} s); sort the rows by time or fix the clock.")
    if not np.isfinite(dt).all():
        raise InputError("the timestamps span more than the float range; check the time column's unit.")


def local_rates(t: np.ndarray, *, stretch: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Rates of consecutive stretches of ``stretch`` intervals: ``(start times, rates in Hz)``.

    Each stretch's rate is its number of intervals over its duration, gaps
    left out: the mean rate, which quantised timestamps (400 Hz logged in whole
    milliseconds: 2, 3, 2, 3 ms) still give right where the median interval does
    not. A gap is an interval over :data:`GAP_FACTOR` x the file's median interval,
    or, in a stretch where such intervals take most of the time and number at least
    :data:`RATE_CHANGE_MIN_S` x :data:`MIN_RATE_HZ` (a slower rate, not gaps), over
    :data:`GAP_FACTOR` x the stretch's own time-weighted median.
    ``stretch`` defaults to :data:`RATE_STRETCH_INTERVALS`.
    """
    t = np.asarray(t, dtype=float)
    starts, rates, _ = _local_rates(t, np.diff(t), None, stretch)
    return starts, rates


def _local_rates(t: np.ndarray, dt: np.ndarray, med: float | None, stretch: int | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`local_rates` from the intervals ``dt`` (and their median) already computed, with each stretch's
    duration without its gaps (s) as a third array; no copy of ``dt``."""
    w = int(stretch or RATE_STRETCH_INTERVALS)
    if len(dt) == 0:
        return np.zeros(0), np.zeros(0), np.zeros(0)
    med = float(np.median(dt)) if med is None else med
    n = len(dt) // w if len(dt) >= w else 1
    w_eff = len(dt) // n
    blocks = dt[: n * w_eff].reshape(n, w_eff)
    d = blocks.sum(axis=1)
    c = np.full(n, float(w_eff))
    gaps = np.flatnonzero(dt[: n * w_eff] > GAP_FACTOR * med)
    np.subtract.at(d, gaps // w_eff, dt[gaps])
    np.subtract.at(c, gaps // w_eff, 1.0)
    # "gaps" take most of a stretch's time and are many (a rate change lasts at least RATE_CHANGE_MIN_S,
    # so at least RATE_CHANGE_MIN_S x MIN_RATE_HZ intervals): they are a slower rate's samples; judge its
    # gaps against its own time-weighted median interval
    total = blocks.sum(axis=1)
    slow = np.flatnonzero((d < 0.5 * total) & (w_eff - c >= RATE_CHANGE_MIN_S * MIN_RATE_HZ))
    if slow.size:
        srt = np.sort(blocks[slow], axis=1)
        half = (np.cumsum(srt, axis=1) < 0.5 * total[slow, None]).sum(axis=1)
        own = srt <= GAP_FACTOR * srt[np.arange(slow.size), half][:, None]
        d[slow], c[slow] = np.where(own, srt, 0.0).sum(axis=1), own.sum(axis=1).astype(float)
    with np.errstate(divide="ignore", invalid="ignore"):
        rates = np.where(d > 0, c / d, np.nan)
    return t[: n * w_eff : w_eff], rates, d


def _split_point(d: np.ndarray) -> int:
    """Where the intervals ``d`` change level: the ``k`` (0..len) that leaves the least squared deviation
    of ``d[:k]`` and ``d[k:]`` from their own means (a single change point by least squares)."""
    n = len(d)
    s1 = np.concatenate([[0.0], np.cumsum(d)])
    s2 = np.concatenate([[0.0], np.cumsum(d * d)])
    k = np.arange(n + 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        left = s2[k] - np.where(k > 0, s1[k] ** 2 / k, 0.0)
        right = (s2[n] - s2[k]) - np.where(k < n, (s1[n] - s1[k]) ** 2 / (n - k), 0.0)
    return int(np.argmin(left + right))


def _change_span(t: np.ndarray, dt: np.ndarray, med: float, w: int, n: int, i: int, j: int) -> tuple[int, int]:
    """The samples where a rate change found in stretches ``i..j`` (of ``n`` stretches of ``w`` intervals) starts and ends.

    A stretch's rate only says that the change covers part of it; each edge is placed at the change point
    (:func:`_split_point`) of the intervals of the two stretches around it (the last unchanged one and the
    first changed one; gaps clipped to :data:`GAP_FACTOR` x the median). A run at the file's first or last
    stretch starts at the first or ends at the last sample.
    """
    d = np.minimum(dt, GAP_FACTOR * med)
    start = 0 if i == 0 else (i - 1) * w + _split_point(d[(i - 1) * w : (i + 1) * w])
    if j == n - 1:
        end = len(t) - 1
    else:
        hi = len(dt) if j + 2 >= n else (j + 2) * w
        end = j * w + _split_point(d[j * w : hi])
    return start, max(end, start)


def _mean_rate(d: np.ndarray) -> float:
    """The mean rate (Hz) of the intervals ``d``: their number over their sum, intervals over
    :data:`GAP_FACTOR` x their median (gaps) left out."""
    m = float(np.median(d))
    ok = d[d <= GAP_FACTOR * m]
    return float(len(ok) / ok.sum()) if ok.sum() > 0 else 1.0 / m


def _weighted_median(values: np.ndarray, weights: np.ndarray) -> float:
    """The value below and above which half the weight lies (the lower one on a tie)."""
    order = np.argsort(values, kind="stable")
    cum = np.cumsum(weights[order])
    return float(values[order][int(np.searchsorted(cum, 0.5 * cum[-1]))])


def _level(rates: np.ndarray, durs: np.ndarray) -> float:
    """The rate most of the file runs at, from stretch rates and their durations.

    The stretch rate with the most time within half of :data:`RATE_CHANGE_TOLERANCE` of it (a stretch
    across a rate change has a rate of its own and little time about it) is the level; the rate is the
    time-weighted median of the stretches within :data:`RATE_CHANGE_TOLERANCE` of that level.
    """
    lr = np.log(rates)
    order = np.argsort(lr, kind="stable")
    s, cw = lr[order], np.concatenate([[0.0], np.cumsum(durs[order])])
    half = 0.5 * np.log1p(RATE_CHANGE_TOLERANCE)
    support = cw[np.searchsorted(s, s + half, side="right")] - cw[np.searchsorted(s, s - half, side="left")]
    near = np.abs(lr - s[int(np.argmax(support))]) <= np.log1p(RATE_CHANGE_TOLERANCE)
    return _weighted_median(rates[near], durs[near])


def _rate_changes(
    t: np.ndarray, dt: np.ndarray, med: float, starts: np.ndarray, rates: np.ndarray, rate: float
) -> list[tuple[int, int, float]]:
    """Runs of stretches off ``rate`` by more than :data:`RATE_CHANGE_TOLERANCE` for at least
    :data:`RATE_CHANGE_MIN_S`: ``(first sample, last sample, rate of the intervals between them)``, kept
    when that rate (gaps left out, :func:`_mean_rate`) is off by more than the tolerance too."""
    changes: list[tuple[int, int, float]] = []
    off = np.isfinite(rates) & (np.abs(rates - rate) > RATE_CHANGE_TOLERANCE * rate)
    ends = np.append(starts[1:], t[-1])
    w = len(dt) // len(rates)
    i = 0
    while i < len(off):
        if not off[i]:
            i += 1
            continue
        j = i
        while j + 1 < len(off) and off[j + 1]:
            j += 1
        if ends[j] - starts[i] >= RATE_CHANGE_MIN_S:
            a, b = _change_span(t, dt, med, w, len(rates), i, j)
            r = _mean_rate(dt[a:b]) if b > a else float(np.median(rates[i : j + 1]))
            if abs(r - rate) > RATE_CHANGE_TOLERANCE * rate:  # its own intervals are off too, not only a gap among them
                changes.append((a, b, r))
        i = j + 1
    return changes


def judge_rate(t: np.ndarray, dt: np.ndarray | None = None, med: float | None = None) -> dict[str, Any]:
    """The rate of a recording's timestamps, judged over the whole file (see :func:`judge_timestamps`).

    1. The stretch rates (:func:`local_rates`, the mean rate of each 1000 intervals) give the level most of
       the file's time runs at (:func:`_level`: a time-weighted median, not one counted in samples, so 20 s at
       400 Hz and 40 s at 200 Hz run at 200 Hz).
    2. Stretches whose rate differs from it by more than :data:`RATE_CHANGE_TOLERANCE` for at least
       :data:`RATE_CHANGE_MIN_S` are rate changes, reported from the sample where the intervals change
       (:func:`_change_span`) with the mean rate of the intervals between its edges (gaps left out; the
       rounding of a quantised clock averages out). When the changes at one rate outlast the rest of the
       file, that rate is the file's and the changes are judged again from it.
    3. The file's rate is ``1 / median interval`` of the samples outside the changes, unless those are
       quantised (at most :data:`QUANTISED_LEVELS` distinct intervals, a clock's resolution apart, which is
       at most half the median interval: a second rate or dropped samples lie an interval apart) and that
       rate disagrees by more than :data:`QUANTISED_TOLERANCE` with the mean rate of the intervals within
       1.5 resolutions of the median (the two levels the true interval lies between, and none of dropped
       samples or of a part at another rate too short to be judged a change): the clock's resolution is
       then too coarse for the rate (400 Hz in whole milliseconds: 2, 3, 2, 3 ms; 150 Hz: 6, 7, 7 ms gives
       143 Hz) and that mean is the rate.

    Returns
    -------
    dict
        ``median_interval_s`` (of the whole file), ``rate_hz``, ``rate_rule`` (text), ``max_rate_hz``
        (fastest stretch), ``rate_changes`` (``[[t_start_s, t_end_s, rate_hz], ...]``,
        s from the first timestamp).
    """
    t = np.asarray(t, dtype=float)
    dt = np.diff(t) if dt is None else dt
    med = float(np.median(dt)) if med is None else med
    starts, rates, durs = _local_rates(t, dt, med)
    good = np.isfinite(rates) & (durs > 0)
    rate, rule, found = 1.0 / med, "1 / median interval", []
    if good.any():
        ref = _level(rates[good], durs[good])
        found = _rate_changes(t, dt, med, starts, rates, ref)
        # a faster part that lasts FAST_PART_MIN_SHARE of the file sets the file's rate: resampling to it keeps
        # every part's signal (a slower part is up-sampled, and a model's rate check reads it from rate_changes);
        # a brief faster burst does not multiply the whole file's samples
        span = max(float(t[-1] - t[0]), 1e-12)
        fast = [
            r
            for _, _, r in found
            if r > (1 + RATE_CHANGE_TOLERANCE) * ref
            and sum(t[b] - t[a] for a, b, q in found if abs(q - r) <= RATE_CHANGE_TOLERANCE * r) >= FAST_PART_MIN_SHARE * span
        ]
        if fast:
            ref = float(max(fast))
            found = _rate_changes(t, dt, med, starts, rates, ref)
        main = dt
        if found:
            keep = np.ones(len(dt), dtype=bool)
            for a, b, _ in found:
                keep[a:b] = False
            main = dt[keep]
        main_med = float(np.median(main)) if found and len(main) else med
        rate = 1.0 / main_med
        # distinct intervals among at most QUANTISED_SAMPLE of them, spread over the samples at the main rate
        sample = main[:: max(1, len(main) // QUANTISED_SAMPLE)]
        levels = np.unique(np.round(sample[sample <= GAP_FACTOR * main_med], 9))
        res = float(np.min(np.diff(levels))) if len(levels) > 1 else np.inf
        if len(levels) <= QUANTISED_LEVELS and res <= 0.5 * main_med:
            # the mean of the clock's levels next to the median: neither dropped samples (twice the interval)
            # nor a part at another rate too short to be judged a change pull it
            own = main[np.abs(main - main_med) <= 1.5 * res]
            r_q = float(len(own) / own.sum())
            if abs(r_q - rate) > QUANTISED_TOLERANCE * r_q:
                rule = (
                    f"mean of the intervals within {1.5 * res:.3g} s of the median{' outside the rate changes' if found else ''} "
                    f"(the timestamps are quantised to {res:.3g} s: the median interval gives {rate:.6g} Hz)"
                )
                rate = r_q
    changes = [[round(float(t[a] - t[0]), 6), round(float(t[b] - t[0]), 6), round(r, 3)] for a, b, r in found]
    max_rate = float(np.nanmax(rates)) if good.any() else rate
    return {"median_interval_s": med, "rate_hz": rate, "rate_rule": rule, "max_rate_hz": max(max_rate, rate), "rate_changes": changes}


def rate_change_warning(changes: list[list[float]], rate_hz: float, fs: float) -> str:
    """One line naming where the timestamps' rate differs from the file's and what was done."""
    first = changes[0]
    more = f" ({len(changes)} stretches in all)" if len(changes) > 1 else ""
    return (
        f"the sampling rate changes mid-file: {first[2]:g} Hz from {first[0]:.6g} to {first[1]:.6g} s{more} against "
        f"{rate_hz:.6g} Hz for the rest; resampled to {fs:g} Hz throughout (an anti-alias filter before any decimation), "
        "see meta rate_changes; pass --sampling-rate-hz to choose the rate."
    )


def judge_timestamps(
    t: np.ndarray,
    *,
    sampling_rate_hz: float | None = None,
    max_gap_s: float | None = None,
    uniform_tolerance: float = 1e-3,
) -> dict[str, Any]:
    """Judge checked timestamps: rate, gaps, uniformity, the grid to resample to.

    The same judgement for a file read whole and one read in blocks (the times
    are the whole file's either way). Refuses (InputError) an implausible rate
    (:func:`check_rate`) and a gap longer than ``max_gap_s`` (default
    :func:`max_bridge_s`) with its position.

    Returns
    -------
    dict
        ``fs`` (the uniform rate), ``resampled`` (bool), ``max_rate_hz``,
        ``meta`` (``original_rate_hz``, ``jitter_s``, ``max_interval_s``,
        ``gaps``, ``n_original_samples``, ``t0_original_s``, and ``rate_rule``
        and ``rate_changes`` when they apply) and ``warnings`` (lines).
    """
    t = np.asarray(t, dtype=float)
    dt = np.diff(t)
    judged = judge_rate(t, dt, float(np.median(dt)))
    med = judged["median_interval_s"]
    original_rate = judged["rate_hz"]
    if sampling_rate_hz is not None:
        check_rate(float(sampling_rate_hz), what="the requested sampling rate")
        if original_rate < MIN_RATE_HZ * (1 - 1e-6):
            check_rate(original_rate, what="the rate of the timestamps")
    else:
        check_rate(original_rate, what="the rate of the timestamps")
    limit = max_bridge_s(med) if max_gap_s is None else float(max_gap_s)
    long_gaps = np.flatnonzero(dt > limit)
    if long_gaps.size:
        i = int(long_gaps[0])
        raise InputError(
            f"a {dt[i]:.6g} s gap in the timestamps after sample {i} (t = {t[i] - t[0]:.6g} s from the start; "
            f"{long_gaps.size} gaps longer than {limit:.3g} s in all) is too long to bridge by interpolation; "
            "cut the file at its gaps with `gaitml split FILE --out DIR` (in Python: gaitml.io.read_segments)."
        )
    gaps = [[round(float(t[i] - t[0]), 6), round(float(dt[i]), 6)] for i in np.flatnonzero(dt > GAP_FACTOR * med)]
    uniform = bool(np.all(np.abs(dt - med) <= uniform_tolerance * med))
    meta: dict[str, Any] = {
        "original_rate_hz": round(original_rate, 6),
        "jitter_s": float(np.std(dt)),
        "max_interval_s": float(dt.max()),
        "gaps": gaps,
        "n_original_samples": int(len(t)),
        "t0_original_s": float(t[0]),
    }
    if judged["rate_rule"] != "1 / median interval":
        meta["rate_rule"] = judged["rate_rule"]
    if uniform and sampling_rate_hz is None:
        fs = float(np.round((len(t) - 1) / (t[-1] - t[0]), 6))
        resampled = False
    else:
        fs = float(sampling_rate_hz if sampling_rate_hz is not None else np.round(original_rate, 6))
        resampled = True
    warnings = []
    if judged["rate_changes"]:
        meta["rate_changes"] = judged["rate_changes"]
        warnings.append(rate_change_warning(judged["rate_changes"], original_rate, fs))
    return {"fs": fs, "resampled": resampled, "max_rate_hz": judged["max_rate_hz"], "meta": meta, "warnings": warnings}


#: A rate check (a model's, :func:`gaitml.models.rate_reason`; a step detector's, :func:`gaitml.steps.rate_check`)
#: finds a recording too slow below this fraction of the rate it checks against: phones state a nominal rate and
#: deliver a few per cent less (timestamps' jitter, dropped samples), and a recording a few per cent slower loses
#: almost nothing of what a model or a detector reads.
RATE_TOLERANCE = 0.9


def recorded_rate_hz(rate_hz: float, meta: dict | None) -> float:
    """The rate a recording was made at (Hz): the lowest of its rate ``rate_hz`` and the rates its reader
    or a caller resampled it from (``meta['original_rate_hz']``, the rate its timestamps were judged at;
    ``meta['resampled_from_hz']``). A recording brought up to a higher rate holds no more of the signal
    than it was recorded with, so a rate check (a model's, :func:`gaitml.models.rate_reason`; a step detector's,
    :func:`gaitml.steps.rate_check`) reads the rate before any up-sampling."""
    rates = [float(rate_hz)]
    for k in ("original_rate_hz", "resampled_from_hz"):
        v = (meta or {}).get(k)
        try:
            v = float(v)
        except (TypeError, ValueError):
            continue
        if np.isfinite(v) and v > 0:
            rates.append(v)
    return min(rates)
