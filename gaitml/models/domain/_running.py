"""The causal running median behind the dynamics decision, on the grid of computed windows.

A carrying position is a property of a stretch of recording: the dynamics test decides
on the median of the window distances over the last :data:`DYNAMICS_SPAN` windows, of
which only every :data:`DYNAMICS_EVERY`-th is computed (the half-overlapping windows
then tile the recording).
"""

from __future__ import annotations

import numpy as np

from gaitml.errors import ModelError

__all__ = ["DYNAMICS_EVERY", "DYNAMICS_SPAN", "dynamics_grid_step", "running_median", "span_medians"]

#: Windows in the running span of the dynamics decision (20 windows of 1.5 s at 50 % overlap: 15 s);
#: chosen on held-out simulated seeds (``experiments/reports/model-domain.md``, "Choosing the span with
#: held-out seeds"; ``fit_domain(dynamics_span=)``).
DYNAMICS_SPAN = 20
#: The check computes the orientation dynamics of every ``DYNAMICS_EVERY``-th window only (windows 0, 2, 4, ...
#: of the recording) and decides on the median of those within each window's span. The windows overlap by
#: half, so every second window tiles the recording: the computed windows still see every sample once, at
#: half the cost of the descriptors (the choice against every 4th window is measured in
#: ``experiments/reports/model-domain.md`` with ``experiments/scripts/lopo_domain.py``). ``fit_domain`` fits
#: the threshold on the same grid (pooled over its phases), and the record says which step it was fitted
#: with (``dynamics["every"]``; records without it were fitted on every window and are checked on every
#: window). A span not divisible by it uses its largest divisor below it (:func:`dynamics_grid_step`).
DYNAMICS_EVERY = 2


def dynamics_grid_step(span: int) -> int:
    """Every how many windows the dynamics part is computed: the largest divisor of ``span`` not above :data:`DYNAMICS_EVERY`.

    A divisor, so that the span of every window (the last ``span`` windows) holds the
    same number of computed windows, ``span // every`` (fewer at the recording's start).
    """
    span = max(1, int(span))
    return max(d for d in range(1, min(DYNAMICS_EVERY, span) + 1) if span % d == 0)


def _sequence_order(sequence) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows grouped by ``sequence`` with their time order kept.

    Returns ``codes`` (an integer per row naming its sequence), ``order`` (the stable sort
    of the rows by sequence) and ``first`` (for each position of ``order``, the position
    where its sequence begins), so ``arange(n) - first`` is each sorted row's rank in its
    sequence.
    """
    codes = np.unique(np.asarray(sequence), return_inverse=True)[1].reshape(-1)
    order = np.argsort(codes, kind="stable")
    sc = codes[order]
    return codes, order, np.searchsorted(sc, sc, side="left")


def running_median(d, span: int = DYNAMICS_SPAN, sequence=None) -> np.ndarray:
    """Median of the last ``span`` values (this one included; fewer at the start), NaN values skipped.

    ``d`` is in time order within each sequence; ``sequence`` (same length, optional)
    names the recording of every value: the span never reaches into another one.
    A value whose span holds no finite value is NaN. Equal, bit for bit, to
    ``np.nanmedian`` of each span (the middle value, or the mean of the two middle
    ones, of the sorted non-NaN values), all spans at once.
    """
    d = np.asarray(d, dtype=float).reshape(-1)
    n = len(d)
    span = max(1, int(span))
    if sequence is None and n and not np.isnan(np.add.reduce(d)):  # one recording without NaN (what the check gives)
        return _running_median_finite(d, span)
    if sequence is None:
        order, first = None, np.zeros(n, dtype=np.int64)
        values = d
    else:  # rows grouped by sequence (time order kept); first: the position of each row's sequence start
        _, order, first = _sequence_order(sequence)
        values = d[order]
    at = np.arange(n)[:, None] - np.arange(span - 1, -1, -1)[None, :]  # (n, span) positions of each span
    win = np.where(at >= first[:, None], values[np.maximum(at, 0)], np.nan)
    win.sort(axis=1)  # NaN last
    c = span - np.isnan(win).sum(axis=1)  # values in the span
    rows = np.arange(n)
    lo = win[rows, np.maximum(c - 1, 0) // 2]
    hi = win[rows, c // 2]
    med = np.where(c % 2 == 1, lo, 0.5 * (lo + hi))  # odd: the middle value; even: the mean of the middle two
    med[c == 0] = np.nan
    if order is None:
        return med
    out = np.empty(n)
    out[order] = med
    return out


def _running_median_finite(d: np.ndarray, span: int) -> np.ndarray:
    """:func:`running_median` of one sequence without NaN values (an inf is a value), the same numbers bit for bit.

    Each span is a row of one strided view of the values after ``span - 1`` NaN (the
    missing values before the start), sorted (NaN last); the first ``span - 1`` rows hold
    ``i + 1`` values, every later row ``span``: no NaN count, no index arithmetic per span
    entry. The median is then picked as in :func:`running_median`.
    """
    n = len(d)
    pad = np.empty(n + span - 1)
    pad[: span - 1] = np.nan
    pad[span - 1 :] = d
    win = np.sort(np.lib.stride_tricks.as_strided(pad, (n, span), (pad.strides[0], pad.strides[0]), writeable=False), axis=1)
    c = np.arange(1, n + 1)
    np.minimum(c, span, out=c)  # values in each span
    rows = np.arange(n)
    lo = win[rows, (c - 1) // 2]
    hi = win[rows, c // 2]
    return np.where(c % 2 == 1, lo, 0.5 * (lo + hi))  # odd: the middle value; even: the mean of the middle two


def span_medians(d, span: int = DYNAMICS_SPAN, every: int = 1, sequence=None, phase: int = 0) -> np.ndarray:
    """The dynamics decision statistic of every window: the median of the computed windows within its span.

    Rows of ``d`` are windows in time order within each ``sequence`` (recording; one
    when None). The computed windows are the rows ``phase, phase + every, ...`` of each
    sequence (their values only are read); a window's statistic is the median of the
    computed windows among the last ``span`` windows (this one included), NaN skipped,
    NaN when there is none. ``every`` must divide ``span``: the statistic of the computed
    window is then :func:`running_median` over ``span // every`` computed windows, held
    by the ``every - 1`` windows after it (the same computed windows are in their spans).
    ``every = 1`` is :func:`running_median`.
    """
    d = np.asarray(d, dtype=float).reshape(-1)
    every, span = int(every), max(1, int(span))
    if every < 1 or span % every:
        raise ModelError(f"the dynamics grid step {every} must be at least 1 and divide the span {span}; retrain the model.")
    n = len(d)
    if sequence is None:
        rank = np.arange(n)
        codes = None
    else:
        codes, order, first = _sequence_order(sequence)
        rank = np.empty(n, dtype=np.int64)
        rank[order] = np.arange(n) - first
    p = int(phase) % every
    on = rank % every == p
    grid = np.flatnonzero(on)  # the computed windows, in row order
    med = running_median(d[grid], span // every, None if codes is None else codes[grid])
    # each window takes the statistic of the last computed window at or before it in its sequence (rank - back)
    back = (rank - p) % every
    at = np.cumsum(on) - 1  # row -> index in grid (for computed rows)
    out = np.full(n, np.nan)
    has = rank >= p  # windows before the first computed one have none
    if sequence is None:
        out[has] = med[at[np.flatnonzero(has) - back[has]]]
        return out
    # with several sequences the computed row rank - back of the same sequence: through the sorted order
    pos = np.empty(n, dtype=np.int64)
    pos[order] = np.arange(n)
    src = order[pos[has] - back[has]]  # row of the computed window
    out[has] = med[at[src]]
    return out
