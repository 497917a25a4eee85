"""Per-mode gait patterns: body acceleration as a function of step phase.

Every mode is described by a :class:`ModeGait` (cadence, step length,
vertical waveform, speed fluctuation along the direction of motion, lateral
sway, phone bobbing) derived from a :class:`~gaitml.simulate.subject.Subject`,
and evaluated for all samples at once by :func:`body_acceleration`.

The step phase ``u`` runs from 0 to 1 over one step; ``u = 0`` (and 1) is the
step event, the sample of the vertical acceleration peak:

- ``walk`` and ``backward``: the peak of the vertical ground reaction force in
  the loading response right after initial contact (heel strike for walking,
  toe/forefoot contact for backward walking);
- ``run``: mid-stance, where the vertical force of the single-support stance
  peaks (the flight phase lies around ``u = 0.5``);
- ``side_left`` / ``side_right``: the landing of the lead foot.

The vertical waveform of walking-like modes is a sum of cosines of the
(warped) phase with non-negative weights, so its maximum is exactly at
``u = 0`` whatever the subject's harmonic content; running is a raised-cosine
stance pulse centred on ``u = 0`` plus a flight plateau. Both have zero mean
over a step (the body does not drift vertically).

Motion along the direction of travel follows the speed profile
``v(u) = L/T (1 + c1 cos(2 pi (u + d1)) + c2 cos(4 pi (u + d2)))``, whose
integral over a step is exactly the step length ``L``; its derivative is the
acceleration along the direction of motion, so the forward signal and the true
trajectory come from the same function (:func:`displacement_fraction`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gaitml.consts import GRAVITY_MS2, MOTION_MODES
from gaitml.errors import InputError
from gaitml.simulate.subject import Subject

__all__ = [
    "ModeGait",
    "MODE_OFFSET_RAD",
    "STAND",
    "mode_gait",
    "gait_table",
    "check_modes",
    "vertical_waveform",
    "speed_profile",
    "displacement_fraction",
    "motion_acceleration",
]

#: Label of pauses (only present when pauses are asked for).
STAND = "stand"

#: Warped step phase and width of the secondary vertical bump ("shoulder") after the
#: peak: the real flat-held walks show it about 0.1-0.15 s after the peak (the arm and
#: phone rebound after the impact, and the push-off of the trailing leg).
SHOULDER_PHASE = 0.27
SHOULDER_WIDTH = 0.06

#: Direction of motion relative to the facing heading theta (clockwise compass
#: convention, DESIGN sec. 4): forward/run along theta, backward theta + pi,
#: a left side step theta - pi/2, a right side step theta + pi/2.
MODE_OFFSET_RAD = {
    "walk": 0.0,
    "run": 0.0,
    "backward": np.pi,
    "side_left": -np.pi / 2,
    "side_right": np.pi / 2,
}


@dataclasses.dataclass(frozen=True)
class ModeGait:
    """The gait of one subject in one motion mode (see the module docstring)."""

    mode: str
    cadence_hz: float  # steps per second
    step_length_m: float
    vertical_ms2: float  # amplitude of the fundamental (walk-like) or unused (run)
    harmonics: tuple[float, float, float]  # weights of cos(2 pi h w), h = 1, 2, 3
    skew: float  # phase warp w = u + skew sin(2 pi u) / (2 pi)
    shoulder: float  # secondary vertical bump after the peak, fraction of the amplitude
    is_run: bool
    duty: float  # running: stance fraction
    flight_unload: float  # running: fraction of g unloaded in flight
    speed_c1: float
    speed_d1: float
    speed_c2: float
    speed_d2: float
    sway_ms2: float  # lateral sway at half the step frequency (0 for side steps)
    sway_harmonic3: float
    pitch_bob_rad: float  # phone pitch oscillation at the step frequency
    roll_bob_rad: float  # phone roll oscillation at half the step frequency
    yaw_bob_rad: float  # trunk/arm yaw oscillation at half the step frequency
    offset_rad: float  # direction of motion relative to the facing heading
    impact_scale: float  # heel-strike impact spike, relative to the subject's walking spike
    jitter_scale: float  # hand vibration, relative to walking


def check_modes(modes) -> tuple[str, ...]:
    """Validate a list of motion modes (or a comma-separated string)."""
    if isinstance(modes, str):
        modes = [m.strip() for m in modes.split(",") if m.strip()]
    modes = tuple(str(m) for m in modes)
    if not modes:
        raise InputError(f"no motion modes given; choose from {', '.join(MOTION_MODES)}.")
    bad = [m for m in modes if m not in MOTION_MODES]
    if bad:
        raise InputError(f"unknown motion mode(s) {bad}; choose from {', '.join(MOTION_MODES)}.")
    return tuple(dict.fromkeys(modes))


def mode_gait(subject: Subject, mode: str) -> ModeGait:
    """The :class:`ModeGait` of ``subject`` in ``mode``.

    Biomechanics behind each pattern (see also the package docstring):

    - walk: inverted-pendulum gait; the centre of mass is lowest and fastest
      at double support (heel strike: upward acceleration peak, forward speed
      maximum) and highest and slowest at mid-stance (vertical trough), so the
      forward acceleration is negative (braking) after heel strike and
      positive (push-off) before the next one; lateral sway at half the step
      frequency towards the stance side.
    - run: spring-mass gait; a short stance with a large vertical force peak
      at mid-stance and a flight phase where the body is (partly, the arm
      damps it) in free fall, so the specific force drops well below g;
      braking in the first half of stance, propulsion in the second.
    - side steps: the lead foot lands and brakes the sideways motion hardest
      at impact (lateral deceleration peak at ``u = 0`` with the vertical
      peak: speed phase ``d1 = 0.25``), the body is slowest when the trailing
      foot closes, then the trailing leg pushes; the lateral speed swings by
      ``side_push`` (45-75 %) of its mean, so the lateral acceleration
      dominates and its sign flips between left and right (mirror images).
    - backward: toe-first contact cushions the landing (smaller, smoother
      vertical peak), shorter and slower steps; the speed profile is that of
      walking but along theta + pi, so in the body's forward axis the
      braking/propulsion pattern is reversed.
    """
    s = subject
    if mode == "walk":
        return ModeGait(
            mode, s.walk_cadence_hz, s.walk_step_length_m, s.walk_vertical_ms2,
            (1.0, s.walk_harmonic2, s.walk_harmonic3), s.walk_skew, s.walk_shoulder, False, 0.0, 0.0,
            s.walk_speed_fluctuation, 0.0, 0.02, 0.1,
            s.sway_ms2, s.sway_harmonic3, 0.025, 0.02, 0.03, MODE_OFFSET_RAD[mode], 1.0, 1.0,
        )  # fmt: skip
    if mode == "run":
        return ModeGait(
            mode, s.run_cadence_hz, s.run_step_length_m, 0.0, (1.0, 0.0, 0.0), 0.0, 0.0, True,
            s.run_duty, s.run_flight_unload, 0.12, 0.5, 0.03, 0.1,
            1.6 * s.sway_ms2, s.sway_harmonic3, 0.05, 0.035, 0.05, MODE_OFFSET_RAD[mode], 1.6, 1.6,
        )  # fmt: skip
    if mode in ("side_left", "side_right"):
        return ModeGait(
            mode, s.side_cadence_hz, s.side_step_length_m, s.side_vertical_ms2,
            (1.0, 0.45, 0.2), -0.1, 0.0, False, 0.0, 0.0,
            s.side_push, 0.25, 0.05, 0.05,
            0.0, 0.0, 0.02, 0.03, 0.015, MODE_OFFSET_RAD[mode], 0.8, 1.0,
        )  # fmt: skip
    if mode == "backward":
        return ModeGait(
            mode, s.back_cadence_hz, s.back_step_length_m, s.back_vertical_ms2,
            (1.0, 0.1, 0.02), 0.05, 0.5 * s.walk_shoulder, False, 0.0, 0.0,
            1.3 * s.walk_speed_fluctuation, 0.0, 0.03, 0.15,
            0.8 * s.sway_ms2, s.sway_harmonic3, 0.02, 0.02, 0.025, MODE_OFFSET_RAD[mode], 0.5, 0.9,
        )  # fmt: skip
    raise InputError(f"unknown motion mode {mode!r}; choose from {', '.join(MOTION_MODES)}.")


def gait_table(subject: Subject, modes=MOTION_MODES) -> dict[str, np.ndarray]:
    """Field -> array over ``modes`` (index = position in ``modes``), for gathering per sample."""
    gaits = [mode_gait(subject, m) for m in modes]
    out: dict[str, np.ndarray] = {}
    for f in dataclasses.fields(ModeGait):
        if f.name == "mode":
            continue
        if f.name == "harmonics":
            out["harmonics"] = np.array([g.harmonics for g in gaits], dtype=float)
        else:
            out[f.name] = np.array([getattr(g, f.name) for g in gaits], dtype=float)
    out["vertical_mean"] = np.array([_vertical_mean(g.harmonics, g.skew, g.shoulder) for g in gaits])
    return out


def _warp(u: np.ndarray, skew) -> np.ndarray:
    return u + skew * np.sin(2 * np.pi * u) / (2 * np.pi)


def _shoulder(w, shoulder):
    d = (w - SHOULDER_PHASE + 0.5) % 1.0 - 0.5
    return shoulder * np.exp(-0.5 * (d / SHOULDER_WIDTH) ** 2)


def _vertical_mean(harmonics, skew, shoulder=0.0, n: int = 1024) -> float:
    u = (np.arange(n) + 0.5) / n
    w = _warp(u, skew)
    base = sum(c * np.cos(2 * np.pi * (h + 1) * w) for h, c in enumerate(harmonics))
    return float(np.mean(base + _shoulder(w, shoulder)))


def vertical_waveform(
    u: np.ndarray,
    *,
    amplitude_ms2: np.ndarray,
    harmonics: np.ndarray,
    skew: np.ndarray,
    mean: np.ndarray,
    shoulder: np.ndarray = 0.0,
    is_run: np.ndarray,
    duty: np.ndarray,
    flight_unload: np.ndarray,
) -> np.ndarray:
    """Vertical body acceleration (m/s^2, gravity excluded) at step phase ``u``.

    Walk-like modes: ``A (sum_h c_h cos(2 pi h w(u)) + shoulder bump - mean)``,
    maximal at ``u = 0`` (the bump near ``w = 0.27`` is far narrower than the
    distance to the peak and lower than the peak). Running: a raised-cosine stance pulse of width ``duty``
    centred on ``u = 0`` and height ``2 k g / duty`` minus ``k g`` (``k`` =
    ``flight_unload``), zero mean over the step. All arguments broadcast
    (``harmonics`` has a trailing axis of 3).
    """
    w = _warp(u, skew)
    walk = amplitude_ms2 * (
        harmonics[..., 0] * np.cos(2 * np.pi * w)
        + harmonics[..., 1] * np.cos(4 * np.pi * w)
        + harmonics[..., 2] * np.cos(6 * np.pi * w)
        + _shoulder(w, shoulder)
        - mean
    )
    d = np.minimum(u % 1.0, 1.0 - (u % 1.0))  # distance to the step event in phase
    duty_safe = np.where(duty > 0, duty, 1.0)
    pulse = np.where(d < duty_safe / 2, np.cos(np.pi * d / duty_safe) ** 2, 0.0)
    run = flight_unload * GRAVITY_MS2 * (2.0 / duty_safe * pulse - 1.0)
    return np.where(is_run, run, walk)


def speed_profile(u, c1, d1, c2, d2):
    """Relative speed ``v / (L/T)`` along the direction of motion at phase ``u``."""
    return 1.0 + c1 * np.cos(2 * np.pi * (u + d1)) + c2 * np.cos(4 * np.pi * (u + d2))


def _antiderivative(u, c1, d1, c2, d2):
    return u + c1 / (2 * np.pi) * np.sin(2 * np.pi * (u + d1)) + c2 / (4 * np.pi) * np.sin(4 * np.pi * (u + d2))


def displacement_fraction(u, u0, c1, d1, c2, d2):
    """Fraction of the step length covered at phase ``u`` of a step that starts at phase ``u0``.

    0 at ``u0``, 1 at ``u = 1``: the integral of :func:`speed_profile`.
    """
    s0 = _antiderivative(u0, c1, d1, c2, d2)
    return (_antiderivative(u, c1, d1, c2, d2) - s0) / (_antiderivative(1.0, c1, d1, c2, d2) - s0)


def motion_acceleration(u, u0, du_dt, length_m, c1, d1, c2, d2):
    """Acceleration (m/s^2) along the direction of motion: d^2/dt^2 of the true displacement."""
    s0 = _antiderivative(u0, c1, d1, c2, d2)
    norm = _antiderivative(1.0, c1, d1, c2, d2) - s0
    s2 = -2 * np.pi * c1 * np.sin(2 * np.pi * (u + d1)) - 4 * np.pi * c2 * np.sin(4 * np.pi * (u + d2))
    return length_m / norm * s2 * du_dt**2
