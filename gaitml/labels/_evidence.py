"""Evidence of a mode change at a step boundary: the first step whose character departs from the old mode.

A written boundary says that the motion mode changed near that time. Each detected
step (or stride) is described by a few numbers that a change of mode moves: its
duration (cadence), the spread of the acceleration magnitude (intensity) and the
spread of each accelerometer axis (which way the body accelerates in the phone's
frame: forward, sideways or backward, which a turn of the body into a side step
or a backward walk swaps). Rotation is not used: the turn into a new mode spreads
over the steps around the change and does not mark where it is. The old mode is
described by the steps just before the written boundary's search band, the new
one by the steps just after it (medians; the old mode's robust spread scales every
feature). Each step is placed along the line from the old mode to the new one; the
mode change is put at the end of the last step before the first step that departs
from the old mode towards the new one (``CHANGE_Z`` spreads and ``CHANGE_SHARE`` of
the way). A change step that blends both modes (a turning step, the first step of
a run) therefore belongs to the new mode, as its first step.

No paper describes this; it is the labelling front end's own rule. The step
boundary is the step event (the impact peak, DESIGN sec. 2), as in
:mod:`gaitml.labels`. The boundary moves only when the evidence is clean
(:func:`change_at`); otherwise it stays where it was written (status
``ambiguous``):

- each mode described by at least ``MIN_REFERENCE_STEPS`` steps outside the band,
  none of them over ``MISSED_STEP_RATIO`` times their median or a median over
  ``MAX_STEP_S`` (the detector missed steps there), and not strides (the two
  halves of a step's |acc| correlate above ``STRIDE_HALF_CORR``: the detector
  counts every other step and the change may lie inside one);
- the two modes far enough apart (``CHANGE_Z / CHANGE_SHARE`` spreads) that a step
  a quarter of the way is told from the old mode's own scatter;
- the old mode steady up to the band, the last old step clearly old (at most
  ``CLEAR_OLD_Z`` spreads towards the new mode, within ``CHANGE_Z`` in every
  feature, its duration within ``CLEAR_OLD_Z`` spreads: a shorter one is half of
  a step the detector split), the two steps after the change both departing (a
  single odd step is a stumble or a detection error), and the first new step not
  over ``MISSED_STEP_RATIO`` times the usual step of both modes (it may hide a
  missed step, which may be the true boundary).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "CHANGE_Z",
    "CHANGE_SHARE",
    "CLEAR_OLD_Z",
    "MISSED_STEP_RATIO",
    "MAX_STEP_S",
    "STRIDE_HALF_CORR",
    "REFERENCE_STEPS",
    "MIN_REFERENCE_STEPS",
    "FEATURE_FLOOR",
    "step_character",
    "change_at",
]

#: a step departs from the old mode when it lies this many robust spreads towards the new mode...
CHANGE_Z = 4.0
#: ... and at least this share of the way from the old mode to the new one
CHANGE_SHARE = 0.25
#: steps (outside the search band) that describe each mode
REFERENCE_STEPS = 8
#: fewer steps than this describe a mode: the boundary stays
MIN_REFERENCE_STEPS = 4
#: the last step before the change lies at most this many spreads towards the new mode
CLEAR_OLD_Z = 2.0
#: a step this many times the usual one hides a missed step
MISSED_STEP_RATIO = 1.8
#: the longest step (s): 0.5 steps/s, the low edge of the step band of the adaptive detector; a longer one holds missed steps
MAX_STEP_S = 2.0
#: steps whose two halves correlate above this (median) are strides (two steps each): a change may lie inside one
STRIDE_HALF_CORR = 0.3
#: smallest spread of a (log) feature: 0.1 = a 10 % change is within one spread
FEATURE_FLOOR = 0.1


def step_character(acc: np.ndarray, span_start: np.ndarray, span_end: np.ndarray, fs: float) -> np.ndarray:
    """One row per step ``[span_start, span_end)``: log duration, log |acc| spread, log spread of each axis, halves.

    Logs make the features relative (a 20 % longer step is the same change at any
    cadence); small constants keep a still step finite. The last column is the
    correlation of the two halves of the step's |acc| (NaN for a step of under six
    samples): a step (impact, then swing) anti-correlates with itself shifted by
    half its length, a stride (two alike steps) correlates.
    """
    mag = np.linalg.norm(acc, axis=1)
    rows = []
    for a, b in zip(span_start.astype(int), span_end.astype(int), strict=True):
        b = max(b, a + 2)
        seg = acc[a:b]
        f = [np.log((b - a) / fs), np.log(np.std(mag[a:b]) + 0.05), *np.log(np.std(seg, axis=0) + 0.05)]
        x = mag[a:b] - np.mean(mag[a:b])
        h = len(x) // 2
        r = np.corrcoef(x[:h], x[h : 2 * h])[0, 1] if h >= 3 and np.std(x[:h]) > 0 and np.std(x[h : 2 * h]) > 0 else np.nan
        rows.append([*f, r])
    return np.asarray(rows, dtype=float).reshape(-1, 6)


def change_at(features: np.ndarray, ends: np.ndarray, k: int, band: float, k_prev: float, k_next: float) -> tuple[int | None, str]:
    """The step boundary where the old mode ends near written sample ``k``, or ``None`` and why.

    Parameters
    ----------
    features : (n_steps, d) array from :func:`step_character`.
    ends : (n_steps,) int array
        The sample that ends each step (its boundary with the next step), increasing.
    k : int
        The written boundary (sample).
    band : float
        Search half-width in samples: the true boundary lies within ``band`` of ``k``.
    k_prev, k_next : float
        The previous and next written boundaries (samples): the old mode is described
        by steps between ``k_prev + band`` and ``k - band``, the new one by steps
        between ``k + band`` and ``k_next - band``.

    Returns
    -------
    (sample, 'snapped') when the change is clean, else (None, reason) with reason
    ``ambiguous`` (no clean change) or ``too far`` (no step boundary within the band).
    """
    n = len(ends)
    in_band = np.flatnonzero(np.abs(ends - k) <= band)
    if len(in_band) == 0:
        return None, "too far"
    starts = np.concatenate([[-np.inf], ends[:-1]])
    old = np.flatnonzero((ends < k - band) & (starts >= k_prev + band))[-REFERENCE_STEPS:]
    new = np.flatnonzero((starts > k + band) & (ends <= k_next - band))[:REFERENCE_STEPS]
    if len(old) < MIN_REFERENCE_STEPS or len(new) < MIN_REFERENCE_STEPS:
        return None, "ambiguous"
    for ref in (old, new):
        dur = np.exp(features[ref, 0])
        if np.median(dur) > MAX_STEP_S or dur.max() > MISSED_STEP_RATIO * np.median(dur):
            return None, "ambiguous"  # the detector missed steps there: the steps do not describe the mode
    halves = features[:, 5]
    for ref in (old, new):
        h = halves[ref][np.isfinite(halves[ref])]
        if len(h) and np.median(h) > STRIDE_HALF_CORR:
            return None, "ambiguous"  # the detector counts strides in one mode: the change may lie inside one
    features = features[:, :5]
    mu = np.median(features[old], axis=0)
    sig = np.maximum(1.4826 * np.median(np.abs(features[old] - mu), axis=0), FEATURE_FLOOR)
    z = (features - mu) / sig
    d = np.median(z[new], axis=0)  # the new mode, in robust spreads of the old one
    size = float(np.linalg.norm(d))
    if size < CHANGE_Z / CHANGE_SHARE:
        return None, "ambiguous"  # the two modes differ too little in these features to place the change
    along = z @ d / size  # each step's way from the old mode towards the new one (spreads)
    departs = (along >= CHANGE_Z) & (along >= CHANGE_SHARE * size)
    if departs[old[-2:]].any():
        return None, "ambiguous"  # the old mode is not steady up to the band
    last = min(int(in_band[-1]) + 2, n - 1)
    for m in range(int(old[-1]) + 1, last + 1):
        if departs[m]:
            break
    else:
        return None, "ambiguous"
    # the change lies at the end of step m - 1: it must be in the band and the next step must depart too
    if m - 1 not in set(in_band.tolist()) or m + 1 >= n or not departs[m + 1]:
        return None, "ambiguous"
    # the last old step must be clearly old: not on its way to the new mode (it may be the change's first part),
    # like the old mode in every feature, and of an old step's duration (shorter: a step split in two; the
    # boundary between its parts is no step event)
    if along[m - 1] > CLEAR_OLD_Z or np.abs(z[m - 1]).max() > CHANGE_Z or abs(z[m - 1, 0]) > CLEAR_OLD_Z:
        return None, "ambiguous"
    # a first new step over MISSED_STEP_RATIO times the usual step of both modes may hide a missed step,
    # which may be the true boundary
    t_m = features[m, 0]
    if t_m - max(mu[0], np.median(features[new, 0])) > np.log(MISSED_STEP_RATIO):
        return None, "ambiguous"
    return int(ends[m - 1]), "snapped"
