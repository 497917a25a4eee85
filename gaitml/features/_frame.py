"""Feature frames: the phone's own axes, or a gravity-aligned frame found per window.

``frame = "phone"`` (the default) keeps the accelerometer and gyroscope axes of the
phone, as paper 003 sec. 3.2 does: a feature such as ``acc_y__skew`` then depends on
how the phone is held, and a model trained on a hand-held phone reads a pocket phone
with other features.

``frame = "gravity"`` expresses every window in a frame that depends on the window's
own samples only, so that a constant rotation of the phone leaves every feature
unchanged (tested to 1e-6 on rotated copies of recordings):

- **z (up)**: the unit vector of the window mean of the acceleration. The accelerometer
  measures specific force, which averages to ``+g`` upwards over a window of level
  walking, so the mean is the gravity estimate (a low-pass of 1/window length).
- **y (forward)**: the dominant horizontal direction of the window: the first principal
  axis of the acceleration with its mean removed, projected on the horizontal plane
  (the largest eigenvector of the 3 x 3 horizontal covariance; a constant rotation
  rotates it along).
- **sign of y**: a principal axis has no sign. It is chosen by physics: in walking
  (inverted pendulum) the centre of mass is lowest *and fastest* at heel strike, where
  the vertical acceleration peaks, so the acceleration along the direction of travel
  is a quarter step *behind* the vertical acceleration: it follows the time derivative
  of the vertical acceleration. ``y`` is oriented so that
  ``sum_t h(t) (v(t+1) - v(t)) >= 0`` (``h`` the acceleration along ``y``, ``v`` the
  vertical one): ``y`` points along the direction of travel for walking-like gait.
- **x (right)**: ``y x z``, so ``(x, y, z)`` is right-handed like the phone frame of a
  phone held flat and pointing forward (x right, y forward, z up; DESIGN sec. 2).

The gyroscope, when used, is rotated by the same matrix (rates about right, forward,
up). The magnitudes ``acc_mag`` and ``gyr_mag`` do not depend on the frame.

What this frame can and cannot tell apart (its limits):

- The direction the person *faces* is not in the window's acceleration; the frame is
  tied to the direction of *travel*. Forward and backward walking therefore differ
  only by what is not mirror-symmetric in time and body: toe-first versus heel-first
  contact, the step shape and cadence, the lateral sway at half the step frequency,
  the phone's pitching. The sign rule does not flip them onto each other; it does not
  make them more different either.
- Running (spring-mass) has the opposite phase (slowest at mid-stance, where the
  vertical acceleration peaks), so for running ``y`` points backwards; this is
  consistent from window to window, so a classifier sees one pattern per mode.
- Side steps: the dominant horizontal direction is the sideways travel; left and right
  side steps are mirror images, told apart only by the body's own asymmetries (e.g.
  which way the phone hand and the trunk sway), not by the frame.
- Windows without a dominant horizontal direction (standing still: isotropic noise)
  have an arbitrary forward axis; their x/y statistics are noise either way.
- Windows in which the phone turns a lot (a swinging arm) get the *average* vertical
  over the window; the tilt inside the window stays in the signal.
- Only proper rotations (det +1) are removed; a mirrored axis convention is not.
"""

from __future__ import annotations

import numpy as np

from gaitml.errors import InputError

__all__ = ["FEATURE_FRAMES", "check_frame", "gravity_frame_rotations", "rotate_windows"]

#: The feature frames (``features.frame`` in configs, ``gaitml features --frame``).
FEATURE_FRAMES = ("phone", "gravity")
#: Windows per block when gathering samples (bounds temporary memory).
_BLOCK = 512
#: A window mean below this (m/s^2) has no usable gravity direction (free fall): phone z is used.
_MIN_GRAVITY_MS2 = 1e-6


def check_frame(frame: str) -> str:
    """Return ``frame`` when it is a known feature frame, else raise InputError."""
    if frame not in FEATURE_FRAMES:
        raise InputError(f"unknown feature frame {frame!r}; choose one of {', '.join(FEATURE_FRAMES)}.")
    return frame


def _rotations_block(w: np.ndarray) -> np.ndarray:
    """(k, 3, L) acceleration windows -> (k, 3, 3) rotation matrices (rows x, y, z)."""
    k, _, n = w.shape
    mean = w.mean(axis=-1)  # (k, 3)
    norm = np.linalg.norm(mean, axis=1)
    z = np.where(norm[:, None] > _MIN_GRAVITY_MS2, mean / np.maximum(norm, _MIN_GRAVITY_MS2)[:, None], np.array([0.0, 0.0, 1.0]))
    d = w - mean[..., None]
    vz = np.einsum("kc,kcl->kl", z, d)  # vertical component (k, L)
    h = d - z[:, :, None] * vz[:, None, :]  # horizontal part (k, 3, L)
    cov = np.einsum("kal,kbl->kab", h, h) / n
    _, vecs = np.linalg.eigh(cov)  # ascending eigenvalues
    y = vecs[:, :, -1]
    y = y - z * np.einsum("kc,kc->k", y, z)[:, None]  # exactly horizontal
    yn = np.linalg.norm(y, axis=1)
    bad = yn < 1e-12  # no horizontal direction at all: any horizontal unit vector
    if bad.any():
        ref = np.where(np.abs(z[bad, 0:1]) < 0.9, np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0]]))
        alt = np.cross(z[bad], ref)
        y[bad] = alt
        yn[bad] = np.linalg.norm(alt, axis=1)
    y = y / yn[:, None]
    # sign: horizontal acceleration follows the derivative of the vertical one (module docstring)
    hy = np.einsum("kc,kcl->kl", y, d)
    s = np.einsum("kl,kl->k", hy[:, :-1], vz[:, 1:] - vz[:, :-1])
    y = np.where((s < 0)[:, None], -y, y)
    x = np.cross(y, z)
    return np.stack([x, y, z], axis=1)


def gravity_frame_rotations(acc, starts, length: int) -> np.ndarray:
    """Rotation into the gravity-aligned frame of every window ``[start, start + length)``.

    Parameters
    ----------
    acc : array, shape (n, 3)
        Acceleration in m/s^2, gravity included, phone frame.
    starts : array of int, shape (k,)
        Window start indices.
    length : int
        Window length in samples (>= 2).

    Returns
    -------
    ndarray, shape (k, 3, 3)
        ``R[i]`` with rows x (right), y (forward), z (up) in phone coordinates, so
        ``R[i] @ a`` expresses a phone-frame vector ``a`` of window ``i`` in its
        gravity frame. A constant rotation ``Q`` of the phone (``acc' = acc Q^T``)
        gives ``R' = R Q^T`` (the module docstring explains the construction).
    """
    acc = np.asarray(acc, dtype=float)
    starts = np.asarray(starts, dtype=np.int64).reshape(-1)
    out = np.empty((len(starts), 3, 3))
    if len(starts) == 0:
        return out
    view = np.lib.stride_tricks.sliding_window_view(acc, int(length), axis=0)  # (n-L+1, 3, L)
    for b in range(0, len(starts), _BLOCK):
        st = starts[b : b + _BLOCK]
        out[b : b + len(st)] = _rotations_block(view[st])
    return out


def rotate_windows(block: np.ndarray, rotations: np.ndarray) -> np.ndarray:
    """Rotate gathered windows ``(k, 3, L)`` by ``(k, 3, 3)`` matrices: ``R[i] @ block[i]``."""
    return np.einsum("kab,kbl->kal", rotations, block)
