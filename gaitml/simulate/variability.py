"""Step-to-step and slow gait variability of the simulated walker and phone.

Real gait is not a periodic signal. A person's steps differ in duration,
length, force and shape, the walking speed drifts over seconds, and a
hand-held phone adds the compliance of the elbow and wrist. A window of
0.5 s sees about one step, so this variability decides how noisy a short
window's view of the motion mode is (paper 003 sec. 3.3, Table 2: 0.5 s
windows recognise the mode far worse than 1.5 s ones).

Sources and sizes (defaults and ranges in :class:`~gaitml.simulate.subject.Subject`):

- *Step time and length*: scatter of 2-4.5 % per step (``step_jitter``,
  :mod:`.plan`). Healthy adults walk with a stride-time CV of about 2-4 %
  (Hausdorff 2005, J. NeuroEng. Rehabil. 2:19; Beauchet et al. 2009) and a
  step-length CV of 2-5 %.
- *Slow speed drift* (:func:`speed_drift`): a smooth log-normal modulation
  of the walking speed, sd ``speed_drift_cv`` 1.5-4 % with a correlation time
  of 3-8 s, shared between cadence and step length (``v = f L``; both rise
  about equally with speed, so each gets the square root). People do not
  hold a constant speed on a 200 m walk (they slow down before turns and
  obstacles, speed up on straight stretches).
- *Amplitude follows speed* (:func:`speed_gain`): for the inverted pendulum
  the vertical excursion of the centre of mass grows with ``L^2`` and the
  oscillation frequency with the cadence, so the vertical acceleration grows
  about with ``(L f)^2 = v^2`` (:data:`AMPLITUDE_SPEED_EXPONENT`; measured
  trunk accelerations rise steeply with speed, e.g. Kavanagh & Menz 2008,
  Gait Posture 28:1). Each step's relative speed (its jitter and the drift,
  not the left/right asymmetry nor the longer turning step of a mode change)
  sets its amplitude.
- *Per-half-step amplitude* (``step_amp_cv``, 5-11 %): the heel-strike
  peak and the mid-stance trough of each step vary independently (foot
  placement, heel-strike force, knee flexion in loading response) and, for a
  hand-held phone, much more through the elbow and wrist, which are not
  locked. The real flat-held walks of ``ifsm-flat-phone`` have a per-step
  CV of the smoothed ``|acc|`` peak excursion of 13-15 % and of the trough of
  14 %, about twice what the body model with step-time jitter gives alone.
- *Waveform shape* (``step_shape_cv``, 15-35 %): the 2nd and 3rd harmonics
  and the post-peak "shoulder" (arm rebound, push-off) change from step to
  step.
- *Lateral sway and forward speed swing* (``step_lateral_cv``, 10-25 %):
  mediolateral control is less regular than the sagittal bounce (step
  width CV of 10-20 % in healthy gait, far larger than the step-time CV).
- *Hand vibration* (``hand_jitter_drift``, 20-40 %): the 3-15 Hz shake of
  the hand is modulated slowly (grip tension, attention to the screen).

How the per-step values enter the signal without breaking it: every value is
a *knot* at a half step of the continuous step count ``phi`` (``phi = k`` at
the event of global step ``k``, ``k - 1/2`` at its mid-stance); between
knots the value is interpolated with a raised cosine (:func:`interpolate_knots`),
so the signal stays continuous, and the event remains a local maximum of the
vertical acceleration (the gain has zero slope at the knots). The speed-swing
factor is constant over a step (it enters the true displacement of the step
too, so the trajectory stays the integral of the forward acceleration). All
draws come from the recording's seeded generator, vectorised over steps.
"""

from __future__ import annotations

import numpy as np

from gaitml.simulate.sensor import smooth_noise

__all__ = [
    "AMPLITUDE_SPEED_EXPONENT",
    "SPEED_GAIN_RANGE",
    "speed_drift",
    "speed_gain",
    "step_knots",
    "interpolate_knots",
    "knot_index",
]

#: Vertical acceleration ~ speed^2 (inverted pendulum, see the module docstring).
AMPLITUDE_SPEED_EXPONENT = 2.0
#: Clip of the speed gain (a step 25 % faster or slower than usual is already rare).
SPEED_GAIN_RANGE = (0.6, 1.6)
#: Sampling rate of the slow drift grid (Hz): ample for a 3-8 s correlation time.
DRIFT_GRID_HZ = 10.0


def speed_drift(rng: np.random.Generator, horizon_s: float, cv: float, correlation_time_s: float):
    """A slow log-normal speed factor: a function ``t_s -> factor`` (mean about 1).

    ``exp(cv * z(t))`` with ``z`` unit-variance low-passed noise
    (:func:`~gaitml.simulate.sensor.smooth_noise`) on a 10 Hz grid covering
    ``[0, horizon_s]``; times past the grid hold the last value.
    """
    n = int(np.ceil(max(horizon_s, 1.0) * DRIFT_GRID_HZ)) + 2
    z = smooth_noise(rng, n, DRIFT_GRID_HZ, correlation_time_s)[:, 0]
    f = np.exp(cv * z)
    t_grid = np.arange(n) / DRIFT_GRID_HZ
    return lambda t_s: np.interp(t_s, t_grid, f)


def speed_gain(speed_rel: np.ndarray) -> np.ndarray:
    """Amplitude factor of steps walked at ``speed_rel`` times the usual speed: ``speed_rel ** 2``, clipped."""
    return np.clip(np.asarray(speed_rel, dtype=float) ** AMPLITUDE_SPEED_EXPONENT, *SPEED_GAIN_RANGE)


def knot_index(step_index: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Knot positions of each step's mid-stance (``phi = k - 1/2``) and event (``phi = k``).

    Knot ``q = 2 (phi + 1)``, so mid-stance of step ``k`` is ``2 k + 1`` and its event ``2 k + 2``.
    """
    k = np.asarray(step_index, dtype=np.int64)
    return 2 * k + 1, 2 * k + 2


def step_knots(
    rng: np.random.Generator,
    step_index: np.ndarray,
    sd: float,
    *,
    base: np.ndarray | float = 1.0,
    n_channels: int = 1,
) -> np.ndarray:
    """Knot values (n_knots, n_channels): ``base_k * exp(sd * z)``, independent at each half step.

    ``base`` (per step) multiplies both knots of the step; knots no step owns stay 1.
    """
    mid, ev = knot_index(step_index)
    n_knots = int(ev.max()) + 3 if len(ev) else 3
    out = np.ones((n_knots, n_channels))
    b = np.broadcast_to(np.asarray(base, dtype=float), (len(ev),))[:, None]
    z = rng.standard_normal((2, len(ev), n_channels))
    out[mid] = b * np.exp(sd * z[0])
    out[ev] = b * np.exp(sd * z[1])
    return out


def interpolate_knots(phi: np.ndarray, knots: np.ndarray) -> np.ndarray:
    """Values at continuous step count ``phi`` (n,), raised-cosine between half-step knots.

    Returns (n, n_channels). The interpolant is continuous with zero slope
    at every knot.
    """
    q = 2.0 * (np.asarray(phi, dtype=float) + 1.0)
    q = np.clip(q, 0.0, len(knots) - 1.000001)
    i0 = np.floor(q).astype(np.int64)
    w = 0.5 * (1.0 - np.cos(np.pi * (q - i0)))[:, None]
    return knots[i0] * (1.0 - w) + knots[i0 + 1] * w
