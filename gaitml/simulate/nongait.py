"""Phone motion without gait: hand gestures while standing, a phone handled at a desk.

A step counter must count no steps where nobody walks. These recordings have no
steps (``reference['n_steps_true'] = 0``) but plenty of motion:

- ``gestures``: a person stands and talks with the phone in the hand. Gesture
  units (McNeill, *Hand and Mind*, 1992) come in bursts of 0.5-4 s separated
  by 0.5-4 s of holding; inside a burst the hand makes rhythmic strokes ("beats")
  at 1-3 Hz, with an amplitude of 2-8 cm and a rotation of 10-50 deg along a
  direction drawn per burst, plus the hand's tremor. A quarter of the bursts are
  a wave (a larger back-and-forth of the forearm, 5-12 cm).
- ``desk``: the phone lies on a desk, is picked up, held and tapped (typing at
  2-6 taps/s, each tap a 20 ms push of 0.5-2 m/s^2 into the screen), turned,
  put down with a small impact, slid or tapped on the desk.

The phone's attitude and position are smooth random curves through the knots of
each episode; the accelerometer reads ``R^T (a + g z_up)`` and the gyroscope the
body rate of the same attitude (:mod:`.sensor`), plus sensor noise.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.interpolate import PchipInterpolator

from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.simulate.sensor import band_noise, body_rates, nav_to_phone, smooth_noise

__all__ = ["NONGAIT_KINDS", "simulate_nongait"]

#: the kinds of non-gait recordings
NONGAIT_KINDS = ("gestures", "desk")
_DEG = np.pi / 180.0


def _gesture_track(rng: np.random.Generator, n: int, fs: float) -> tuple[np.ndarray, np.ndarray]:
    """Hand position (n, 3) m and attitude angles (n, 3) rad (yaw, pitch, roll offsets) of a gesturing hand."""
    t = np.arange(n) / fs
    pos = np.zeros((n, 3))
    ang = np.zeros((n, 3))
    t0 = rng.uniform(0.0, 2.0)
    while t0 < t[-1]:
        dur = rng.uniform(0.5, 4.0)
        f = rng.uniform(1.0, 3.0)
        wave = rng.uniform() < 0.25
        amp = rng.uniform(0.05, 0.12) if wave else rng.uniform(0.02, 0.08)
        d = rng.standard_normal(3)
        d /= np.linalg.norm(d)
        rot = rng.uniform(10.0, 50.0) * _DEG * rng.standard_normal(3) / np.sqrt(3)
        m = (t >= t0) & (t < t0 + dur)
        u = (t[m] - t0) / dur
        env = np.sin(np.pi * u) ** 2
        ph = 2 * np.pi * f * (t[m] - t0) + rng.uniform(0, 2 * np.pi)
        # beats are sharper than a sine: a stroke and a slower return
        s = np.sin(ph) + (0.0 if wave else 0.3) * np.sin(2 * ph)
        pos[m] += (amp * env * s)[:, None] * d
        ang[m] += (env * s)[:, None] * rot
        t0 += dur + rng.uniform(0.5, 4.0)
    # slow drift of the holding posture
    pos += 0.03 * smooth_noise(rng, n, fs, 3.0, 3)
    ang += 8 * _DEG * smooth_noise(rng, n, fs, 3.0, 3)
    return pos, ang


def _desk_track(rng: np.random.Generator, n: int, fs: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Phone position (n, 3), attitude angles (n, 3) and extra specific force (n, 3, phone frame) at a desk."""
    t = np.arange(n) / fs
    knots_t, knots_p, knots_a = [0.0], [np.zeros(3)], [np.zeros(3)]
    taps = np.zeros((n, 3))
    tc = 0.0
    on_desk = True
    while tc < t[-1]:
        if on_desk:
            rest = rng.uniform(2.0, 10.0)
            if rng.uniform() < 0.3:  # slid or turned on the desk
                knots_t += [tc + rest, tc + rest + rng.uniform(0.4, 1.2)]
                p = knots_p[-1] + np.r_[rng.normal(0, 0.1, 2), 0.0]
                a = knots_a[-1] + np.r_[rng.normal(0, 40 * _DEG), 0.0, 0.0]
                knots_p += [knots_p[-1], p]
                knots_a += [knots_a[-1], a]
                tc = knots_t[-1]
                continue
            lift = rng.uniform(0.7, 1.5)
            hold_p = knots_p[-1] + np.r_[rng.normal(0, 0.1, 2), rng.uniform(0.15, 0.4)]
            hold_a = np.r_[knots_a[-1][0] + rng.normal(0, 20 * _DEG), rng.uniform(20, 60) * _DEG, rng.normal(0, 10 * _DEG)]
            knots_t += [tc + rest, tc + rest + lift]
            knots_p += [knots_p[-1], hold_p]
            knots_a += [knots_a[-1], hold_a]
            tc = knots_t[-1]
            on_desk = False
        else:
            hold = rng.uniform(3.0, 20.0)
            # taps while held: typing or scrolling
            a0, a1 = np.searchsorted(t, [tc, tc + hold])
            rate = rng.uniform(2.0, 6.0)
            k = a0
            while k < a1:
                k += max(1, int(fs * rng.exponential(1.0 / rate)))
                w = int(0.02 * fs) + 1
                if k + w < n:
                    taps[k : k + w, 2] -= rng.uniform(0.5, 2.0) * np.hanning(w + 2)[1:-1]
            put = rng.uniform(0.6, 1.2)
            down_p = np.r_[knots_p[-1][:2] + rng.normal(0, 0.1, 2), 0.0]
            down_a = np.r_[knots_a[-1][0] + rng.normal(0, 20 * _DEG), 0.0, 0.0]
            knots_t += [tc + hold, tc + hold + put]
            knots_p += [knots_p[-1] + 0.01 * rng.standard_normal(3) * np.r_[1, 1, 0], down_p]
            knots_a += [knots_a[-1], down_a]
            tc = knots_t[-1]
            j = int(tc * fs)
            if j + 3 < n:  # the landing
                taps[j : j + 3, 2] += rng.uniform(2.0, 6.0) * np.array([1.0, -0.6, 0.3])
            on_desk = True
    kt = np.asarray(knots_t)
    keep = np.concatenate(([True], np.diff(kt) > 1e-6))
    pos = PchipInterpolator(kt[keep], np.asarray(knots_p)[keep], extrapolate=True)(t)
    ang = PchipInterpolator(kt[keep], np.asarray(knots_a)[keep], extrapolate=True)(t)
    held = pos[:, 2] > 0.005
    pos += (0.002 * smooth_noise(rng, n, fs, 0.5, 3)) * held[:, None]
    ang += (1.5 * _DEG * smooth_noise(rng, n, fs, 0.5, 3)) * held[:, None]
    return pos, ang, taps


def simulate_nongait(kind: str = "gestures", *, duration_s: float = 120.0, sampling_rate_hz: float = 50.0, seed: int = 0) -> Recording:
    """A recording of phone motion without a single step (module docstring).

    Parameters
    ----------
    kind : {'gestures', 'desk'}
    duration_s : float
        2 s - 1 h.
    sampling_rate_hz : float
        20-400 Hz.
    seed : int

    Returns
    -------
    Recording
        ``acc`` (m/s^2, gravity included), ``gyr`` (rad/s), labels ``kind``,
        ``reference['n_steps_true'] = 0`` and an empty ``steps`` table.
    """
    if kind not in NONGAIT_KINDS:
        raise InputError(f"unknown non-gait kind {kind!r}; choose one of {', '.join(NONGAIT_KINDS)}.")
    if not (np.isfinite(duration_s) and 2.0 <= duration_s <= 3600.0):
        raise InputError(f"`duration_s` must be within 2-3600 s, got {duration_s!r}.")
    fs = float(sampling_rate_hz)
    if not 20.0 <= fs <= 400.0:
        raise InputError(f"`sampling_rate_hz` must be within 20-400 Hz, got {sampling_rate_hz!r}.")
    rng = np.random.default_rng([int(seed), 4409, NONGAIT_KINDS.index(kind)])
    n = int(round(duration_s * fs))
    dt = 1.0 / fs
    extra = np.zeros((n, 3))
    if kind == "gestures":
        pos, ang = _gesture_track(rng, n, fs)
        ang = ang + np.array([0.0, rng.uniform(15, 50) * _DEG, 0.0])  # holding pitch
    else:
        pos, ang, extra = _desk_track(rng, n, fs)
    acc_nav = np.gradient(np.gradient(pos, dt, axis=0), dt, axis=0)
    yaw, pitch, roll = ang[:, 0], ang[:, 1], ang[:, 2]
    f = acc_nav.copy()
    f[:, 2] += 9.80665
    acc = nav_to_phone(f, yaw, pitch, roll) + extra
    gyr = body_rates(np.gradient(yaw, dt), pitch, np.gradient(pitch, dt), roll, np.gradient(roll, dt))
    if kind == "gestures":  # hand tremor (8-12 Hz physiological tremor band)
        acc += band_noise(rng, n, fs, 8.0, 12.0, 3) * rng.uniform(0.05, 0.15)
        gyr += band_noise(rng, n, fs, 8.0, 12.0, 3) * rng.uniform(0.005, 0.02)
    acc += rng.normal(0, 0.02, (n, 3)) + rng.normal(0, 0.05, 3)
    gyr += rng.normal(0, 0.002, (n, 3)) + rng.normal(0, 0.005, 3)
    steps = pd.DataFrame({"t_s": np.zeros(0), "mode": np.zeros(0, dtype=object)})
    meta = {"source": "gaitml.simulate.nongait", "format": "simulated", "device": "simulated phone", "kind": kind, "seed": int(seed)}
    return Recording(
        acc=acc,
        gyr=gyr,
        labels=np.full(n, kind, dtype=object),
        sampling_rate_hz=fs,
        meta=meta,
        reference={"n_steps_true": 0, "steps": steps, "steps_t_s": np.zeros(0)},
        check_units=False,
    )
