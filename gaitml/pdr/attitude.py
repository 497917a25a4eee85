"""Phone attitude by quaternion integration of the gyroscope, and the heading it implies.

Paper 003 sec. 4.2 computes the attitude with the quaternion method (eqs. 14-15), maps
the angular rate to the navigation frame with C_b^n and integrates it to a heading.
Here the body-to-navigation rotation is propagated with the body angular rate,
``q_k = q_{k-1} (x) exp(omega dt / 2)`` (trapezoidal rate), starting from the tilt given
by gravity (mean of the first ``init_window_s`` of acc) and a chosen initial heading.
The heading is the compass yaw of the phone's forward axis projected on the horizontal
plane (DESIGN sec. 2: x east, y north, clockwise from north).

Navigation frame: x east, y north, z up. Phone frame: x right, y forward (top of the
phone), z out of the screen (up when the phone lies flat), as in
:func:`gaitml.signal.tilt_angles`.

Pure integration lets gyro bias tip the estimated vertical over time, which then
leaks into the heading. ``gravity_gain_hz > 0`` adds a complementary (Mahony-style)
correction toward the low-passed gravity direction: the body rate is augmented by
``gain * (up_measured x up_estimated)``. ``gravity_gain_hz = 0`` is the literal
paper method (vectorised as a parallel prefix product of the per-sample rotations).

References
----------
Paper 003 sec. 4.2, eqs. (14)-(15).
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np
from scipy.spatial.transform import Rotation

from gaitml._base import NON_NEGATIVE, POSITIVE, BaseAlgorithm
from gaitml.errors import InputError
from gaitml.signal import gravity_direction
from gaitml.signal._gyro_bias import GyroBias, estimate_gyro_bias, steady_tilt_mask

__all__ = [
    "AttitudeEstimator",
    "compass_heading",
    "initial_attitude",
    "integrate_gyro",
    "integrate_gyro_gravity",
    "step_headings",
    "wrap_angle",
]

#: Phone axis that points where the person faces when the phone is held in front (body +y).
FORWARD_AXIS_BODY = (0.0, 1.0, 0.0)


def wrap_angle(a):
    """Wrap angles to [-pi, pi)."""
    return (np.asarray(a, dtype=float) + np.pi) % (2 * np.pi) - np.pi


def compass_heading(vec_nav: np.ndarray) -> np.ndarray:
    """Compass heading (clockwise from north, rad) of navigation-frame vectors (..., 3)."""
    v = np.asarray(vec_nav, dtype=float)
    return np.arctan2(v[..., 0], v[..., 1])


def initial_attitude(up_body, *, heading_rad: float = 0.0, forward_axis_body=FORWARD_AXIS_BODY) -> Rotation:
    """Body-to-navigation rotation with the given gravity ("up") direction and heading.

    Parameters
    ----------
    up_body : (3,) unit vector of "up" in the phone frame (a resting accelerometer reads +g up).
    heading_rad : compass heading of the projected forward axis.
    forward_axis_body : (3,) the phone axis that points forward.

    Notes
    -----
    When the forward axis is (nearly) vertical the projection is undefined; the phone's
    -z axis (the back of a phone held upright, screen toward the user) is used instead.
    """
    up = np.asarray(up_body, dtype=float)
    up = up / np.linalg.norm(up)
    fwd = np.asarray(forward_axis_body, dtype=float)
    f = fwd - (fwd @ up) * up
    if np.linalg.norm(f) < 0.2:
        alt = np.array([0.0, 0.0, -1.0])
        f = alt - (alt @ up) * up
    north = f / np.linalg.norm(f)
    east = np.cross(north, up)
    level = Rotation.from_matrix(np.vstack([east, north, up]))  # rows: nav axes in body -> body to nav
    return Rotation.from_euler("z", -heading_rad) * level


def _qmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product of scalar-last quaternions, vectorised over leading axes."""
    ax, ay, az, aw = np.moveaxis(a, -1, 0)
    bx, by, bz, bw = np.moveaxis(b, -1, 0)
    return np.stack(
        [
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        ],
        axis=-1,
    )


def _rate_increments(gyr_rads: np.ndarray, sampling_rate_hz: float) -> np.ndarray:
    """Per-sample body rotation quaternions (trapezoidal rate), shape (n, 4); the first is identity."""
    w = np.asarray(gyr_rads, dtype=float)
    dt = 1.0 / sampling_rate_hz
    mid = np.empty_like(w)
    mid[0] = 0.0
    mid[1:] = 0.5 * (w[1:] + w[:-1])
    return Rotation.from_rotvec(mid * dt).as_quat()


def integrate_gyro(gyr_rads: np.ndarray, sampling_rate_hz: float, initial: Rotation) -> Rotation:
    """Pure quaternion integration of body rates from ``initial`` (paper 003 sec. 4.2).

    Vectorised as an inclusive prefix product (Hillis-Steele scan, log2(n) numpy passes)
    of the per-sample increments: rotation composition is associative.

    Returns a stacked :class:`~scipy.spatial.transform.Rotation` of n body-to-nav attitudes.
    """
    q = _rate_increments(gyr_rads, sampling_rate_hz)
    q[0] = initial.as_quat()
    d = 1
    n = len(q)
    while d < n:
        q[d:] = _qmul(q[:-d], q[d:])
        q[d:] /= np.linalg.norm(q[d:], axis=1, keepdims=True)
        d *= 2
    return Rotation.from_quat(q)


def integrate_gyro_gravity(
    gyr_rads: np.ndarray,
    up_body: np.ndarray,
    sampling_rate_hz: float,
    initial: Rotation,
    gain_hz: float,
    *,
    bias_gain: float = 0.0,
    initial_bias_rads=(0.0, 0.0, 0.0),
    max_bias_rads: float = 0.3,
    bias_update=None,
    return_bias: bool = False,
):
    """Quaternion integration with a complementary pull of the vertical toward ``up_body``.

    Parameters
    ----------
    gyr_rads : (n, 3) body rates.
    up_body : (n, 3) measured unit up direction in the phone frame (low-passed acc).
    gain_hz : correction gain (1/s); the tilt error decays with time constant 1 / gain.
    bias_gain : integral gain (1/s^2) of an online gyroscope-bias estimate, the explicit
        complementary filter of Mahony, Hamel & Pflimlin (IEEE TAC 2008, eq. 32-33):
        ``omega = gyr - b + gain * c`` and ``db/dt = -bias_gain * c`` with
        ``c = up_measured x up_estimated``. 0 (default) keeps the bias fixed at
        ``initial_bias_rads``. Only the bias components across the vertical are observed
        at any instant; a phone whose orientation changes (swinging, pockets) reveals all
        three over time.
    initial_bias_rads : (3,) bias subtracted from the first sample on (rad/s).
    max_bias_rads : each bias component is clipped to +-this (rad/s), so a long stretch of
        acceleration that misreads the vertical cannot run the estimate away.
    bias_update : (n,) bool, optional; the samples at which the bias estimate may move
        (where the measured vertical is trusted, :func:`bias_update_mask`); all by default.
    return_bias : also return the (n, 3) bias estimate per sample.

    Returns
    -------
    Rotation of n body-to-nav attitudes, or ``(Rotation, bias (n, 3))`` with ``return_bias``.

    Notes
    -----
    A sequential loop over samples on plain floats (the feedback makes it inherently
    sequential); yaw about the true vertical is not observed by gravity and is left to
    the gyro.
    """
    w = np.asarray(gyr_rads, dtype=float)
    up = np.asarray(up_body, dtype=float)
    dt = 1.0 / sampling_rate_hz
    n = len(w)
    # pre-computed with numpy: trapezoidal rate increments (rad) and the gain-scaled up vectors
    mid = np.zeros_like(w)
    mid[1:] = 0.5 * (w[1:] + w[:-1]) * dt
    kdt = float(gain_hz) * dt
    kidt = float(bias_gain) * dt
    bmax = float(max_bias_rads)
    bx, by, bz = (float(v) for v in np.asarray(initial_bias_rads, dtype=float).reshape(3))
    track = return_bias or kidt != 0.0
    gate = [True] * n if bias_update is None else np.asarray(bias_update, dtype=bool).tolist()
    bias_out = [(bx, by, bz)]
    mx_l, my_l, mz_l = (up[:, j] for j in range(3))
    wx_l, wy_l, wz_l = (mid[:, j] for j in range(3))
    mx_l, my_l, mz_l, wx_l, wy_l, wz_l = (a.tolist() for a in (mx_l, my_l, mz_l, wx_l, wy_l, wz_l))
    x, y, z, s = (float(v) for v in initial.as_quat())
    out = [(x, y, z, s)]
    append = out.append
    sqrt, sin, cos = math.sqrt, math.sin, math.cos
    for i in range(1, n):
        # estimated up in body = R^T e_z (third row of R)
        ex = 2.0 * (x * z - s * y)
        ey = 2.0 * (y * z + s * x)
        ez = 1.0 - 2.0 * (x * x + y * y)
        mx, my, mz = mx_l[i], my_l[i], mz_l[i]
        # c = measured x estimated up
        cx = my * ez - mz * ey
        cy = mz * ex - mx * ez
        cz = mx * ey - my * ex
        # rotation vector of this sample: (omega - b + k c) dt
        ox = wx_l[i] - bx * dt + kdt * cx
        oy = wy_l[i] - by * dt + kdt * cy
        oz = wz_l[i] - bz * dt + kdt * cz
        if track and gate[i]:
            bx = min(bmax, max(-bmax, bx - kidt * cx))
            by = min(bmax, max(-bmax, by - kidt * cy))
            bz = min(bmax, max(-bmax, bz - kidt * cz))
        if track:
            bias_out.append((bx, by, bz))
        ang = sqrt(ox * ox + oy * oy + oz * oz)
        if ang > 1e-12:
            sc = sin(0.5 * ang) / ang
            dx, dy, dz, dw = ox * sc, oy * sc, oz * sc, cos(0.5 * ang)
        else:
            dx, dy, dz, dw = 0.5 * ox, 0.5 * oy, 0.5 * oz, 1.0
        # q = q (x) d
        x, y, z, s = (
            s * dx + x * dw + y * dz - z * dy,
            s * dy - x * dz + y * dw + z * dx,
            s * dz + x * dy - y * dx + z * dw,
            s * dw - x * dx - y * dy - z * dz,
        )
        nrm = 1.0 / sqrt(x * x + y * y + z * z + s * s)
        x, y, z, s = x * nrm, y * nrm, z * nrm, s * nrm
        append((x, y, z, s))
    rot = Rotation.from_quat(np.asarray(out))
    if not return_bias:
        return rot
    bias = np.asarray(bias_out) if track else np.tile([bx, by, bz], (n, 1))
    return rot, bias


#: values of ``AttitudeEstimator(gyro_bias=...)`` given by name
GYRO_BIAS_MODES = ("auto", "still", "off")
#: :class:`~gaitml.signal.GyroBias` methods of a bias measured outside the recording (``start_bias``)
MEASURED_ELSEWHERE = ("still-recording", "file", "given")


def _online_summary(start: GyroBias, bias: np.ndarray, fs: float) -> GyroBias:
    """The removed bias of an online run: the median of the tracked estimate over the second half."""
    half = bias[len(bias) // 2 :]
    med = np.median(half, axis=0) if len(half) else start.bias_rads
    b = np.degrees(med)
    if start.method == "still":
        how, method = f"from {start.still_s:.1f} s still, then", "still+online"
    elif start.method in MEASURED_ELSEWHERE:
        how, method = f"from {start.source or start.method} ({start.method}), then", f"{start.method}+online"
    else:
        how, method = "from zero (no still stretch), then", "online"
    return GyroBias(
        med,
        method,
        still_s=start.still_s,
        n_still_windows=start.n_still_windows,
        note=f"gyroscope bias removed, {how} tracked online: median ({b[0]:.2f}, {b[1]:.2f}, {b[2]:.2f}) deg/s over the second half",
        params={**start.params, "start_bias_rads": [float(v) for v in start.bias_rads]},
        source=start.source,
    )


def step_headings(heading_rad: np.ndarray, start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """Mean heading over each step window ``[start, end)`` (on the unwrapped angle), wrapped.

    Vectorised with a cumulative sum of the unwrapped per-sample heading.
    """
    h = np.unwrap(np.asarray(heading_rad, dtype=float))
    start = np.asarray(start, dtype=np.int64)
    end = np.asarray(end, dtype=np.int64)
    if len(start) == 0:
        return np.zeros(0)
    if (end <= start).any() or start.min() < 0 or end.max() > len(h):
        raise InputError(f"step windows must satisfy 0 <= start < end <= {len(h)}; check the step table matches the recording.")
    c = np.concatenate([[0.0], np.cumsum(h)])
    return wrap_angle((c[end] - c[start]) / (end - start))


class AttitudeEstimator(BaseAlgorithm):
    """Attitude and heading of a hand-held phone from acc + gyro.

    Parameters
    ----------
    initial_heading_rad : float, default 0.0
        Compass heading of the phone's forward axis at the first sample. Without a
        magnetometer it is unobservable; 0 means "the first direction is north", which
        suits heuristic drift elimination when the walk starts along a corridor.
    init_window_s : float
        Length of the initial segment whose mean acc gives the initial tilt.
    gravity_gain_hz : float
        Complementary tilt correction toward the low-passed gravity (0 = pure
        integration as in paper 003). Default 0.5 1/s (time constant 2 s).
    gravity_cutoff_hz : float
        Low-pass cutoff of the measured gravity direction.
    forward_axis_body : (3,) float
        Phone axis taken as forward (default the y axis).
    gyro_bias : {'auto', 'still', 'off'} or (3,) float, default 'auto'
        Gyroscope bias removed before integration. ``still``: the median rate over the
        recording's still stretches (:func:`gaitml.signal.estimate_gyro_bias`); nothing is
        removed when the phone never rests. ``auto``: the same start value, then tracked
        online by the complementary filter's integral term (Mahony et al. 2008, gain
        ``bias_gain``; needs ``gravity_gain_hz > 0``, else as ``still``), which also
        serves recordings without a still stretch. ``off``: the rate as logged (paper 003
        sec. 4.2 integrates it so). An array: that bias (rad/s), e.g. from a static
        calibration recording.
    bias_gain : float, default 0.05
        Integral gain (1/s^2) of the online bias estimate of ``gyro_bias='auto'``: a tenth
        of ``gravity_gain_hz``'s default, the proportional-to-integral ratio commonly used
        with Mahony's filter (bias time constant of tens of seconds).
    start_bias : :class:`gaitml.signal.GyroBias` or None, default None
        With ``gyro_bias`` ``'still'`` or ``'auto'``: the bias to start from in place of the
        recording's own still stretches, measured elsewhere (e.g. :func:`gaitml.signal.gyro_bias_from_still`
        of a recording of the same phone lying still, or :func:`gaitml.signal.read_gyro_bias_json`).
        ``'still'`` then holds it for the whole recording, ``'auto'`` tracks it online from there
        (``gyro_bias_.method`` gets ``'+online'``). Ignored with ``'off'`` or an array.

    Attributes
    ----------
    rotation_ : scipy Rotation, n body-to-navigation attitudes.
    heading_rad_ : (n,) compass heading of the projected forward axis, wrapped to [-pi, pi).
    gyro_bias_ : :class:`gaitml.signal.GyroBias`, what was removed (``to_dict()`` for JSON).
    bias_rads_ : (n, 3) the bias subtracted at every sample (constant unless tracked online).
    """

    _action_method = "estimate"
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "init_window_s": [POSITIVE],
        "gravity_cutoff_hz": [POSITIVE],
        "gravity_gain_hz": [NON_NEGATIVE],
        "bias_gain": [NON_NEGATIVE],
    }

    def __init__(
        self,
        *,
        initial_heading_rad: float = 0.0,
        init_window_s: float = 1.0,
        gravity_gain_hz: float = 0.5,
        gravity_cutoff_hz: float = 0.3,
        forward_axis_body=FORWARD_AXIS_BODY,
        gyro_bias="auto",
        bias_gain: float = 0.05,
        start_bias: GyroBias | None = None,
    ):
        self.initial_heading_rad = initial_heading_rad
        self.init_window_s = init_window_s
        self.gravity_gain_hz = gravity_gain_hz
        self.gravity_cutoff_hz = gravity_cutoff_hz
        self.forward_axis_body = forward_axis_body
        self.gyro_bias = gyro_bias
        self.bias_gain = bias_gain
        self.start_bias = start_bias

    def _start_bias(self, recording, still: GyroBias | None = None) -> tuple[GyroBias, bool]:
        """The bias removed from the start and whether it is tracked online afterwards (``still``: the
        still-stretch estimate made elsewhere, used in place of this recording's own)."""
        gb = self.gyro_bias
        if isinstance(gb, str):
            if gb not in GYRO_BIAS_MODES:
                raise InputError(f"unknown gyro_bias {gb!r}; use one of {', '.join(GYRO_BIAS_MODES)} or a (3,) bias in rad/s.")
            if gb == "off":
                return GyroBias(np.zeros(3), "off", note="gyroscope bias removal turned off"), False
            if still is None and self.start_bias is not None:
                if not isinstance(self.start_bias, GyroBias):
                    raise InputError(f"`start_bias` must be a gaitml.signal.GyroBias, got {type(self.start_bias).__name__}.")
                still = self.start_bias
            est = estimate_gyro_bias(recording.acc, recording.gyr, recording.sampling_rate_hz) if still is None else still
            online = gb == "auto" and self.gravity_gain_hz > 0 and self.bias_gain > 0
            return est, online
        b = np.asarray(gb, dtype=float).reshape(-1)
        if b.shape != (3,) or not np.isfinite(b).all():
            raise InputError(f"`gyro_bias` as a bias must be 3 finite numbers (rad/s), got {gb!r}.")
        return GyroBias(b, "given", note=f"gyroscope bias {np.round(np.degrees(b), 2).tolist()} deg/s given, removed"), False

    def _integrate(self, gyr, acc_rec, fs, r0, start_bias: np.ndarray, online: bool, start: int = 0):
        if self.gravity_gain_hz == 0:
            rot = integrate_gyro(gyr[start:] - start_bias, fs, r0)
            return rot, np.tile(start_bias, (len(gyr) - start, 1))
        up = gravity_direction(acc_rec, fs, cutoff_hz=self.gravity_cutoff_hz)
        gate = steady_tilt_mask(acc_rec, gyr, fs)[start:] if online else None
        rot, bias = integrate_gyro_gravity(
            gyr[start:],
            up[start:],
            fs,
            r0,
            self.gravity_gain_hz,
            bias_gain=self.bias_gain if online else 0.0,
            initial_bias_rads=start_bias,
            bias_update=gate,
            return_bias=True,
        )
        self.steady_s_ = float(np.count_nonzero(gate) / fs) if online else 0.0
        return rot, bias

    def estimate(self, recording, *, still_bias: GyroBias | None = None) -> AttitudeEstimator:
        """Integrate the attitude over ``recording``; sets ``rotation_``, ``heading_rad_``, ``gyro_bias_`` and
        ``bias_rads_``, returns ``self``.

        ``still_bias``: with ``gyro_bias`` ``'still'`` or ``'auto'``, the still-stretch estimate to
        start from in place of this recording's own (:func:`gaitml.signal.estimate_gyro_bias`): the
        estimate over a whole file when ``recording`` is its first chunk
        (:func:`gaitml.chunked_run.long_pdr`, from :func:`gaitml.signal.gyro_bias_from_windows`).
        Ignored for ``'off'`` and a given bias.
        """
        self._validate_params()
        gyr = recording.require_gyr("gyro heading (attitude integration)")
        fs = recording.sampling_rate_hz
        recording.require_samples(2, "attitude integration")
        gb, online = self._start_bias(recording, still_bias)
        n0 = max(1, min(recording.n_samples, int(round(self.init_window_s * fs))))
        up0 = gravity_direction(recording.acc[:n0])
        r0 = initial_attitude(up0, heading_rad=self.initial_heading_rad, forward_axis_body=self.forward_axis_body)
        rot, bias = self._integrate(gyr, recording.acc, fs, r0, gb.bias_rads, online)
        if online:
            gb = _online_summary(gb, bias, fs)
        self.rotation_ = rot
        self.bias_rads_ = bias
        self.gyro_bias_ = gb
        fwd = rot.apply(np.asarray(self.forward_axis_body, dtype=float))
        self.heading_rad_ = compass_heading(fwd)
        return self

    def estimate_from(self, recording, start: int, initial: Rotation, initial_bias_rads=None) -> AttitudeEstimator:
        """Continue an integration: the attitudes of samples ``[start, n)`` of ``recording``, sample
        ``start`` having the attitude ``initial`` (from an earlier run over the samples before).

        Used to integrate a long recording chunk by chunk (:func:`gaitml.chunked_run.long_pdr`):
        the filter state of eqs. (14)-(15) is the attitude quaternion alone, so carrying the
        attitude of the sample before a chunk's core continues the integration as a whole-file
        run would. The complementary correction's gravity direction (a zero-phase low-pass of
        the chunk's acc) differs from the whole file's only near the chunk's ends, which the
        chunk margins keep away from the core. ``initial_bias_rads`` is the gyroscope bias at
        sample ``start`` (the earlier run's ``bias_rads_``); without it the bias is found as
        :meth:`estimate` finds it, from this recording. Sets ``rotation_``, ``heading_rad_``,
        ``gyro_bias_`` and ``bias_rads_`` for the ``n - start`` samples from ``start``;
        returns ``self``.
        """
        self._validate_params()
        gyr = recording.require_gyr("gyro heading (attitude integration)")
        fs = recording.sampling_rate_hz
        start = int(start)
        if not 0 <= start < recording.n_samples:
            raise InputError(f"`start` must be a sample of the recording (0 to {recording.n_samples - 1}), got {start}.")
        gb, online = self._start_bias(recording) if initial_bias_rads is None else (None, None)
        if gb is None:
            b0 = np.asarray(initial_bias_rads, dtype=float).reshape(3)
            online = isinstance(self.gyro_bias, str) and self.gyro_bias == "auto" and self.gravity_gain_hz > 0 and self.bias_gain > 0
            gb = GyroBias(b0, "carried", note="gyroscope bias carried from the previous part")
        rot, bias = self._integrate(gyr, recording.acc, fs, initial, gb.bias_rads, online, start=start)
        if online:
            gb = _online_summary(gb, bias, fs)
        self.gyro_bias_ = gb
        self.bias_rads_ = bias
        self.rotation_ = rot
        self.heading_rad_ = compass_heading(rot.apply(np.asarray(self.forward_axis_body, dtype=float)))
        return self

    def linear_acc_nav(self, recording) -> np.ndarray:
        """Acceleration in the navigation frame with gravity removed (n, 3), m/s^2."""
        from gaitml.consts import GRAVITY_MS2

        a = self.rotation_.apply(np.array(recording.acc, dtype=float))
        a[:, 2] -= GRAVITY_MS2
        return a
