"""Simulated subjects: the per-person gait, pose and sensor parameters.

A :class:`Subject` holds everything that makes one simulated person and phone
differ from another: body height, cadence and step length per motion mode,
the amplitude and harmonic content of the vertical acceleration, left/right
asymmetry, how the phone is held (flat or tilted, slow orientation wander)
and the sensor's noise and bias. :meth:`Subject.random` draws a plausible
person; :func:`sample_subjects` draws ``n`` reproducibly from a seed.

Ranges (the sources of the numbers):

- walking cadence 1.7-2.15 steps/s and step length ~0.41 x height: normal
  adult gait (Table 3 of paper 000 lists 0.50-0.64 s step durations; the
  two real flat-held walkers of ``ifsm-flat-phone`` lie inside);
- vertical acceleration amplitude 3.0-4.8 m/s^2 at the hand (plus the
  impact spike of 1.5-5 m/s^2 and the post-peak shoulder): sized so that
  the per-step ``|acc|`` peaks and troughs (smoothed with N = 5) fall in the
  range of the real flat-held walks, about +/-4 m/s^2 around g (the
  comparison: ``experiments/reports/simulator-hand.md``);
- running cadence 2.5-3.1 steps/s (the brief's 2.4-3.2 Hz), duty factor
  0.38-0.48 of the step in stance;
- side steps 1.4-1.9 cycles/s of 0.35-0.55 m, backward walking 1.45-1.85
  steps/s of 0.38-0.55 m (backward gait is slower with shorter steps);
- phone pitch 3-12 deg when "flat" (the real files show about 8 deg: mean
  acc_y 1.4 m/s^2), 14-50 deg when "tilted" (reading posture,
  :data:`HAND_TILTED_PITCH_DEG`, fitted to the real hand-held walks);
- hand vibration 0.25-0.65 m/s^2 per axis in 3-15 Hz (the real files have
  0.45-0.49 m/s^2 on x and y above their N = 5 moving average);
- step-to-step and slow variability (applied by :mod:`.plan` and
  :mod:`.dataset`, see :mod:`gaitml.simulate.variability`): step time and
  length scatter 2-4.5 % (stride-time CV of healthy adults is about 2-4 %,
  Hausdorff 2005; step length CV 2-5 %); the walking speed drifts slowly by
  1.5-4 % (correlation time 3-8 s: people do not hold a constant speed, gait
  speed CV within a walk is a few percent); the vertical acceleration of the
  hand scales with the speed squared (inverted pendulum: vertical excursion
  ~ L^2, frequency ~ cadence, so acceleration ~ (L f)^2 = v^2); on top,
  every step's peak and mid-stance amplitude vary independently by 5-11 %
  (``step_amp_cv``: foot placement, heel-strike force and above all the
  compliant elbow/wrist between trunk and phone, sized against the per-step
  ``|acc|`` excursions of the real flat-held walks), the harmonic
  content (waveform shape) by 15-35 % per step (``step_shape_cv``), the
  lateral sway and forward speed swing by 10-25 % per step
  (``step_lateral_cv``: arm swing and trunk sway are less regular than the
  vertical bounce), and the hand vibration is modulated slowly by 20-40 %
  (``hand_jitter_drift``: grip tension changes);
- hand gain 0.25-1.2 (log-uniform, :data:`HAND_GAIN_RANGE`): the fraction
  of the trunk's acceleration (bounce, sway, forward speed swing, heel-strike
  impact) that reaches a hand-held phone in walking, side and backward steps.
  The elbow and wrist are compliant and damp it, more in some people and
  grips than others (the IFSM flat-held walks, which sized the amplitudes
  above, have a gain of about 1). Running is not damped (its flight phase is free fall for body and phone
  alike). The range is fitted to those real walks, each user held out in
  turn, by ``python -m experiments.scripts.hand_gain``;
- accelerometer noise 0.03-0.10 m/s^2, bias up to 0.12 m/s^2 per axis;
  gyroscope noise 0.002-0.008 rad/s, bias up to 0.015 rad/s per axis
  (consumer MEMS IMUs after factory calibration).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from gaitml.errors import InputError

__all__ = ["Subject", "sample_subjects", "POSES", "HAND_GAIN_RANGE", "HAND_TILTED_PITCH_DEG"]

#: Phone holding poses the simulator knows.
POSES = ("flat", "tilted")

#: Range (log-uniform) of :attr:`Subject.hand_gain`, the fraction of the trunk's acceleration
#: (all three axes, heel-strike impact included) that reaches a hand-held phone in walking, side
#: and backward steps (a relaxed elbow and wrist damp it; not in running, whose flight phase is
#: free fall for body and phone alike). Carried positions (:mod:`.positions`) do not use it.
#: Fitted to the real hand-held walks (IFSM's two flat-held walkers and the Oxford ``InHand``
#: walks of three users) by ``python -m experiments.scripts.hand_gain``: the simulated
#: population's 5-95 % range of the walking ``|acc|`` standard deviation spans the real walks'
#: range; leave-one-user-out in ``experiments/reports/model-domain.md`` ("Calm hand-held walkers").
HAND_GAIN_RANGE = (0.25, 1.2)

#: Range (uniform, deg) of the pitch of a phone held "tilted" (reading posture; "flat" is 3-12
#: deg). The lower end is fitted to the real hand-held walks by ``python -m
#: experiments.scripts.hand_pose``: the smallest median pitch of the tuning users' tilted walks
#: (over 12 deg) less 5 deg, floored to a whole degree; the upper end keeps the prior 50 deg,
#: above every real walk (figures, held out per user: ``experiments/reports/model-domain.md``,
#: "The phone's holding angle").
HAND_TILTED_PITCH_DEG = (14.0, 50.0)


def _pose_pitch(pose: str, rng: np.random.Generator) -> float:
    """The phone's pitch (rad) drawn for ``pose``: flat 0.05-0.21 rad (3-12 deg), tilted :data:`HAND_TILTED_PITCH_DEG`."""
    if pose == "flat":
        return rng.uniform(0.05, 0.21)
    lo, hi = HAND_TILTED_PITCH_DEG
    return float(rng.uniform(np.radians(lo), np.radians(hi)))


@dataclasses.dataclass(frozen=True)
class Subject:
    """One simulated person holding a phone in front of them.

    All lengths in m, rates in Hz (steps per second), accelerations in m/s^2,
    angles in rad. Step frequencies count steps (foot contacts), not strides.
    """

    subject: str = "S01"
    height_m: float = 1.72
    # walking
    walk_cadence_hz: float = 1.94
    walk_step_length_m: float = 0.70
    walk_vertical_ms2: float = 3.7  # amplitude of the step-frequency fundamental
    walk_harmonic2: float = 0.15  # 2nd / 1st harmonic of vertical acceleration
    walk_harmonic3: float = 0.05  # 3rd / 1st harmonic
    walk_skew: float = -0.15  # phase warp: < 0 makes the rise to heel strike steeper than the fall
    walk_shoulder: float = 0.4  # secondary vertical bump after heel strike, fraction of the amplitude
    walk_speed_fluctuation: float = 0.10  # +/- fraction of the mean forward speed within a step
    sway_ms2: float = 0.9  # lateral sway amplitude at half the step frequency
    sway_harmonic3: float = 0.35
    asymmetry_time: float = 0.02  # step duration L/R difference: (1 +/- a)
    asymmetry_amp: float = 0.03  # vertical peak L/R difference: (1 +/- a)
    step_jitter: float = 0.03  # coefficient of variation of step duration and length
    impact_ms2: float = 3.0  # height of the heel-strike impact spike (vertical, raw signal)
    impact_width_s: float = 0.014  # its Gaussian width (sigma)
    hand_jitter_ms2: float = 0.45  # std of the 3-15 Hz hand/arm vibration while moving, per axis
    # running
    run_cadence_hz: float = 2.8
    run_step_length_m: float = 1.15
    run_duty: float = 0.43  # stance fraction of a step
    run_flight_unload: float = 0.5  # fraction of g unloaded in flight (1 = free fall)
    # side steps (one lead-out + close cycle per step)
    side_cadence_hz: float = 1.65
    side_step_length_m: float = 0.45
    side_vertical_ms2: float = 2.4
    side_push: float = 0.6  # lateral speed fluctuation (1 = stops between steps)
    # backward
    back_cadence_hz: float = 1.65
    back_step_length_m: float = 0.45
    back_vertical_ms2: float = 2.9
    # phone pose and sensor
    pose: str = "flat"
    pitch_rad: float = 0.13
    roll_rad: float = -0.03
    wander_rad: float = 0.03  # std of the slow orientation wander
    wander_time_s: float = 4.0  # its correlation time
    acc_noise_ms2: float = 0.06
    acc_bias_x_ms2: float = 0.03
    acc_bias_y_ms2: float = -0.05
    acc_bias_z_ms2: float = 0.04
    gyr_noise_rads: float = 0.004
    gyr_bias_x_rads: float = 0.004
    gyr_bias_y_rads: float = -0.003
    gyr_bias_z_rads: float = 0.005
    # step-to-step and slow variability (module docstring; gaitml.simulate.variability)
    step_amp_cv: float = 0.08  # per half step (peak / mid-stance) amplitude variation, log-normal sd
    step_shape_cv: float = 0.25  # per half step variation of the 2nd/3rd harmonics and the shoulder
    step_lateral_cv: float = 0.18  # per step variation of lateral sway and forward speed swing
    speed_drift_cv: float = 0.03  # slow walking-speed modulation, log-normal sd
    speed_drift_time_s: float = 5.0  # its correlation time
    hand_jitter_drift: float = 0.3  # slow modulation of the hand vibration amplitude, log-normal sd
    # fraction of the trunk's acceleration that reaches a hand-held phone (walk, side, backward; HAND_GAIN_RANGE)
    hand_gain: float = 1.0

    def __post_init__(self) -> None:
        if self.pose not in POSES:
            raise InputError(f"Subject.pose must be one of {POSES}, got {self.pose!r}.")
        for name in ("walk_cadence_hz", "run_cadence_hz", "side_cadence_hz", "back_cadence_hz"):
            v = getattr(self, name)
            if not 0.5 <= v <= 4.0:
                raise InputError(f"Subject.{name} must be a step rate in 0.5-4 steps/s, got {v!r}.")
        for name in ("walk_step_length_m", "run_step_length_m", "side_step_length_m", "back_step_length_m"):
            v = getattr(self, name)
            if not 0.05 <= v <= 2.5:
                raise InputError(f"Subject.{name} must be 0.05-2.5 m, got {v!r}.")
        for name in ("step_amp_cv", "step_shape_cv", "step_lateral_cv", "speed_drift_cv", "hand_jitter_drift"):
            v = getattr(self, name)
            if not 0.0 <= v <= 0.6:
                raise InputError(f"Subject.{name} must be a relative variation in 0-0.6, got {v!r}.")
        if not 0.05 <= self.hand_gain <= 2.0:
            raise InputError(f"Subject.hand_gain must be a gain in 0.05-2, got {self.hand_gain!r}.")
        if not self.speed_drift_time_s > 0:
            raise InputError(f"Subject.speed_drift_time_s must be > 0 s, got {self.speed_drift_time_s!r}.")

    # ------------------------------------------------------------------
    @classmethod
    def random(cls, rng: np.random.Generator, *, subject: str = "S01", pose: str | None = None) -> Subject:
        """Draw a plausible subject (see the module docstring for the ranges).

        Parameters
        ----------
        rng : numpy Generator
        subject : str
            The subject id.
        pose : {'flat', 'tilted'} or None
            Phone pose; None draws it (70 % flat).
        """
        u = rng.uniform
        height = u(1.55, 1.90)
        cad = u(1.70, 2.15)
        # longer legs -> longer steps; faster cadence -> slightly longer steps too
        step_len = 0.415 * height * (0.85 + 0.15 * cad / 1.9) * u(0.92, 1.08)
        pose_ = pose if pose is not None else ("flat" if u() < 0.7 else "tilted")
        if pose_ not in POSES:
            raise InputError(f"pose must be one of {POSES}, got {pose_!r}.")
        pitch = _pose_pitch(pose_, rng)
        sign = lambda: 1.0 if u() < 0.5 else -1.0  # noqa: E731
        return cls(
            subject=subject,
            height_m=round(height, 3),
            walk_cadence_hz=cad,
            walk_step_length_m=step_len,
            walk_vertical_ms2=u(3.0, 4.8),
            walk_harmonic2=u(0.05, 0.25),
            walk_harmonic3=u(0.0, 0.10),
            walk_skew=u(-0.30, 0.05),
            walk_shoulder=u(0.15, 0.55),
            walk_speed_fluctuation=u(0.06, 0.14),
            sway_ms2=u(0.6, 1.3),
            sway_harmonic3=u(0.2, 0.5),
            asymmetry_time=u(0.0, 0.04),
            asymmetry_amp=u(0.0, 0.06),
            step_jitter=u(0.02, 0.045),
            impact_ms2=u(1.5, 5.0),
            impact_width_s=u(0.010, 0.020),
            hand_jitter_ms2=u(0.25, 0.65),
            run_cadence_hz=u(2.5, 3.1),
            run_step_length_m=0.68 * height * u(0.92, 1.12),
            run_duty=u(0.40, 0.50),
            run_flight_unload=u(0.35, 0.55),
            side_cadence_hz=u(1.4, 1.9),
            side_step_length_m=u(0.35, 0.55),
            side_vertical_ms2=u(2.2, 3.2),
            side_push=u(0.45, 0.75),
            back_cadence_hz=u(1.45, 1.85),
            back_step_length_m=u(0.38, 0.55),
            back_vertical_ms2=u(2.4, 3.6),
            pose=pose_,
            pitch_rad=pitch,
            roll_rad=u(-0.09, 0.09),
            wander_rad=u(0.015, 0.05),
            wander_time_s=u(2.0, 6.0),
            acc_noise_ms2=u(0.03, 0.10),
            acc_bias_x_ms2=sign() * u(0.0, 0.12),
            acc_bias_y_ms2=sign() * u(0.0, 0.12),
            acc_bias_z_ms2=sign() * u(0.0, 0.12),
            gyr_noise_rads=u(0.002, 0.008),
            gyr_bias_x_rads=sign() * u(0.0, 0.015),
            gyr_bias_y_rads=sign() * u(0.0, 0.015),
            gyr_bias_z_rads=sign() * u(0.0, 0.015),
            # drawn last: the parameters above keep their values for a given seed
            step_amp_cv=u(0.05, 0.11),
            step_shape_cv=u(0.15, 0.35),
            step_lateral_cv=u(0.10, 0.25),
            speed_drift_cv=u(0.015, 0.04),
            speed_drift_time_s=u(3.0, 8.0),
            hand_jitter_drift=u(0.2, 0.4),
            # drawn after them all (the same reason): log-uniform over HAND_GAIN_RANGE
            hand_gain=float(np.exp(u(np.log(HAND_GAIN_RANGE[0]), np.log(HAND_GAIN_RANGE[1])))),
        )

    def with_pose(self, pose: str, rng: np.random.Generator | None = None) -> Subject:
        """Return the subject holding the phone in ``pose`` (pitch redrawn if it changes)."""
        if pose not in POSES:
            raise InputError(f"pose must be one of {POSES}, got {pose!r}.")
        if pose == self.pose:
            return self
        rng = rng if rng is not None else np.random.default_rng(0)
        pitch = _pose_pitch(pose, rng)
        return dataclasses.replace(self, pose=pose, pitch_rad=pitch)

    def session_variant(self, rng: np.random.Generator, *, scale: float = 1.0) -> Subject:
        """The same person on another day: small changes of cadence, step length, amplitude and grip.

        Cadences and step lengths change by about 3 %, amplitudes by 6 %, the
        phone pitch and roll by about 3 deg (standard deviations, times ``scale``).
        """
        n = lambda sd: 1.0 + scale * sd * rng.standard_normal()  # noqa: E731
        cad, length, amp = n(0.03), n(0.03), n(0.06)
        return dataclasses.replace(
            self,
            walk_cadence_hz=self.walk_cadence_hz * cad,
            run_cadence_hz=min(max(self.run_cadence_hz * cad, 2.4), 3.2),
            side_cadence_hz=self.side_cadence_hz * cad,
            back_cadence_hz=self.back_cadence_hz * cad,
            walk_step_length_m=self.walk_step_length_m * length,
            run_step_length_m=self.run_step_length_m * length,
            side_step_length_m=self.side_step_length_m * length,
            back_step_length_m=self.back_step_length_m * length,
            walk_vertical_ms2=self.walk_vertical_ms2 * amp,
            side_vertical_ms2=self.side_vertical_ms2 * amp,
            back_vertical_ms2=self.back_vertical_ms2 * amp,
            sway_ms2=self.sway_ms2 * n(0.06),
            pitch_rad=self.pitch_rad + scale * 0.05 * rng.standard_normal(),
            roll_rad=self.roll_rad + scale * 0.05 * rng.standard_normal(),
        )

    def to_dict(self, *, digits: int = 6) -> dict[str, Any]:
        """The parameters as a flat dict (floats rounded to ``digits``) for a manifest."""
        out: dict[str, Any] = {}
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            out[f.name] = round(float(v), digits) if isinstance(v, float) else v
        return out


#: Upper bound on subjects per call (argument validation; each one is a separate recording).
MAX_SUBJECTS = 1000


def sample_subjects(n: int, seed: int = 0, *, pose: str | None = None) -> list[Subject]:
    """Draw ``n`` subjects ``S01``.. reproducibly from ``seed``.

    Subject ``i`` depends only on ``seed`` and ``i`` (its own spawned random
    stream), so asking for more subjects does not change the first ones.
    """
    if int(n) != n or n < 1:
        raise InputError(f"the number of subjects must be a positive integer, got {n!r}.")
    if int(n) > MAX_SUBJECTS:
        raise InputError(f"the number of subjects must be at most {MAX_SUBJECTS}, got {n!r}; simulate fewer subjects per call.")
    if int(seed) != seed or seed < 0:
        raise InputError(f"seed must be a non-negative integer, got {seed!r}; use e.g. seed=0.")
    streams = np.random.SeedSequence([int(seed), 7919]).spawn(int(n))
    return [Subject.random(np.random.default_rng(s), subject=f"S{i + 1:02d}", pose=pose) for i, s in enumerate(streams)]
