"""Orientation-free descriptors of how a phone moves and turns in a window (the dynamics part of the domain check).

A pocket phone rotates with the thigh, a belt phone hardly rotates, a swinging hand
rotates a lot, a bag damps: :func:`orientation_dynamics` gives 13 numbers per window
that differ between those carrying positions while being unchanged by a constant
rotation of the phone. Ours, not from a paper.
"""

from __future__ import annotations

import numpy as np

from gaitml.parallel import one_blas_thread

__all__ = ["DYNAMICS_CHUNK_S", "DYNAMICS_NAMES", "DYNAMICS_RATE_HZ", "dynamics_sample_step", "orientation_dynamics"]

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
    gives a NaN row. All are unchanged by a constant rotation of the phone. Ours,
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
