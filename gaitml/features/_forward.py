"""The forward vector: a time-asymmetric feature group that tells forward from backward walking (``+fwd`` sets).

Why a new group. Every one of the 52 accelerometer features of paper 003 sec. 3.2 is the
same for a window and for that window played backwards in time: they are order-free
statistics (mean, quantiles, moments, zero-lag correlations) or sums of squared first and
second differences (M4, f(1)), which a time reversal leaves unchanged. In the body frame,
walking backwards is close to walking forwards run backwards in time (the same
inverted-pendulum gait travelling the other way), so those features see backward walking
only through amplitude and harmonic differences, and a phone held in the hand reads much of
it as walking (experiments/reports/default-model.md, "Backward in the hand").

The physics. In walking the body vaults over the stance leg like an inverted pendulum: the
centre of mass is highest and slowest at mid-stance and lowest and fastest at the double
support around heel strike, where the vertical acceleration peaks (Cavagna, Heglund and
Taylor 1977, "Mechanical work in terrestrial locomotion: two basic mechanisms for minimizing
energy expenditure", *Am. J. Physiol.* 233: R243-R261, the kinetic and potential energies in
opposite phase; Zijlstra and Hof 2003, "Assessment of spatio-temporal gait parameters from
trunk accelerations during human walking", *Gait & Posture* 18: 1-10, the inverted-pendulum
model of the trunk's vertical motion). The forward speed therefore rises while the vertical
acceleration rises and falls while it falls: the forward acceleration follows the *time
derivative* of the vertical acceleration, a quarter step behind it. The covariance of the
horizontal acceleration with that derivative,

    F = (1/N) sum_t h(t) dv/dt(t),

points along the direction of travel, sign included. It is odd under time reversal (h and v
reversed, dv/dt reversed and negated), so it separates a walk from the same walk played
backwards, which no feature of the catalogue can. Running (spring-mass: slowest at
mid-stance, where the vertical acceleration peaks) points it backwards; that is the same in
every running window, so a classifier sees one pattern per mode.

The computation, per window of N samples at ``fs`` Hz, every step a function of the window's
own samples (so batch, chunked and streamed rows are equal, as for the other features):

1. up: the unit vector of the window mean of the acceleration (the gravity estimate of the
   gravity frame, :mod:`gaitml.features._frame`);
2. each axis has its least-squares line removed and is band-passed to :data:`FORWARD_BAND_HZ`
   by zeroing the window's discrete Fourier coefficients outside the band (a zero-phase,
   per-window filter: the window is its own period);
3. v = the band-passed acceleration along up; h = the band-passed acceleration minus v up (its
   horizontal part, a 3-vector per sample);
4. dv/dt = the circular central difference ``(v[t+1] - v[t-1]) fs / 2`` (the band-passed window
   is periodic);
5. F = mean over t of h(t) dv/dt(t), a horizontal 3-vector in the phone's axes;
6. the features are F normalised by ``sqrt(mean |h|^2 mean (dv/dt)^2)``: by Cauchy-Schwarz the
   vector then has length <= 1 (1: the horizontal acceleration is one fixed direction times the
   vertical's rate), each component lies in [-1, 1], and a window without a consistent lag
   (standing, noise) gives a short vector instead of a random unit one. The scale of the
   acceleration and the sampling rate cancel. A window holding a NaN or infinite sample gives NaN
   (as the 52 statistics of :func:`gaitml.features.features_from_arrays` do), not the 0 of a window without a lag.

The three columns are F's components along the phone's x, y and z (``acc_x__fwd``,
``acc_y__fwd``, ``acc_z__fwd``): a phone held in front, screen up, top forward, reads walking
as ``acc_y__fwd`` > 0 and backward walking as < 0. With ``frame = "gravity"`` the components
are along the gravity frame's axes instead (x right, y the window's forward, z up: ``acc_z__fwd``
is 0 by construction, and ``acc_y__fwd`` is mostly positive because that frame's y is signed by
the same lag, unfiltered); the group is meant for the phone frame.

The face-up-weighted group (``acc_x__fwdface``, ... of the ``all52+fwdface`` / ``all52+gyro+fwdface``
sets) multiplies the vector by ``max(0, up_z)``, the window's gravity direction along the phone's +z:
1 for a phone lying flat, the cosine of the tilt for a phone held in front and tilted towards the
face, 0 or near it upright (a trouser pocket, a swinging hand, at the ear) or face down. The phone's y axis is the walker's forward only
when the phone is held in front, face up; upright, the vector's direction in the phone's axes depends
on the placement, and in a swinging hand the arm's swing rather than the trunk can dominate the
horizontal acceleration (checked against the motion capture of real swinging-hand walks in
experiments/reports/default-model.md SD.4). The weight keeps the group where
it is tied to the body and near 0 where it is not. It is not equivariant under a rotation of the phone
(the plain group is).

Every step is exactly odd or even under time reversal (the line fit, the Fourier mask, the
projection and the central difference commute with reversing the window), so the reversed
window gives exactly ``-F`` (a test checks it).

What it cannot do. The direction of travel is tied to the phone's axes only through how the
phone is carried: in the hand it is the phone's +y; in a pocket or the swinging hand it
depends on the placement, which the classifier has to learn from its training positions.
Side steps travel sideways and give a lateral F whose sign depends on the lead leg's braking
(experiments/reports/default-model.md, "Side-step direction"). The band's coefficients lie at
multiples of 1 / (window length): a window shorter than 1 / 3 s has none in the band and gives 0.
"""

from __future__ import annotations

import functools

import numpy as np

__all__ = ["FORWARD_BAND_HZ", "FORWARD_FACE_NAMES", "FORWARD_NAMES", "check_forward_window", "forward_vectors"]

#: The gait band (Hz) the forward vector reads. The lag it measures lives at the step frequency:
#: normal walking is at 1.6-2.4 steps/s (Ji and Pachi 2005, "Frequency and velocity of people
#: walking", *The Structural Engineer* 83(3): 36-40), slow walking below that, and adults change to
#: running at about 140 steps/min, 2.3 Hz (Hansen et al. 2017, *Sci. Rep.*, doi:10.1038/s41598-017-01972-1;
#: :data:`gaitml.models._predict.RUN_MIN_CADENCE_HZ`). 0.5 Hz keeps the slowest walking (and the
#: lateral sway at the stride frequency, which is orthogonal to the vertical's step-frequency rate
#: and adds nothing to F) and drops the phone's slow turns and tilts; 3 Hz keeps the fastest
#: walking and drops the step's higher harmonics (heel-strike transients), whose phase against the
#: vertical is not the pendulum's. How the band was chosen is told in experiments/reports/default-model.md
#: (SD.4, SD.6 and "Forward vector"). In a 1.5 s window at 50 Hz the band keeps the coefficients at 0.67, 1.33,
#: 2.00 and 2.67 Hz.
FORWARD_BAND_HZ = (0.5, 3.0)
#: The columns of the group, in order (``<channel>__<stat>``, stat ``fwd``).
FORWARD_NAMES = ("acc_x__fwd", "acc_y__fwd", "acc_z__fwd")
#: The columns of the face-up-weighted group (``+fwdface`` sets): the same vector times ``max(0, up_z)``.
FORWARD_FACE_NAMES = ("acc_x__fwdface", "acc_y__fwdface", "acc_z__fwdface")
#: A window mean below this (m/s^2) has no usable up direction (free fall): phone z is used.
_MIN_GRAVITY_MS2 = 1e-6
#: Windows per block (bounds the temporary memory).
_BLOCK = 512
#: Up to this many windows (a stream's one new window) are gathered by fancy indexing instead of a strided view,
#: whose construction costs more than the copy (as ``gaitml.features._extract._FEW_WINDOWS``).
_FEW_WINDOWS = 16
#: The up direction of a window without a usable mean (:data:`_MIN_GRAVITY_MS2`).
_PHONE_Z = np.array([0.0, 0.0, 1.0])
_PHONE_Z.setflags(write=False)


def check_forward_window(length: int, fs: float, band: tuple[float, float] = FORWARD_BAND_HZ) -> None:
    """Refuse a window of ``length`` samples at ``fs`` Hz none of whose Fourier coefficients (``k fs / length``) lies in
    ``band``: every vector would be 0, read as a window without a lag (:class:`gaitml.errors.InputError`).

    Called for the fixed-length windows of :func:`gaitml.features.extract_features`; the step windows
    (:func:`gaitml.features.extract_step_features`) keep 0 for a step too short for the band (module docstring).
    """
    from gaitml.errors import InputError

    n = int(length)
    f = np.fft.rfftfreq(n, d=1.0 / float(fs))
    if not ((f >= band[0]) & (f <= band[1])).any():
        raise InputError(
            f"a window of {n / float(fs):.3g} s ({n} samples at {float(fs):g} Hz) holds no frequency of the forward vector's "
            f"{band[0]:g}-{band[1]:g} Hz band (it needs >= {1.0 / band[1]:.3g} s); use a longer window (--window-s) or a "
            "feature set without +fwd / +fwdface."
        )


def _detrend(w: np.ndarray) -> np.ndarray:
    """Remove each row's least-squares line along the last axis (``(k, 3, N)``)."""
    n = w.shape[-1]
    t = np.arange(n, dtype=float) - (n - 1) / 2.0  # centred: the line's mean and slope are uncoupled
    tt = float(t @ t)
    mean = w.mean(axis=-1, keepdims=True)
    slope = (w @ t)[..., None] / tt if tt > 0 else 0.0
    return w - mean - slope * t


@functools.lru_cache(maxsize=32)
def _band_operators(n: int, fs: float, band: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """The module docstring's steps 2-4 for windows of ``n`` samples as two (N, N) matrices, transposed for ``w @ op``.

    ``bp_op``: detrend, then the zero-phase Fourier mask that keeps the coefficients ``k fs / n`` inside ``band``;
    ``dbp_op``: the same followed by the circular central difference ``(x[t+1] - x[t-1]) fs / 2``. Both are linear in
    the window, so building them once by passing the identity through those steps gives the same numbers as applying
    the steps to every window (to rounding), with two matrix products in place of a detrend, an FFT pair and a roll
    per window (the streaming extractor calls this once per window).
    """
    eye = np.eye(n)
    spec = np.fft.rfft(_detrend(eye[None]), axis=-1)[0]
    f = np.fft.rfftfreq(n, d=1.0 / fs)
    keep = (f >= band[0]) & (f <= band[1])
    spec[:, ~keep] = 0.0
    bp = np.fft.irfft(spec, n=n, axis=-1)  # row i: the band-passed unit impulse at sample i
    dbp = (np.roll(bp, -1, axis=-1) - np.roll(bp, 1, axis=-1)) * (fs / 2.0)
    bp.setflags(write=False)
    dbp.setflags(write=False)
    return bp, dbp


def _forward_block(w: np.ndarray, fs: float, band: tuple[float, float], face_up: bool = False) -> np.ndarray:
    """(k, 3, N) acceleration windows (phone frame) -> (k, 3) normalised forward vectors (phone frame).

    ``face_up``: each vector times ``max(0, up_z)``, the window's gravity direction along the phone's +z.
    """
    k, _, n = w.shape
    mean = np.add.reduce(w, axis=-1) / n  # w.mean(axis=-1) and np.linalg.norm(mean, axis=1), without their call overhead
    norm = np.sqrt(np.add.reduce(mean * mean, axis=1))
    up = np.where(norm[:, None] > _MIN_GRAVITY_MS2, mean / np.maximum(norm, _MIN_GRAVITY_MS2)[:, None], _PHONE_Z)
    bp_op, dbp_op = _band_operators(int(n), float(fs), (float(band[0]), float(band[1])))
    bp = w @ bp_op  # (k, 3, N), detrended and zero-phase band-passed
    v = np.einsum("kc,kcl->kl", up, bp)
    h = bp - up[:, :, None] * v[:, None, :]
    dv = np.einsum("kc,kcl->kl", up, w @ dbp_op)  # the rate of the band-passed vertical part
    fwd = np.einsum("kcl,kl->kc", h, dv) / n
    den = np.sqrt(np.einsum("kcl,kcl->k", h, h) / n * np.einsum("kl,kl->k", dv, dv) / n)
    out = np.zeros((k, 3))
    np.divide(fwd, den[:, None], out=out, where=(den > 1e-12)[:, None])  # 0 where there is no lag
    if face_up:
        out *= np.maximum(up[:, 2], 0.0)[:, None]
    finite = np.isfinite(w).all(axis=(1, 2))
    if not finite.all():
        out[~finite] = np.nan  # a non-finite sample: no vector (as the 52 statistics), not a calm 0
    return out


def forward_vectors(
    acc,
    fs: float,
    starts,
    length: int,
    rotations: np.ndarray | None = None,
    band: tuple[float, float] = FORWARD_BAND_HZ,
    *,
    face_up: bool = False,
) -> np.ndarray:
    """The normalised forward vector of every window ``[start, start + length)`` (the module docstring's steps).

    Parameters
    ----------
    acc : array, shape (n, 3)
        Acceleration in m/s^2, gravity included, phone frame.
    fs : float
        Sampling rate in Hz (sets which Fourier coefficients are in the band and the derivative's scale).
    starts : array of int, shape (k,)
    length : int
        Window length in samples (>= 2).
    rotations : array, shape (k, 3, 3), optional
        Rows x, y, z of each window's feature frame in phone coordinates
        (:func:`gaitml.features.gravity_frame_rotations`); the vectors are expressed in it. None: the phone's axes.
    band : (low, high) in Hz
    face_up : bool
        Weight each vector by ``max(0, up_z)``, how face up the phone is (the ``+fwdface`` sets; the module docstring).

    Returns
    -------
    ndarray, shape (k, 3)
        Columns :data:`FORWARD_NAMES`; each row has length <= 1; NaN for a window holding a NaN or infinite sample.
    """
    acc = np.asarray(acc, dtype=float)
    starts = np.asarray(starts, dtype=np.int64).reshape(-1)
    out = np.zeros((len(starts), 3))
    if len(starts) == 0:
        return out
    if len(starts) <= _FEW_WINDOWS:
        # the same (k, 3, L) array as the strided view's copy below, in the same memory order (each window's (L, 3)
        # samples contiguous; the matrix products of _forward_block round by that order)
        w = acc[starts[:, None] + np.arange(int(length))].transpose(0, 2, 1)
        out = _forward_block(w, float(fs), band, face_up)
    else:
        view = np.lib.stride_tricks.sliding_window_view(acc, int(length), axis=0)  # (n-L+1, 3, L), no copy
        for b in range(0, len(starts), _BLOCK):
            st = starts[b : b + _BLOCK]
            out[b : b + len(st)] = _forward_block(np.asarray(view[st]), float(fs), band, face_up)
    if rotations is not None:
        out = np.einsum("kab,kb->ka", rotations, out)
    return out
