"""The training domain of a model, and whether a new window lies inside it.

A classifier has no "unknown" class: a window unlike anything it was trained on (a
phone in a pocket for a model trained on hand-held phones, a foot-mounted IMU, a
recording in g read as m/s^2) still gets one of its modes, often confidently. The
domain record lets ``gaitml predict`` and ``gaitml pdr`` say so, window by window.

What is recorded at training time (``model.json`` key ``domain``; the arrays in
``arrays.npz`` under names starting ``domain__``, read with ``allow_pickle=False``):

- **positions**: the carrying positions of the training recordings (recording meta
  ``position``, ``"unknown"`` where absent) with their window counts.
- **feature distance**: the features are standardised with the training mean and
  standard deviation; each training class gets a Gaussian (class mean and a
  Ledoit-Wolf shrunk covariance, which stays invertible with the 104 strongly
  correlated features). The distance of a window is its smallest Mahalanobis distance
  to the classes: small when it looks like *some* trained mode.
- **gravity direction** (phone-frame models only): the unit vector of the window mean
  of the acceleration in the phone frame. A set of up to ``MAX_GRAVITY_DIRECTIONS``
  training directions is kept (the distribution, which may have several modes:
  flat and tilted phones); the angle of a window's direction to the nearest of
  them is its gravity distance. Its mean direction and the quantiles of the angle to
  it summarise the distribution for the model card. A gravity-frame model's features
  do not depend on the phone's orientation, so its gravity direction is recorded but
  not checked.
- **thresholds**: the ``quantile`` (default 0.99) of the distances of training
  windows *held out*: the training groups (subjects) are split into up to 5 folds;
  the standardisation, class Gaussians and gravity set are fitted on the other folds
  and the distances measured on the held-out one. A threshold from the in-sample
  distances would be optimistic (every training window is near its own Gaussian); it
  is recorded next to the held-out one for comparison.

- **orientation dynamics** (models with the gyroscope, ``all52+gyro``): 13 descriptors
  per window of how the phone moves and turns, independent of how it is held
  (:func:`orientation_dynamics`: spread of the gravity direction within the window,
  vertical vs horizontal acceleration variance and their correlation, rotation rate
  statistics and the axis it turns about). A pocket phone rotates with the thigh, a belt
  phone hardly rotates, a swinging hand rotates a lot, a bag damps; these differ where
  the 104 features of a phone placed at a random orientation do not. One Ledoit-Wolf
  Gaussian per (mode, position) on the standardised descriptors; a window's dynamics
  distance is its smallest Mahalanobis distance to them, and because a carrying
  position is a property of a stretch of recording, the decision uses the **median over
  the last** ``DYNAMICS_SPAN`` **windows** of the recording (this one included, fewer at
  its start; causal, so a stream can do the same) of the distances of **every**
  ``DYNAMICS_EVERY``**-th window** (windows 0, 2, 4, ...: the half-overlapping windows
  then tile the recording; 10 computed windows per span, :func:`span_medians`): the
  descriptors are computed for those windows only, which halves the cost of the largest
  part of the check. Its threshold is the quantile of the held-out span medians on the
  same grid (pooled over its phases); the record keeps its grid step (``every``). Leave
  one position out on the simulator (8 training subjects, 4 new ones,
  ``experiments/scripts/lopo_domain.py``): a left-out bag, belt or swinging hand is
  flagged on 81-100 % of its windows (the 104-feature distance: 0-80 %), 0.1-0.4 % of the
  trained positions' windows (0.4-1.4 % with the other tests); a left-out twin of a
  trained position (flat vs tilted hand, front vs back pocket) is not flagged (0-28 %).
  Records written before the grid (no ``every``) were fitted on every window and are
  checked on every window (85-100 %, 0.1-0.2 %); older records have no dynamics part and
  check as before.

A window is **in domain** when its feature distance is at most the distance threshold,
(phone frame) its gravity angle is at most the gravity threshold and (when recorded)
its span dynamics distance is at most the dynamics threshold. By construction
about 1 - quantile of new windows from the training distribution (new subjects) fall
outside each test; the domain report (``experiments/reports/model-domain.md``) measures
it on new simulated subjects and on real recordings.

This is ours (the papers have no domain check); it detects *that* a window is unlike the
training data, not *why*.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import threading
from typing import Any

import numpy as np

from gaitml.errors import ModelError

__all__ = [
    "DOMAIN_VERSION",
    "DomainModel",
    "fit_domain",
    "window_gravity",
    "feature_gravity",
    "orientation_dynamics",
    "DYNAMICS_NAMES",
    "DYNAMICS_SPAN",
    "DYNAMICS_EVERY",
    "dynamics_grid_step",
    "running_median",
    "span_medians",
    "domain_from_model_info",
    "NO_DOMAIN_WARNING",
    "OUT_OF_DOMAIN_WARN_FRACTION",
    "domain_warning",
    "out_of_domain_fraction",
]

DOMAIN_VERSION = 1
#: Prefix of the domain arrays inside ``arrays.npz``.
ARRAY_PREFIX = "domain__"
#: At most this many training gravity directions are kept (a random subset).
MAX_GRAVITY_DIRECTIONS = 400
#: Default quantile of the held-out distances used as thresholds.
DEFAULT_QUANTILE = 0.99
#: Folds over the training groups for the held-out thresholds.
HELDOUT_FOLDS = 5
#: ``gaitml predict`` / ``pdr`` print one warning when more than this fraction of windows is out of domain.
OUT_OF_DOMAIN_WARN_FRACTION = 0.10
#: The warning for a model saved without a domain record.
NO_DOMAIN_WARNING = (
    "the model has no domain record (trained before gaitml recorded one), so in_domain is unknown (null); "
    "retrain it with 'gaitml train CONFIG' to get the out-of-domain check"
)
_ARRAYS = ("center", "scale", "class_means", "class_precisions", "gravity_dirs", "feature_lo", "feature_hi")
#: The batch feature distance (:meth:`DomainModel.distances` of at least ``_BLOCKED_MIN_ROWS`` rows) multiplies by the
#: Cholesky factors in column blocks of about this many columns, skipping the zeros above their diagonal.
_DISTANCE_BLOCK_COLUMNS = 13  # 8 blocks of 104 features: 56 % of the full product's multiplications (4 blocks: 62 %, 0.3 ms slower)
#: Fewer rows (a stream's one window) take one product with the whole stacked factors: fewer calls.
_BLOCKED_MIN_ROWS = 64
#: The arrays of the optional orientation-dynamics part.
_DYN_ARRAYS = ("dyn_center", "dyn_scale", "dyn_means", "dyn_precisions")
#: Windows in the running span of the dynamics decision (20 windows of 1.5 s at 50 % overlap: 15 s).
#: Kept after a choice on held-out seeds: span 30, chosen among 10-60 on the usual simulated seeds,
#: flags a left-out position on >= 80 % for as few positions as 20 on new seeds
#: (``experiments/reports/model-domain.md``, "Choosing the span with held-out seeds"; ``fit_domain(dynamics_span=)``).
DYNAMICS_SPAN = 20
#: The check computes the orientation dynamics of every ``DYNAMICS_EVERY``-th window only (windows 0, 2, 4, ...
#: of the recording) and decides on the median of those within each window's span (10 of its last 20 windows).
#: The decision is a 15 s running median of a property of the stretch of recording (how the phone is
#: carried), and the windows overlap by half: every second window tiles the recording, so the computed
#: windows still see every sample once, at half the cost of the descriptors (the largest part of the
#: check; ``benchmarks/README.md``). Every 4th window (5 per span) sees half the samples and lost
#: detection in ``experiments/scripts/lopo_domain.py`` (left-out belt 77 %, swinging hand 74 % against
#: 89 / 85 % on every window; with 2: 87.5 / 85.6 %). ``fit_domain`` fits the threshold on the same grid
#: (pooled over its phases), and the record says which step it was fitted with (``dynamics["every"]``;
#: records without it were fitted on every window and are checked on every window). A span not
#: divisible by it uses its largest divisor below it (:func:`dynamics_grid_step`).
DYNAMICS_EVERY = 2
#: Length (s) of the chunks whose gravity directions give the within-window spread.
DYNAMICS_CHUNK_S = 0.3
#: The descriptors are computed from the signals taken at about this rate (every ``floor(fs / 25)``-th
#: sample): they describe slow orientation changes, and half the samples halve the cost of the check.
DYNAMICS_RATE_HZ = 25.0
#: The orientation-dynamics descriptors (:func:`orientation_dynamics`), in order.
DYNAMICS_NAMES = (
    "gravity_spread_deg",
    "log_var_ratio_vertical_horizontal",
    "abs_corr_vertical_horizontal",
    "horizontal_anisotropy",
    "log_std_vertical",
    "log_std_horizontal",
    "gravity_range_deg",
    "skew_vertical",
    "log_gyr_mean",
    "log_gyr_std",
    "gyr_vertical_share",
    "gyr_axis_share",
    "gyr_horizontal_main_share",
)


def dynamics_sample_step(sampling_rate_hz: float) -> int:
    """Every how many samples :func:`orientation_dynamics` keeps one (about ``DYNAMICS_RATE_HZ``)."""
    return max(1, int(float(sampling_rate_hz) // DYNAMICS_RATE_HZ))


def orientation_dynamics(acc, gyr, starts, ends, sampling_rate_hz: float) -> np.ndarray:
    """Orientation-free descriptors of how the phone moves and turns in each window, shape (k, 13).

    Per ``[start, end)`` span of ``acc`` (m/s^2) and ``gyr`` (rad/s), phone frame, with
    ``g`` the unit window mean of the acceleration (the gravity direction), ``v = a . g``
    the vertical and ``h = a - v g`` the horizontal acceleration (:data:`DYNAMICS_NAMES`):

    0. mean and 6. largest angle (deg) between ``g`` and the mean directions of the
       window's chunks of ``DYNAMICS_CHUNK_S`` (how far the phone tilts within it);
    1. ``log(var v / var h)`` (``var h``: trace of the horizontal covariance);
    2. ``|corr(v, h1)|``, ``h1`` the horizontal component along the main axis of the
       horizontal covariance;
    3. second over first eigenvalue of the horizontal covariance;
    4. ``log std v``, 5. ``log sqrt(var h)``; 7. skewness of ``v``;
    8. ``log`` mean and 9. ``log`` std of ``|omega|``;
    10. share of the rotation-rate variance about ``g``, 11. its largest eigenvalue share,
        12. its share about the main horizontal acceleration axis.

    The signals are first taken at every ``step = max(1, floor(fs / DYNAMICS_RATE_HZ))``-th
    sample (samples 0, step, 2 step, ...; a window keeps the kept samples inside it; spans
    reaching past the signal are cut at its end). A window with fewer than 2 kept samples
    gives a NaN row. All are unchanged by a constant rotation of the phone. Ours (issue 12),
    not from a paper.

    Only the samples of the given windows are read (gathered into one zero-padded
    (k, longest window, 3) block per signal; the moments are two-pass sums over it), so the
    cost grows with the number of windows asked for, not with the recording: a caller that
    needs every ``DYNAMICS_EVERY``-th window only (the check) pays for those.
    """
    step = dynamics_sample_step(sampling_rate_hz)
    acc = np.asarray(acc, dtype=float)
    gyr = np.asarray(gyr, dtype=float)
    kept = -(-len(acc) // step)  # kept samples of the signal
    j0 = np.clip(-(-np.asarray(starts, dtype=np.int64).reshape(-1) // step), 0, kept)  # first kept sample at or after the start
    j1 = np.clip(-(-np.asarray(ends, dtype=np.int64).reshape(-1) // step), 0, kept)
    out = np.full((len(j0), len(DYNAMICS_NAMES)), np.nan)
    chunk = max(1, int(round(DYNAMICS_CHUNK_S * float(sampling_rate_hz) / step)))
    rows = np.flatnonzero(j1 - j0 >= 2)
    with one_blas_thread():  # its matrix-vector products: one BLAS thread (see one_blas_thread)
        for b in range(0, len(rows), _DYNAMICS_BATCH):  # bounded memory for long recordings (training on every window)
            r = rows[b : b + _DYNAMICS_BATCH]
            if len(r) == len(out):
                out[:] = _dynamics_of_spans(acc, gyr, j0, j1, step, chunk)
            else:
                out[r] = _dynamics_of_spans(acc, gyr, j0[r], j1[r], step, chunk)
    return out


#: :func:`orientation_dynamics` takes at most this many windows at once (its blocks: about 20 x 8 bytes per kept sample).
_DYNAMICS_BATCH = 4096
#: The distinct entries (i <= j) of a symmetric 3 x 3 matrix, and the entry of each (i, j) among them.
_PAIRS = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))
_SYM = np.array([[0, 1, 2], [1, 3, 4], [2, 4, 5]])


def _window_block(acc: np.ndarray, gyr: np.ndarray, j0: np.ndarray, width: int, step: int) -> np.ndarray:
    """The kept samples ``j0 + 0 .. width - 1`` (every ``step``-th sample) of both signals, shape (6, k, width).

    Windows past the end repeat the last kept sample (the caller zeroes what lies beyond
    a window). Evenly spaced windows inside the signal (what the check asks for) are
    copied from one strided view of each signal, others gathered by index.
    """
    k = len(j0)
    last = (len(acc) - 1) // step  # the last kept sample
    S = np.empty((6, k, width))
    gap = int(j0[1] - j0[0]) if k > 1 else 0
    if j0[0] >= 0 and int(j0[-1]) + width - 1 <= last and gap >= 0 and (k < 3 or (np.diff(j0) == gap).all()):
        if gap == width or k == 1:  # windows that tile the kept samples (the check's grid): one slice of each signal
            a = int(j0[0]) * step
            for sig, rows in ((acc, S[:3]), (gyr, S[3:])):
                rows[...] = sig[a : a + k * width * step : step].T.reshape(3, k, width)
            return S
        for sig, rows in ((acc, S[:3]), (gyr, S[3:])):
            s0, s1 = sig.strides
            rows[...] = np.lib.stride_tricks.as_strided(
                sig[int(j0[0]) * step :], (3, k, width), (s1, gap * step * s0, step * s0), writeable=False
            )
        return S
    idx = np.minimum(j0[:, None] + np.arange(width), last) * step
    for c in range(3):
        S[c] = acc[:, c][idx]
        S[3 + c] = gyr[:, c][idx]
    return S


def _dynamics_of_spans(acc: np.ndarray, gyr: np.ndarray, j0: np.ndarray, j1: np.ndarray, step: int, chunk: int) -> np.ndarray:
    """:func:`orientation_dynamics` of spans ``[j0, j1)`` of the kept samples (every ``step``-th), each at least 2 long.

    ``chunk``: kept samples per chunk of the gravity spread. Layout: components first,
    windows next, samples last (sums over a window's samples are one matrix-vector
    product), so that every operation is one pass over a small block whatever the
    number of windows.
    """
    k = len(j0)
    n = j1 - j0
    width = int(n.max())
    pos = np.arange(width)
    S = _window_block(acc, gyr, j0, width, step)  # (6, k, width): acc x, y, z, gyr x, y, z
    pad = None if (n == width).all() else pos < n[:, None]  # (k, width): the window's own samples
    if pad is not None:
        S *= pad
    ones = np.ones(width)
    cnt = n.astype(float)
    mean = (S.reshape(-1, width) @ ones).reshape(6, k) / cnt
    Ac = S[:3] - mean[:3, :, None]  # centred acceleration (two passes: gravity dwarfs the motion)
    if pad is not None:
        Ac *= pad
    # the six distinct products of the centred acceleration and of the rotation rate (raw: its mean is small
    # next to its spread), summed over each window with one matrix-vector product
    P = np.empty((12, k, width))
    for r, (i, j) in enumerate(_PAIRS):
        np.multiply(Ac[i], Ac[j], out=P[r])
        np.multiply(S[3 + i], S[3 + j], out=P[6 + r])
    m2 = (P.reshape(-1, width) @ ones).reshape(12, k) / cnt
    cov = m2[_SYM]  # central covariance of the acceleration (3, 3, k)
    cw = m2[6 + _SYM] - mean[3:, None] * mean[None, 3:]  # and of the rotation rate
    g = mean[:3] / np.maximum(np.sqrt((mean[:3] * mean[:3]).sum(axis=0)), 1e-9)  # (3, k)
    v = Ac[0] * g[0][:, None]  # centred vertical acceleration (k, width), 0 on the padding
    v += Ac[1] * g[1][:, None]
    v += Ac[2] * g[2][:, None]
    v3 = v * v
    v3 *= v
    third = (v3 @ ones) / cnt
    # an orthonormal frame (g, u1, u2), u1 from the axis least aligned with g; the covariances in it
    ax = np.argmin(np.abs(g), axis=0)
    cols = np.arange(k)
    u1 = -g * g[ax, cols]
    u1[ax, cols] += 1.0
    u1 /= np.sqrt((u1 * u1).sum(axis=0))
    u2 = g[[1, 2, 0]] * u1[[2, 0, 1]] - g[[2, 0, 1]] * u1[[1, 2, 0]]  # g x u1
    R = np.stack([g, u1, u2])  # (3 axes, 3, k)

    def in_frame(M: np.ndarray) -> np.ndarray:  # R M R^T of every window, (3, 3, k)
        MR = (M[None] * R[:, None]).sum(axis=2)
        return (R[:, None] * MR[None]).sum(axis=2)

    F = in_frame(cov)
    var_v, h11, h22, h12 = F[0, 0], F[1, 1], F[2, 2], F[1, 2]
    # the horizontal covariance [[h11, h12], [h12, h22]]: its 2 x 2 eigenproblem in closed form
    half = 0.5 * (h11 - h22)
    rad = np.sqrt(half * half + h12 * h12)
    lam1 = 0.5 * (h11 + h22) + rad  # largest horizontal eigenvalue
    lam2 = 0.5 * (h11 + h22) - rad
    theta = 0.5 * np.arctan2(2.0 * h12, h11 - h22)  # main horizontal axis: cos theta u1 + sin theta u2
    cs, sn = np.cos(theta), np.sin(theta)
    var_h = h11 + h22
    cov_vh1 = cs * F[0, 1] + sn * F[0, 2]
    Fw = in_frame(cw)
    tot = np.maximum(Fw[0, 0] + Fw[1, 1] + Fw[2, 2], 1e-12)
    w_main = cs * cs * Fw[1, 1] + 2.0 * cs * sn * Fw[1, 2] + sn * sn * Fw[2, 2]
    mag = P[6] + P[9]  # |omega| (k, width), 0 on the padding
    mag += P[11]
    np.sqrt(mag, out=mag)
    mag_mean = (mag @ ones) / cnt
    mag_var = m2[6] + m2[9] + m2[11] - mag_mean * mag_mean  # E|omega|^2 - (E|omega|)^2
    # chunk gravity directions: the acceleration summed over [c chunk, (c + 1) chunk) of the window, c below
    # max(1, n // chunk) (a window shorter than a chunk: its own samples, the padding being 0)
    nch = np.maximum(1, n // chunk)
    nc = int(nch.max())
    member = (pos[:, None] // chunk == np.arange(nc)[None, :]).astype(float)  # (width, nc)
    C = (S[:3].reshape(-1, width) @ member).reshape(3, k, nc)
    norm = np.sqrt((C * C).sum(axis=0))
    cosang = (C * g[:, :, None]).sum(axis=0) / np.maximum(norm, 1e-9 * np.minimum(chunk, n)[:, None])  # 1e-9 on the chunk mean
    ang = np.degrees(np.arccos(np.clip(cosang, -1.0, 1.0)))
    if not (nch == nc).all():
        ang *= np.arange(nc)[None, :] < nch[:, None]  # angles are >= 0: 0 changes neither the sum nor the max
    out = np.empty((len(DYNAMICS_NAMES), k))  # rows filled in place, one transposed view returned (no column_stack copy)
    np.divide(ang.sum(axis=1), nch, out=out[0])
    np.log(np.maximum(var_v, 1e-9) / np.maximum(var_h, 1e-9), out=out[1])
    np.abs(cov_vh1 / np.sqrt(np.maximum(var_v * lam1, 1e-12)), out=out[2])
    np.divide(np.maximum(lam2, 0.0), np.maximum(lam1, 1e-12), out=out[3])
    np.multiply(0.5, np.log(np.maximum(var_v, 1e-12)), out=out[4])
    np.multiply(0.5, np.log(np.maximum(var_h, 1e-12)), out=out[5])
    np.max(ang, axis=1, out=out[6])
    np.divide(third, np.maximum(var_v, 1e-12) ** 1.5, out=out[7])
    np.log(np.maximum(mag_mean, 1e-6), out=out[8])
    np.multiply(0.5, np.log(np.maximum(mag_var, 1e-12)), out=out[9])
    np.divide(Fw[0, 0], tot, out=out[10])
    np.divide(_largest_eigenvalue(cw), tot, out=out[11])
    np.divide(w_main, tot, out=out[12])
    return out.T


def _largest_eigenvalue(S: np.ndarray) -> np.ndarray:
    """Largest eigenvalue of symmetric 3 x 3 matrices (3, 3, k), in closed form (trigonometric solution of the cubic)."""
    q = (S[0, 0] + S[1, 1] + S[2, 2]) / 3.0
    off = S[0, 1] ** 2 + S[0, 2] ** 2 + S[1, 2] ** 2
    d0, d1, d2 = S[0, 0] - q, S[1, 1] - q, S[2, 2] - q
    p = np.sqrt((d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * off) / 6.0)
    safe = p > 1e-15 * (1.0 + np.abs(q))
    # det(S - q I) / p^3 (the determinant written out)
    det = d0 * (d1 * d2 - S[1, 2] ** 2) - S[0, 1] * (S[0, 1] * d2 - S[1, 2] * S[0, 2]) + S[0, 2] * (S[0, 1] * S[1, 2] - d1 * S[0, 2])
    pp = np.where(safe, p, 1.0)
    r = np.clip(det / (2.0 * pp * pp * pp), -1.0, 1.0)
    return np.where(safe, q + 2.0 * p * np.cos(np.arccos(r) / 3.0), q)


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


def window_gravity(acc, starts, length: int) -> np.ndarray:
    """Unit vector of the mean acceleration of every window (phone frame), shape (k, 3).

    Windows whose mean is (nearly) zero (free fall) have no direction: NaN rows.
    """
    starts = np.asarray(starts, dtype=np.int64).reshape(-1)
    return span_gravity(acc, starts, starts + int(length))


#: The phone-frame features that are the window means of the acceleration along x, y, z (``all52``, ``all52+gyro``).
ACC_MEAN_FEATURES = ("acc_x__mean", "acc_y__mean", "acc_z__mean")


def feature_gravity(X, feature_names) -> np.ndarray | None:
    """:func:`window_gravity` read off a phone-frame feature matrix of the windows, or None when it cannot be.

    The window gravity is the unit mean of the window's acceleration, and the
    ``all52`` / ``all52+gyro`` features of a window in the **phone frame** hold that mean
    (:data:`ACC_MEAN_FEATURES`, the window's own samples summed): normalising those three
    columns gives the same direction without a second pass over the recording. The two
    differ by rounding only (:func:`span_gravity` takes differences of running sums,
    which lose about 1e-13 relative on a 10-minute recording). Windows whose mean is
    (nearly) zero have no direction (NaN rows), as in :func:`span_gravity`.

    Parameters
    ----------
    X : (k, p) features of the windows in the phone frame, columns ``feature_names``.
    feature_names : the column names.

    Returns
    -------
    (k, 3) unit vectors, or None when a mean column is missing (e.g. ``paper34``) or a
    mean is not finite: the caller then uses :func:`window_gravity`.
    """
    names = list(feature_names)
    if not all(n in names for n in ACC_MEAN_FEATURES):
        return None
    mean = np.asarray(X, dtype=float)[:, [names.index(n) for n in ACC_MEAN_FEATURES]]
    if not np.isfinite(mean).all():
        return None
    norm = np.linalg.norm(mean, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = mean / norm[:, None]
    out[~(norm > 1e-6)] = np.nan
    return out


def span_gravity(acc, starts, ends) -> np.ndarray:
    """:func:`window_gravity` of windows of different lengths (``[start, end)`` spans, e.g. step windows)."""
    acc = np.asarray(acc, dtype=float)
    starts = np.asarray(starts, dtype=np.int64).reshape(-1)
    ends = np.asarray(ends, dtype=np.int64).reshape(-1)
    cum = np.zeros((len(acc) + 1, 3))
    np.cumsum(acc, axis=0, out=cum[1:])
    length = np.maximum(ends - starts, 1).astype(float)
    mean = (cum[ends] - cum[starts]) / length[:, None]
    norm = np.linalg.norm(mean, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = mean / norm[:, None]
    out[~(norm > 1e-6)] = np.nan
    return out


def _standardiser(X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    center = X.mean(axis=0)
    scale = X.std(axis=0)
    scale = np.where(scale > 1e-9 * (1.0 + np.abs(center)), scale, 1.0)  # constant features: unit scale
    return center, scale


def _class_gaussians(Z: np.ndarray, y: np.ndarray, classes: list[str]) -> tuple[np.ndarray, np.ndarray]:
    from sklearn.covariance import LedoitWolf

    p = Z.shape[1]
    means = np.zeros((len(classes), p))
    precs = np.zeros((len(classes), p, p))
    for i, c in enumerate(classes):
        zc = Z[y == c]
        if len(zc) < 2:  # a class with one window: unit covariance around it
            means[i] = zc.mean(axis=0) if len(zc) else 0.0
            precs[i] = np.eye(p)
            continue
        lw = LedoitWolf(assume_centered=False).fit(zc)
        means[i] = lw.location_
        precs[i] = lw.precision_ if _positive_definite(lw.precision_) else _ridge_precision(lw.covariance_)
    return means, precs


#: Ridge (standardised feature units) added to a class covariance whose shrunk estimate is
#: singular: as lenient as the unit covariance of a one-window class, plus the spread seen.
RIDGE_UNITS = 1.0


def _positive_definite(a: np.ndarray) -> bool:
    if not np.all(np.isfinite(a)):
        return False
    try:
        np.linalg.cholesky(a)
    except np.linalg.LinAlgError:
        return False
    return True


def _ridge_precision(cov: np.ndarray) -> np.ndarray:
    """Precision of ``cov + RIDGE_UNITS * I`` (unit precision when even that fails).

    Ledoit-Wolf shrinkage can leave the covariance of a class with very few windows (two, say,
    in a small step-window data set) singular: its shrinkage intensity is estimated as 0. Such
    a class is treated like a one-window class (unit covariance in the standardised features)
    widened by the little spread its windows show, so its distances stay comparable with the
    other classes' instead of exploding off the line through its windows.
    """
    p = len(cov)
    prec = np.linalg.inv(cov + RIDGE_UNITS * np.eye(p))
    prec = 0.5 * (prec + prec.T)
    return prec if _positive_definite(prec) else np.eye(p)


def _min_mahalanobis(Z: np.ndarray, means: np.ndarray, precs: np.ndarray) -> np.ndarray:
    best = np.full(len(Z), np.inf)
    for m, P in zip(means, precs, strict=True):
        d = Z - m
        q = np.einsum("ij,ij->i", d @ P, d)
        best = np.minimum(best, np.sqrt(np.maximum(q, 0.0)))
    return best


def _nearest_angle(g: np.ndarray, dirs: np.ndarray) -> np.ndarray:
    """Angle (rad) from each row of ``g`` to the nearest of ``dirs``; NaN rows give NaN."""
    if len(dirs) == 0:
        return np.full(len(g), np.nan)
    if not len(g):
        return np.zeros(0)
    bad = ~np.isfinite(g).all(axis=1)
    any_bad = bad.any()
    cos = ((np.where(bad[:, None], 0.0, g) if any_bad else g) @ dirs.T).max(axis=1)
    out = np.arccos(np.clip(cos, -1.0, 1.0))
    if any_bad:
        out[bad] = np.nan
    return out


#: The one-window path keeps every intermediate under this magnitude (far from overflow; see :func:`_feature_bound`).
_SAFE_MAGNITUDE = 1e300


def _feature_bound(center: np.ndarray, scale: np.ndarray, stacked: np.ndarray, offset: np.ndarray) -> float:
    """Largest ``|x|`` feature entry for which the distance arithmetic cannot overflow; -1 when none is safe.

    With every ``|x_i| <= B``: ``|z_i| <= (B + max|center|) / min(scale)`` and every
    entry of ``z L - m L`` is at most ``max|z| max_j sum_i |L_ij| + max|m L|``; the
    bound keeps that entry's square, summed over the ``p`` columns of a class, under
    :data:`_SAFE_MAGNITUDE`. No floating-point overflow or invalid operation can then
    occur, so the one-window path needs no ``np.errstate``.
    """
    parts = (center, scale, stacked, offset)
    if not all(np.isfinite(a).all() for a in parts) or not (scale > 0).all() or not len(center):
        return -1.0
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        a = float(np.abs(center).max())
        cmax = float(np.abs(stacked).sum(axis=0).max())
        z_max = (np.sqrt(_SAFE_MAGNITUDE / len(center)) - float(np.abs(offset).max())) / max(cmax, 1e-300)
        bound = min(1e100, min(z_max, _SAFE_MAGNITUDE) * float(scale.min()) - a)
    return float(bound) if np.isfinite(bound) and bound > 0 else -1.0


def _gravity_bound(dirs: np.ndarray) -> float:
    """Largest ``|g|`` entry for which ``g @ dirs.T`` cannot overflow; -1 without kept (finite) directions."""
    if not len(dirs) or not np.isfinite(dirs).all():
        return -1.0
    return min(1e100, _SAFE_MAGNITUDE / (3.0 * max(float(np.abs(dirs).max()), 1.0)))


def _subsample_dirs(g: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    g = g[np.all(np.isfinite(g), axis=1)]
    if len(g) > MAX_GRAVITY_DIRECTIONS:
        g = g[np.sort(rng.choice(len(g), MAX_GRAVITY_DIRECTIONS, replace=False))]
    return g


#: The BLAS libraries whose thread count the batch check limits (threadpoolctl controllers), found at its first call.
_BLAS_LIBS: list | None = None
_BLAS_LOCK = threading.Lock()
_BLAS_STATE = {"depth": 0, "saved": []}


@contextlib.contextmanager
def one_blas_thread():
    """Run the block with one BLAS thread (restored after; nested and concurrent uses restore once, at the last exit).

    The batch check's matrix products are small (the largest, the feature distance of a
    10-minute recording, about 10 million multiply-adds per block): a second BLAS thread
    saves about a millisecond on an idle machine, but when the other core is busy the
    product waits for it, and OpenBLAS's threads spin meanwhile: the same products then
    took 15-60 ms instead of 3-4 ms (``experiments/reports/model-domain.md``, "The cost,
    third follow-up"). One thread keeps the check's cost what its arithmetic costs,
    loaded or not. The first call finds the BLAS libraries (threadpoolctl, a dependency
    of scikit-learn; about 20 ms once); without threadpoolctl the block runs unchanged.
    """
    global _BLAS_LIBS
    if _BLAS_LIBS is None:
        try:
            from threadpoolctl import ThreadpoolController

            _BLAS_LIBS = [lib for lib in ThreadpoolController().lib_controllers if lib.user_api == "blas"]
        except ImportError:  # no threadpoolctl: leave the threads alone
            _BLAS_LIBS = []
    with _BLAS_LOCK:
        if _BLAS_STATE["depth"] == 0:
            _BLAS_STATE["saved"] = [lib.get_num_threads() for lib in _BLAS_LIBS]
            for lib in _BLAS_LIBS:
                lib.set_num_threads(1)
        _BLAS_STATE["depth"] += 1
    try:
        yield
    finally:
        with _BLAS_LOCK:
            _BLAS_STATE["depth"] -= 1
            if _BLAS_STATE["depth"] == 0:
                for lib, k in zip(_BLAS_LIBS, _BLAS_STATE["saved"], strict=True):
                    lib.set_num_threads(k)


@dataclasses.dataclass
class DomainModel:
    """The training domain of a model (see the module docstring).

    Attributes
    ----------
    feature_set, frame : str
        Features the distance is computed on (a feature model's own; ``all52`` /
        ``all52+gyro`` for raw-input models) and their frame.
    feature_names : list of str
    classes : list of str
    positions : dict
        Carrying position -> number of training windows.
    quantile : float
        Quantile of the held-out distances used as thresholds.
    distance_threshold : float
        Largest in-domain feature distance (held out); ``distance_threshold_in_sample`` for comparison.
    gravity_check : bool
        Whether the gravity direction is checked (phone frame only).
    gravity_threshold_rad : float
        Largest in-domain angle to the nearest training gravity direction (held out).
    arrays : dict of ndarray
        ``center``, ``scale`` (standardisation), ``class_means`` (c, p),
        ``class_precisions`` (c, p, p), ``gravity_dirs`` (m, 3), ``feature_lo``,
        ``feature_hi`` (0.5 % and 99.5 % training quantiles per feature, raw units).
    summary : dict
        JSON-ready numbers for the model card (gravity mean and angle quantiles,
        held-out scheme, window counts, in-sample thresholds).
    dynamics : dict or None
        The orientation-dynamics part (None in records without it): ``labels`` (the
        ``mode|position`` of each Gaussian), ``span`` (windows), ``every`` (the check
        computes every ``every``-th window's dynamics, :data:`DYNAMICS_EVERY`; 1 in records
        written before it), ``threshold`` (largest in-domain span median of the dynamics
        distance, held out) and ``threshold_in_sample``; its arrays ``dyn_center``, ``dyn_scale`` (13,),
        ``dyn_means`` (g, 13), ``dyn_precisions`` (g, 13, 13) are in ``arrays``.
    """

    feature_set: str
    frame: str
    feature_names: list[str]
    classes: list[str]
    positions: dict
    quantile: float
    distance_threshold: float
    distance_threshold_in_sample: float
    gravity_check: bool
    gravity_threshold_rad: float
    gravity_threshold_in_sample_rad: float
    arrays: dict
    summary: dict = dataclasses.field(default_factory=dict)
    dynamics: dict | None = None

    # ---- persistence (JSON + plain arrays; no pickle)
    def to_json(self) -> dict:
        """The ``domain`` entry of ``model.json`` (the arrays go to ``arrays.npz``)."""
        return {
            "version": DOMAIN_VERSION,
            "feature_set": self.feature_set,
            "frame": self.frame,
            "feature_names": list(self.feature_names),
            "classes": list(self.classes),
            "positions": {str(k): int(v) for k, v in self.positions.items()},
            "quantile": float(self.quantile),
            "distance_threshold": float(self.distance_threshold),
            "distance_threshold_in_sample": float(self.distance_threshold_in_sample),
            "gravity_check": bool(self.gravity_check),
            "gravity_threshold_rad": float(self.gravity_threshold_rad),
            "gravity_threshold_in_sample_rad": float(self.gravity_threshold_in_sample_rad),
            "arrays": [ARRAY_PREFIX + k for k in self._array_names()],
            "summary": self.summary,
            **({"dynamics": dict(self.dynamics)} if self.dynamics is not None else {}),
        }

    def _array_names(self) -> tuple[str, ...]:
        return _ARRAYS + (_DYN_ARRAYS if self.dynamics is not None else ())

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The arrays to store in ``arrays.npz`` (names prefixed ``domain__``)."""
        return {ARRAY_PREFIX + k: np.asarray(self.arrays[k], dtype=float) for k in self._array_names()}

    @classmethod
    def from_json(cls, info: dict, arrays: dict[str, np.ndarray]) -> DomainModel:
        """Rebuild from the ``domain`` entry and the ``domain__`` arrays; ModelError when they do not fit."""
        try:
            if int(info["version"]) != DOMAIN_VERSION:
                raise ModelError(f"domain record version {info['version']} is not {DOMAIN_VERSION}; retrain the model with this gaitml.")
            arr = {k: np.asarray(arrays[ARRAY_PREFIX + k], dtype=float) for k in _ARRAYS}
            names = [str(n) for n in info["feature_names"]]
            classes = [str(c) for c in info["classes"]]
            p, c = len(names), len(classes)
            shapes = {
                "center": (p,),
                "scale": (p,),
                "feature_lo": (p,),
                "feature_hi": (p,),
                "class_means": (c, p),
                "class_precisions": (c, p, p),
            }
            for k, shp in shapes.items():
                if arr[k].shape != shp:
                    raise ValueError(f"{k} has shape {arr[k].shape}, expected {shp}")
            if arr["gravity_dirs"].ndim != 2 or arr["gravity_dirs"].shape[1] != 3:
                raise ValueError(f"gravity_dirs has shape {arr['gravity_dirs'].shape}, expected (m, 3)")
            dyn = info.get("dynamics")
            if dyn is not None:  # the optional orientation-dynamics part (records without it check as before)
                dyn = {
                    "labels": [str(v) for v in dyn["labels"]],
                    "span": int(dyn["span"]),
                    # records written before the grid was fitted on every window: checked on every window
                    "every": int(dyn.get("every", 1)),
                    "threshold": float(dyn["threshold"]),
                    "threshold_in_sample": float(dyn["threshold_in_sample"]),
                }
                arr.update({k: np.asarray(arrays[ARRAY_PREFIX + k], dtype=float) for k in _DYN_ARRAYS})
                q, g = len(DYNAMICS_NAMES), len(dyn["labels"])
                for k, shp in {"dyn_center": (q,), "dyn_scale": (q,), "dyn_means": (g, q), "dyn_precisions": (g, q, q)}.items():
                    if arr[k].shape != shp:
                        raise ValueError(f"{k} has shape {arr[k].shape}, expected {shp}")
                if dyn["span"] < 1:
                    raise ValueError(f"dynamics span {dyn['span']} is below 1")
                if dyn["every"] < 1 or dyn["span"] % dyn["every"]:
                    raise ValueError(f"dynamics grid step {dyn['every']} does not divide the span {dyn['span']}")
            return cls(
                feature_set=str(info["feature_set"]),
                frame=str(info["frame"]),
                feature_names=names,
                classes=classes,
                positions={str(k): int(v) for k, v in dict(info["positions"]).items()},
                quantile=float(info["quantile"]),
                distance_threshold=float(info["distance_threshold"]),
                distance_threshold_in_sample=float(info["distance_threshold_in_sample"]),
                gravity_check=bool(info["gravity_check"]),
                gravity_threshold_rad=float(info["gravity_threshold_rad"]),
                gravity_threshold_in_sample_rad=float(info["gravity_threshold_in_sample_rad"]),
                arrays=arr,
                summary=dict(info.get("summary") or {}),
                dynamics=dyn,
            )
        except ModelError:
            raise
        except (KeyError, TypeError, ValueError) as exc:
            raise ModelError(
                f"the model's domain record does not fit its arrays ({type(exc).__name__}: {' '.join(str(exc).split())[:160]}); "
                "retrain the model (gaitml train CONFIG)."
            ) from exc

    # ---- the check
    def _factors(self) -> tuple[np.ndarray, np.ndarray]:
        """Stacked Cholesky factors ``[L_1 .. L_c]`` (p, c p) of the precisions and ``m_c L_c`` (c p,), cached.

        ``(z - m_c)^T P_c (z - m_c) = |z L_c - m_c L_c|^2`` with ``P_c = L_c L_c^T``: one
        matrix product serves every class.
        """
        cache = getattr(self, "_factor_cache", None)
        if cache is None:
            precs, means = self.arrays["class_precisions"], self.arrays["class_means"]
            try:
                chol = np.linalg.cholesky(precs)  # (c, p, p)
            except np.linalg.LinAlgError as exc:
                raise ModelError("the domain record's precision matrices are not positive definite; retrain the model.") from exc
            stacked = np.ascontiguousarray(np.concatenate(list(chol), axis=1))
            offset = np.concatenate([m @ c for m, c in zip(means, chol, strict=True)])
            cache = (stacked, offset)
            object.__setattr__(self, "_factor_cache", cache)
        return cache

    def distances(self, X) -> np.ndarray:
        """Feature distance of every row of ``X`` (raw feature units, columns ``feature_names``).

        From :data:`_BLOCKED_MIN_ROWS` rows on, the distances are float32-accurate (about
        1e-7 relative) except within a rounding-error bound of ``distance_threshold``,
        where they are float64: ``distance <= distance_threshold`` is the float64 decision
        on every row (:meth:`_certified_distances`). Fewer rows (a stream's one window): float64.
        """
        X = np.asarray(X, dtype=float)
        if X.ndim != 2 or X.shape[1] != len(self.feature_names):
            raise ModelError(f"the domain check takes {len(self.feature_names)} features, got shape {X.shape}; retrain the model.")
        if not len(X):
            return np.zeros(0)
        finite = np.isfinite(X).all(axis=1)
        all_finite = bool(finite.all())
        # plain array operations (no nan_to_num, no einsum): a one-window call (streaming) costs tens of
        # microseconds, not hundreds (benchmarks/models.py stream-domain-check-per-window); rows with a
        # non-finite feature are out of domain (distance inf) whatever their other features
        Xf = X if all_finite else np.where(np.isfinite(X), X, 0.0)
        d = self._certified_distances(Xf) if len(X) >= _BLOCKED_MIN_ROWS else None  # float32, exact where a flag is at stake
        if d is None:
            d = self._stacked_distances((Xf - self.arrays["center"]) / self.arrays["scale"])
        if not all_finite:
            d[~finite] = np.inf
        return d

    def _stacked_distances(self, Z: np.ndarray) -> np.ndarray:
        """Smallest Mahalanobis distance of standardised rows ``Z`` to the classes: one product with the stacked factors."""
        stacked, offset = self._factors()
        with np.errstate(invalid="ignore", over="ignore"):
            Y = Z @ stacked  # in place from here: the same arithmetic without two more (n, c p) temporaries
            Y -= offset
            Y *= Y
            return np.sqrt(Y.reshape(len(Z), -1, Z.shape[1]).sum(axis=2).min(axis=1))

    def _factor_blocks(self) -> list[tuple[int, int, np.ndarray]]:
        """The stacked factors of :meth:`_factors` cut into column blocks without their zero rows, with the standardisation folded in; cached.

        ``L_c`` is lower triangular: its columns ``[j0, j1)`` are zero above row ``j0``. With
        ``F`` (p - j0, c (j1 - j0)) the rows ``j0:`` of those columns of every class and ``o``
        the matching entries of the offsets ``m_c L_c``, the block's entries of ``z L - m L``
        for a raw feature row ``x`` (``z = (x - center) / scale``) are ``x A`` with the
        augmented ``x = [x_j0.., 1]`` and ``A = [F / scale; -(o + (center / scale) F)]``
        (p - j0 + 1, c (j1 - j0)): the standardisation and the offset are taken inside the one
        product instead of two more passes over the (windows x features) and (windows x
        c p) arrays. Per block ``(j0, j1, A^T)``; kept transposed: the products are taken as
        ``A^T X^T`` (windows last), which measured 15-20 % faster than ``X A`` with two BLAS threads.
        """
        cache = self.__dict__.get("_block_cache")
        if cache is None:
            stacked, offset = self._factors()
            p = len(self.feature_names)
            c = len(offset) // p
            per_class = stacked.reshape(p, c, p)  # [row, class, column]
            center, scale = self.arrays["center"], self.arrays["scale"]
            edges = np.linspace(0, p, max(1, round(p / _DISTANCE_BLOCK_COLUMNS)) + 1).round().astype(int)
            cache = []
            for j0, j1 in zip(edges[:-1].tolist(), edges[1:].tolist(), strict=True):
                F = per_class[j0:, :, j0:j1].reshape(p - j0, c * (j1 - j0))
                o = offset.reshape(c, p)[:, j0:j1].reshape(-1)
                A = np.concatenate([F / scale[j0:, None], -(o + (center[j0:] / scale[j0:]) @ F)[None, :]], axis=0)
                cache.append((j0, j1, np.ascontiguousarray(A.T)))
            object.__setattr__(self, "_block_cache", cache)
        return cache

    def _float32_blocks(self) -> tuple[list[tuple[int, int, np.ndarray]], float]:
        """The column blocks of :meth:`_factor_blocks` in float32 on standardised rows, and the error scale; cached.

        Per block ``(j0, j1, B^T)`` with ``B = [F; -o]`` (p - j0 + 1, c (j1 - j0)) in float32
        (``F``, ``o`` as in :meth:`_factor_blocks`, not folded with the standardisation: the
        rows are standardised in float64 first, which keeps the float32 products' error
        small), and ``max_c ||[L_c; -m_c L_c]||_F``, the largest Frobenius norm of a class's
        augmented factor, which bounds that error (:meth:`_certified_distances`).
        """
        cache = self.__dict__.get("_f32_cache")
        if cache is None:
            stacked, offset = self._factors()
            p = len(self.feature_names)
            c = len(offset) // p
            per_class = stacked.reshape(p, c, p)
            edges = np.linspace(0, p, max(1, round(p / _DISTANCE_BLOCK_COLUMNS)) + 1).round().astype(int)
            blocks = []
            for j0, j1 in zip(edges[:-1].tolist(), edges[1:].tolist(), strict=True):
                F = per_class[j0:, :, j0:j1].reshape(p - j0, c * (j1 - j0))
                o = offset.reshape(c, p)[:, j0:j1].reshape(-1)
                blocks.append((j0, j1, np.ascontiguousarray(np.concatenate([F, -o[None, :]], axis=0).T, dtype=np.float32)))
            norm = float(np.sqrt(np.max((per_class * per_class).sum(axis=(0, 2)) + (offset.reshape(c, p) ** 2).sum(axis=1))))
            cache = (blocks, norm)
            object.__setattr__(self, "_f32_cache", cache)
        return cache

    def _certified_distances(self, X: np.ndarray) -> np.ndarray | None:
        """Feature distances of raw finite rows ``X`` in float32, recomputed in float64 wherever the flag could differ; or None.

        The column-block products of :meth:`_blocked_distances` taken in float32 on the
        rows standardised in float64 (about 60 % of the time of the float64 products). A
        float32 distance ``d~`` differs from the exact one by at most
        ``eps = 2 (gamma + 2u) (N ||z_aug|| + d~)`` with ``u = 2^-24``, ``gamma = (p + 3) u /
        (1 - (p + 3) u)`` (Higham's bound for a sum of ``p + 1`` products), ``N`` the
        largest Frobenius norm of a class's augmented factor (:meth:`_float32_blocks`) and
        ``z_aug = [z, 1]``: the rounding of the inputs, of every product's sums (entry by
        entry at most ``gamma |B|^T |z_aug|``, whose norm Cauchy-Schwarz bounds by
        ``N ||z_aug||``) and of the sum of the squares, with a factor 2 to spare. Every
        window whose ``d~`` lies within its ``eps`` of the distance threshold (or is not
        finite) is recomputed in float64 (:meth:`_blocked_distances`): the flags
        ``distance <= threshold`` are those of the float64 distances, by construction. The
        distances themselves are float32-accurate (about 1e-7 relative, 3e-7 measured:
        ``tests/domain/test_check_cost.py``), those near the threshold float64 (the bound is
        about 0.015 for distances of 3-10: none of the 788 windows of the benchmark recording).
        None when the float64 recomputation overflows (the caller takes the one product).
        """
        n, p = X.shape
        blocks, norm = self._float32_blocks()
        c = len(blocks[0][2]) // (blocks[0][1] - blocks[0][0])
        Z = (X - self.arrays["center"]) / self.arrays["scale"]
        ZT = np.empty((p + 1, n), dtype=np.float32)  # standardised features x windows and a row of ones (the offsets)
        ZT[:p] = Z.T
        ZT[p] = 1.0
        sq = np.zeros((c, n), dtype=np.float32)
        with np.errstate(invalid="ignore", over="ignore"):
            for j0, j1, BT in blocks:
                Y = BT @ ZT[j0:]
                Y *= Y
                sq += Y.reshape(c, j1 - j0, n).sum(axis=1)
            d = np.sqrt(sq.min(axis=0), dtype=float)
            u = 2.0**-24
            gamma = (p + 3) * u / (1.0 - (p + 3) * u)
            eps = 2.0 * (gamma + 2.0 * u) * (norm * np.sqrt(np.add.reduce(Z * Z, axis=1) + 1.0) + d)
            exact = ~(np.abs(d - self.distance_threshold) > eps)  # near the threshold, or not finite (NaN compares False)
        if exact.any():
            d64 = self._blocked_distances(X[exact])
            if d64 is None:
                return None
            d[exact] = d64
        return d

    def _blocked_distances(self, X: np.ndarray) -> np.ndarray | None:
        """:meth:`_stacked_distances` of raw finite rows ``X`` without the products with the factors' zeros (batch rows), or None.

        The same quadratic forms, grouped per column block (about
        :data:`_DISTANCE_BLOCK_COLUMNS` columns): 56 % of the multiplications with the 104
        features of ``all52+gyro`` (8 blocks), 62 % with 52 (4 blocks), each block one
        matrix product that also standardises and subtracts the class offsets
        (:meth:`_factor_blocks`). Equal to the one product up to rounding (the sums in
        another order, the centre subtracted inside the product: relative differences of
        about 1e-14; ``tests/domain/test_check_cost.py``). Plain sums of the squares:
        every multi-threaded BLAS call can wait for a core on a loaded machine, so they
        are not summed with a matrix-vector product. None when a distance is not finite
        (an input so large that a sum overflows): the caller then takes the one product,
        as before.
        """
        n, p = X.shape
        blocks = self._factor_blocks()
        c = len(blocks[0][2]) // (blocks[0][1] - blocks[0][0])
        XT = np.empty((p + 1, n))  # features x windows and a row of ones (the offsets): the blocks' rows are slices of it
        XT[:p] = X.T
        XT[p] = 1.0
        sq = np.zeros((c, n))
        with np.errstate(invalid="ignore", over="ignore"):
            for j0, j1, AT in blocks:
                Y = AT @ XT[j0:]  # (c (j1 - j0), n): the block's columns of z L - m L of every class, transposed
                Y *= Y
                sq += Y.reshape(c, j1 - j0, n).sum(axis=1)  # over the block's columns of every class (no BLAS call: see above)
            d = np.sqrt(sq.min(axis=0))
        return d if np.isfinite(d).all() else None

    def gravity_angles(self, gravity) -> np.ndarray:
        """Angle (rad) of each gravity unit vector (rows, phone frame) to the nearest training direction."""
        return _nearest_angle(np.asarray(gravity, dtype=float).reshape(-1, 3), self.arrays["gravity_dirs"])

    @property
    def dynamics_every(self) -> int:
        """Every how many windows the check computes the orientation dynamics (1 without a dynamics part)."""
        return 1 if self.dynamics is None else int(self.dynamics.get("every", 1))

    def dynamics_rows(self, n: int) -> np.ndarray:
        """The windows (of ``n``, in time order) whose :func:`orientation_dynamics` :meth:`check` reads: 0, every, 2 every, ..."""
        return np.arange(0, max(0, int(n)), self.dynamics_every)

    def dynamics_distances(self, dynamics) -> np.ndarray:
        """Window dynamics distance of every row of ``dynamics`` (:func:`orientation_dynamics`); inf for non-finite rows."""
        if self.dynamics is None:
            raise ModelError("this model's domain record has no orientation-dynamics part; retrain the model to get it.")
        Q = np.asarray(dynamics, dtype=float).reshape(-1, len(DYNAMICS_NAMES))
        if not len(Q):
            return np.zeros(0)
        finite = np.isfinite(Q).all(axis=1)
        all_finite = bool(finite.all())
        cache = self.__dict__.get("_dyn_cache")
        if cache is None:
            cache = self._dynamics_factors()
        A, g = cache
        q = Q.shape[1]
        Qa = np.empty((len(Q), q + 1))  # the descriptors and a column of ones (the offsets)
        Qa[:, :q] = Q if all_finite else np.where(finite[:, None], Q, 0.0)
        Qa[:, q] = 1.0
        with np.errstate(invalid="ignore", over="ignore"):
            Y = Qa @ A  # z L - m L of every Gaussian, standardised inside the product
            Y *= Y
            # squared distance to every Gaussian: sums over its q columns as one matrix-vector product, the smallest
            d = np.sqrt((Y.reshape(-1, q) @ np.ones(q)).reshape(len(Q), g).min(axis=1))
        if not all_finite:
            d[~finite] = np.inf
        d[np.isnan(d)] = np.inf  # an input so large that a sum overflows: out of domain
        return d

    def _dynamics_factors(self) -> tuple[np.ndarray, int]:
        """The stacked Cholesky factors of the dynamics Gaussians with the standardisation folded in, cached.

        As :meth:`_factor_blocks` for the features: with ``L_g`` the Cholesky factor of
        Gaussian g's precision (lower triangular) and ``m_g`` its mean, ``z L_g - m_g L_g``
        for descriptors ``x`` (``z = (x - dyn_center) / dyn_scale``) is ``[x, 1] A_g`` with
        ``A_g = [L_g / dyn_scale; -(m_g + dyn_center / dyn_scale) L_g]``. Returns ``([A_1 .. A_g], g)``
        ((q + 1, g q), one matrix product serves every Gaussian) and the number of Gaussians.
        """
        try:
            chol = np.linalg.cholesky(self.arrays["dyn_precisions"])
        except np.linalg.LinAlgError as exc:
            raise ModelError("the domain record's dynamics precision matrices are not positive definite; retrain the model.") from exc
        center, scale = self.arrays["dyn_center"], self.arrays["dyn_scale"]
        stacked = np.concatenate(list(chol), axis=1)
        offset = np.concatenate([m @ c for m, c in zip(self.arrays["dyn_means"], chol, strict=True)])
        A = np.ascontiguousarray(np.concatenate([stacked / scale[:, None], -(offset + (center / scale) @ stacked)[None, :]], axis=0))
        cache = (A, len(chol))
        object.__setattr__(self, "_dyn_cache", cache)
        return cache

    def check(self, X, gravity=None, dynamics=None) -> dict[str, np.ndarray]:
        """In-domain flags of windows.

        Parameters
        ----------
        X : (k, p) features of the windows (``feature_names`` order, raw units).
        gravity : (k, 3) window gravity unit vectors (:func:`window_gravity`), optional;
            needed when ``gravity_check`` is on.
        dynamics : :func:`orientation_dynamics` of the windows, **all of one recording in
            time order**: of the windows :meth:`dynamics_rows` names (0, every, 2 every,
            ...; what ``gaitml predict`` computes) or of all k windows (the others are
            not read). The decision uses the median of those windows' dynamics
            distances within the last ``dynamics["span"]`` windows (:func:`span_medians`);
            checked when the record has a dynamics part and this is given (``gaitml
            predict`` always gives it). Without it the dynamics part is not checked
            (one-window callers).

        Returns
        -------
        dict with ``distance`` (k,), ``gravity_angle_rad`` (k,; NaN when not checked),
        ``dynamics_distance`` (k,; the span median, NaN when not checked) and
        ``in_domain`` (k,) bool.
        """
        X = np.asarray(X, dtype=float)
        if X.shape == (1, len(self.feature_names)) and (dynamics is None or self.dynamics is None):
            # one window (streaming) without a dynamics test to make: the short path when it applies
            one = self._check_one(X, gravity)
            if one is not None:
                return one
        with one_blas_thread():  # the products of a batch: one BLAS thread (see one_blas_thread)
            return self._check_batch(X, gravity, dynamics)

    def _check_batch(self, X: np.ndarray, gravity, dynamics) -> dict[str, np.ndarray]:
        """:meth:`check` of any number of windows (the general path)."""
        d = self.distances(X)
        ok = d <= self.distance_threshold
        dyn = np.full(len(d), np.nan)
        if self.dynamics is not None and dynamics is not None:
            every = self.dynamics_every
            Q = np.asarray(dynamics, dtype=float).reshape(-1, len(DYNAMICS_NAMES))
            m = -(-len(d) // every)  # computed windows
            if len(Q) == len(d) and m != len(d):
                Q = Q[::every]  # every window given: the computed ones
            if len(Q) != m:
                raise ModelError(
                    f"the domain check got {len(d)} feature rows and {len(Q)} dynamics rows; pass one row per window "
                    f"or one per {every}-th window (DomainModel.dynamics_rows)."
                )
            # the median of the computed windows within each window's span: their running median, held (span_medians)
            dyn = running_median(self.dynamics_distances(Q), self.dynamics["span"] // every)[np.arange(len(d)) // every]
            ok &= dyn <= self.dynamics["threshold"]
        if not self.gravity_check:
            return {"distance": d, "gravity_angle_rad": np.full(len(d), np.nan), "dynamics_distance": dyn, "in_domain": ok}
        if gravity is None:
            raise ModelError("this model's domain checks the gravity direction; pass the window gravity (window_gravity).")
        ang = self.gravity_angles(gravity)
        ok &= ang <= self.gravity_threshold_rad  # a NaN angle (no gravity direction) compares False: out of domain
        return {"distance": d, "gravity_angle_rad": ang, "dynamics_distance": dyn, "in_domain": ok}

    def _one_window(self) -> tuple:
        """What the one-window check needs beyond the stored arrays, computed at its first call and cached.

        ``(stacked, offset, n_classes, center, scale, gravity_dirs.T, feature_bound, gravity_bound)``
        (:meth:`_factors`, :func:`_feature_bound`, :func:`_gravity_bound`).
        """
        cache = self.__dict__.get("_one_window_cache")
        if cache is None:
            stacked, offset = self._factors()
            a = self.arrays
            cache = (
                stacked,
                offset,
                len(self.classes),
                a["center"],
                a["scale"],
                a["gravity_dirs"].T,
                _feature_bound(a["center"], a["scale"], stacked, offset),
                _gravity_bound(a["gravity_dirs"]),
            )
            object.__setattr__(self, "_one_window_cache", cache)
        return cache

    def _check_one(self, X: np.ndarray, gravity) -> dict[str, np.ndarray] | None:
        """:meth:`check` of one window ``X`` (1, p) (streaming), or None when the general path must answer.

        The same arithmetic as :meth:`distances` and :func:`_nearest_angle` on one row
        (standardise, one product with the stacked factors, squared norms per class,
        min, sqrt; the largest cosine to the kept gravity directions, clipped, arccos),
        so the same numbers bit for bit, with a dozen array operations instead of about
        thirty (each costs about a microsecond whatever its size, which is what a
        one-window call spends its time on): the non-finite masks and ``np.errstate``
        give way to one test of the input magnitudes against bounds computed once
        (:func:`_feature_bound`, :func:`_gravity_bound`: under them nothing can overflow
        or be invalid, so nothing needs silencing). Anything else (a non-finite or huge
        input, no kept direction, gravity of another shape) returns None and goes the
        general way, which handles it as before.
        """
        stacked, offset, n_classes, center, scale, dirs_t, x_bound, g_bound = self.__dict__.get("_one_window_cache") or self._one_window()
        if self.gravity_check:
            if gravity is None:
                return None
            g = np.asarray(gravity, dtype=float)
            if g.size != 3 or not max(map(abs, g.ravel().tolist())) <= g_bound:  # inf, huge (a NaN may pass: caught below)
                return None
        if x_bound < 0 or not np.maximum.reduce(np.abs(X), axis=None) <= x_bound:  # inf, huge, NaN (compares False)
            return None
        Y = (X - center) / scale @ stacked
        Y -= offset
        Y *= Y
        sq = np.add.reduce(Y.reshape(n_classes, -1), axis=1).tolist()  # squared distance to every class (ndarray.sum without its wrapper)
        d = math.sqrt(min(sq))  # correctly rounded, as np.sqrt
        ok = d <= self.distance_threshold
        if not self.gravity_check:
            return {
                "distance": np.array([d]),
                "gravity_angle_rad": np.array([np.nan]),
                "dynamics_distance": np.array([np.nan]),
                "in_domain": np.array([ok]),
            }
        cos = float(np.maximum.reduce(g.reshape(1, 3) @ dirs_t, axis=None))  # ndarray.max without its wrapper
        if math.isnan(cos):
            return None
        ang = float(np.arccos(min(max(cos, -1.0), 1.0)))  # np.clip of a number
        return {
            "distance": np.array([d]),
            "gravity_angle_rad": np.array([ang]),
            "dynamics_distance": np.array([np.nan]),
            "in_domain": np.array([ok and ang <= self.gravity_threshold_rad]),
        }


def fit_domain(
    X,
    y,
    groups,
    gravity,
    *,
    feature_names,
    feature_set: str,
    frame: str,
    positions=None,
    quantile: float = DEFAULT_QUANTILE,
    seed: int = 0,
    dynamics=None,
    sequence=None,
    dynamics_every: int | None = None,
    dynamics_span: int | None = None,
) -> DomainModel:
    """Fit the domain record of a training set (see the module docstring).

    Parameters
    ----------
    X : (n, p) training features (raw units), ``feature_names`` order.
    y : (n,) window labels.
    groups : (n,) cross-validation group (subject) of every window; the held-out
        thresholds come from folds over these groups.
    gravity : (n, 3) window gravity unit vectors in the phone frame (:func:`window_gravity`).
    feature_names, feature_set, frame : what ``X`` is.
    positions : (n,) carrying position of every window, optional (``"unknown"``).
    quantile : threshold quantile of the held-out distances (0.5-1).
    seed : seeds the gravity-direction subset.
    dynamics : (n, 13) :func:`orientation_dynamics` of the windows, optional: when
        given, the orientation-dynamics part is recorded (one Gaussian per
        ``mode|position`` fitted on every window; threshold = the quantile of the
        held-out span medians over :data:`DYNAMICS_SPAN` windows, computed on the grid
        of every ``dynamics_every``-th window as the check does, :func:`span_medians`,
        pooled over the grid's phases: every window's statistic once per phase).
    sequence : (n,) recording of every window (the span never crosses recordings);
        needed with ``dynamics``. Rows of one recording must be in time order.
    dynamics_every : the grid step recorded with the dynamics part (default
        :func:`dynamics_grid_step` of :data:`DYNAMICS_SPAN`, i.e. :data:`DYNAMICS_EVERY`; 1 gives
        the statistic over every window of records written before the grid).
    dynamics_span : windows in the running span recorded with the dynamics part (default
        :data:`DYNAMICS_SPAN`); the grid step then defaults to :func:`dynamics_grid_step` of it.
    """
    from sklearn.model_selection import GroupKFold

    X = np.asarray(X, dtype=float)
    y = np.asarray(y).astype(str)
    groups = np.asarray(groups).astype(str)
    gravity = np.asarray(gravity, dtype=float).reshape(-1, 3)
    n = len(X)
    if not (len(y) == len(groups) == len(gravity) == n) or n < 2:
        raise ModelError(f"fit_domain needs matching rows (X {n}, y {len(y)}, groups {len(groups)}, gravity {len(gravity)}), at least 2.")
    if not 0.5 <= float(quantile) < 1.0:
        raise ModelError(f"domain quantile must be in [0.5, 1), got {quantile}.")
    span = DYNAMICS_SPAN if dynamics_span is None else int(dynamics_span)
    if span < 1:
        raise ModelError(f"the dynamics span must be at least 1 window, got {dynamics_span}.")
    if dynamics is not None:
        dynamics = np.asarray(dynamics, dtype=float)
        if dynamics.shape != (n, len(DYNAMICS_NAMES)) or sequence is None or len(sequence) != n:
            raise ModelError(f"fit_domain needs dynamics of shape ({n}, {len(DYNAMICS_NAMES)}) and one sequence id per window.")
    rng = np.random.default_rng(seed)
    classes = sorted({str(c) for c in y})
    gravity_check = frame == "phone"
    ug = np.unique(groups)
    k = min(HELDOUT_FOLDS, len(ug))
    held_d = np.full(n, np.nan)
    held_a = np.full(n, np.nan)
    held_q = np.full(n, np.nan)
    pos = np.full(n, "unknown", dtype=object) if positions is None else np.asarray(positions).astype(str)
    dyn_labels = np.char.add(np.char.add(y.astype(str), "|"), pos.astype(str)) if dynamics is not None else None
    dyn_ok = np.isfinite(dynamics).all(axis=1) if dynamics is not None else None
    if k >= 2:
        for tr, te in GroupKFold(n_splits=k).split(X, y, groups):
            if dynamics is not None:
                held_q[te] = _dynamics_fit_distance(dynamics, dyn_labels, dyn_ok, tr, te)
            c, s = _standardiser(X[tr])
            means, precs = _class_gaussians((X[tr] - c) / s, y[tr], sorted(set(y[tr])))
            held_d[te] = _min_mahalanobis((X[te] - c) / s, means, precs)
            held_a[te] = _nearest_angle(gravity[te], _subsample_dirs(gravity[tr], rng))
        scheme = f"{k}-fold over the {len(ug)} training groups (subjects)"
    else:
        scheme = "in-sample (a single training group: no held-out threshold possible)"
    center, scale = _standardiser(X)
    Z = (X - center) / scale
    means, precs = _class_gaussians(Z, y, classes)
    in_d = _min_mahalanobis(Z, means, precs)
    dirs = _subsample_dirs(gravity, rng)
    # in-sample angle: to the nearest *other* stored direction would be 0 for stored ones; use all training windows
    in_a = _nearest_angle(gravity, dirs)
    if k < 2:
        held_d, held_a = in_d, in_a
    q = float(quantile)
    fin = np.isfinite(gravity).all(axis=1)
    gmean = gravity[fin].mean(axis=0) if fin.any() else np.array([0.0, 0.0, 1.0])
    gmean = gmean / max(float(np.linalg.norm(gmean)), 1e-12)
    to_mean = np.degrees(np.arccos(np.clip(gravity[fin] @ gmean, -1, 1))) if fin.any() else np.zeros(1)
    pos_counts = {str(p): int((pos == p).sum()) for p in sorted(set(pos))}
    summary = {
        "n_windows": int(n),
        "n_groups": int(len(ug)),
        "heldout": scheme,
        "gravity_mean": [round(float(v), 4) for v in gmean],
        "gravity_angle_to_mean_deg": {f"q{int(p)}": round(float(np.percentile(to_mean, p)), 2) for p in (50, 90, 99)},
        "gravity_directions_kept": int(len(dirs)),
        "distance_threshold_heldout_vs_in_sample": [float(np.nanquantile(held_d, q)), float(np.quantile(in_d, q))],
    }
    dyn_record = None
    dyn_arrays: dict = {}
    if dynamics is not None:
        every = np.arange(n)
        in_q = _dynamics_fit_distance(dynamics, dyn_labels, dyn_ok, every, every)
        seq = np.asarray(sequence).astype(str)
        every = dynamics_grid_step(span) if dynamics_every is None else int(dynamics_every)

        def pooled(d):  # the check's statistic on the grid, each of its phases in turn (every window once per phase)
            return np.concatenate([span_medians(d, span, every, seq, phase) for phase in range(every)])

        span_held = pooled(held_q if k >= 2 else in_q)
        span_in = pooled(in_q)
        labels = sorted(set(dyn_labels[dyn_ok]))
        c_q, s_q = _standardiser(dynamics[dyn_ok])
        m_q, p_q = _class_gaussians((dynamics[dyn_ok] - c_q) / s_q, dyn_labels[dyn_ok], labels)
        dyn_record = {
            "labels": labels,
            "span": span,
            "every": every,
            "threshold": float(np.nanquantile(span_held, q)),
            "threshold_in_sample": float(np.nanquantile(span_in, q)),
        }
        dyn_arrays = {"dyn_center": c_q, "dyn_scale": s_q, "dyn_means": m_q, "dyn_precisions": p_q}
        summary["dynamics_threshold_heldout_vs_in_sample"] = [dyn_record["threshold"], dyn_record["threshold_in_sample"]]
    return DomainModel(
        feature_set=feature_set,
        frame=frame,
        feature_names=list(feature_names),
        classes=classes,
        positions=pos_counts,
        quantile=q,
        distance_threshold=float(np.nanquantile(held_d, q)),
        distance_threshold_in_sample=float(np.quantile(in_d, q)),
        gravity_check=gravity_check,
        gravity_threshold_rad=float(np.nanquantile(held_a, q)) if np.isfinite(held_a).any() else float(np.pi),
        gravity_threshold_in_sample_rad=float(np.nanquantile(in_a, q)) if np.isfinite(in_a).any() else float(np.pi),
        arrays={
            "center": center,
            "scale": scale,
            "class_means": means,
            "class_precisions": precs,
            "gravity_dirs": dirs if len(dirs) else np.zeros((0, 3)),
            "feature_lo": np.quantile(X, 0.005, axis=0),
            "feature_hi": np.quantile(X, 0.995, axis=0),
            **dyn_arrays,
        },
        summary=summary,
        dynamics=dyn_record,
    )


def _dynamics_fit_distance(Q, labels, ok, tr, te) -> np.ndarray:
    """Dynamics distances of rows ``te`` to Gaussians fitted on rows ``tr`` (finite rows only; inf for non-finite ``te`` rows)."""
    tr = tr[ok[tr]]
    c, s = _standardiser(Q[tr])
    means, precs = _class_gaussians((Q[tr] - c) / s, labels[tr], sorted(set(labels[tr])))
    out = np.full(len(te), np.inf)
    good = ok[te]
    out[good] = _min_mahalanobis((Q[te][good] - c) / s, means, precs)
    return out


def domain_from_model_info(info: dict, arrays: dict[str, np.ndarray]) -> DomainModel | None:
    """The model's :class:`DomainModel`, or None for a model saved without one."""
    dom: Any = info.get("domain")
    if dom is None:
        return None
    if not isinstance(dom, dict):
        raise ModelError("the model's domain entry in model.json is not an object; retrain the model (gaitml train CONFIG).")
    return DomainModel.from_json(dom, arrays)


def out_of_domain_fraction(in_domain) -> float | None:
    """Fraction of windows flagged out of domain; None when unknown (no domain record) or no windows."""
    flags = [v for v in np.asarray(in_domain, dtype=object).reshape(-1) if v is not None]
    if not flags:
        return None
    return float(np.mean([not bool(v) for v in flags]))


def domain_warning(model, in_domain, what: str = "windows") -> str | None:
    """The one warning line (without the ``gaitml: warning:`` prefix) for a prediction, or None.

    A model without a domain record gives :data:`NO_DOMAIN_WARNING`; otherwise a
    warning is given when more than :data:`OUT_OF_DOMAIN_WARN_FRACTION` of the
    ``what`` are out of domain.
    """
    dom = getattr(model, "domain", None)
    if dom is None:
        return NO_DOMAIN_WARNING
    frac = out_of_domain_fraction(in_domain)
    if frac is None or frac <= OUT_OF_DOMAIN_WARN_FRACTION:
        return None
    n = len(np.asarray(in_domain, dtype=object).reshape(-1))
    k = int(round(frac * n))
    positions = ", ".join(sorted(dom.positions)) or "unknown"
    return (
        f"{100 * frac:.1f} % of the {what} ({k} of {n}) lie outside the model's training domain (positions {positions}, "
        f"{dom.frame} frame); their modes are unreliable: use a model trained on recordings like this one "
        "(README: 'Is my recording in the model's domain?')"
    )
