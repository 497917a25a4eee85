"""Adaptive step detector for a phone in any carrying position (our own design).

Not from the papers: a detector for hand, pockets, bag, armband, neck pouch and
swinging arm, where fixed magnitude thresholds (papers 000, 002, 003) fail
because the amplitude and the shape of the step signal change with the
position. Its settings are physiological ranges and dimensionless ratios, not
thresholds fitted to the recordings it is evaluated on; the one
amplitude it uses is a noise floor. Five stages:

1. **Band-pass** the acceleration magnitude (|acc| minus its median) to the gait
   band ``band_hz`` (default 0.5-4 Hz, zero-phase 2nd-order Butterworth, so that
   running cadences up to ``max_step_hz`` = 3.5 Hz pass): removes gravity,
   orientation drift and impact ringing.
2. **Cadence and stride-versus-step disambiguation.** In sliding windows
   (``window_s`` long, every ``hop_s``) the normalised autocorrelation of the
   band-passed signal (each lag normalised by the energies of its two
   overlapping segments, so it does not decay with the lag) is searched over
   every lag a human step *or stride* can take: ``1 / max_step_hz`` to
   ``2 / slow_step_hz`` (strides at 1.2-3.5 steps/s; steps down to
   ``min_step_hz`` = 0.75 Hz lie inside that range). The
   fundamental period is the shortest autocorrelation peak within
   ``OCTAVE_TOLERANCE`` (90 %) of the strongest one (multiples of a period
   correlate about as well as the period). It may be one step (two legs that
   look alike) or one stride (a pocket phone sees one leg). Half-period
   structure decides: if the autocorrelation at half the period is above
   ``half_lag_min_correlation`` (default 0: the signal shifted by half a
   period still resembles itself, so each period holds two similar events, the
   left and the right step), the period is a stride and the step period is
   the local maximum near its half (or the half itself where the
   autocorrelation has a plateau there); repeated while the half stays in the
   step range. A period of one step instead gives a deep negative correlation
   at its half (the signal is in anti-phase there).
   A period still longer than the longest human step (``1 / min_step_hz``) is
   a stride whose second step is not visible: its half is the step period.
   So is a period longer than ``1 / slow_step_hz`` (1.2 Hz) in a window with
   more motion than a slow walker makes (band-passed RMS over
   ``slow_step_max_rms_ms2``): a slow step, 0.75-1.2 Hz, shows as a deep
   anti-phase at its half (the half-period rule does not take it for a
   stride) and a gentle signal; a one-leg stride of normal walking at the
   same period shows several m/s^2. That alternative needs a phone on a
   swinging thigh or arm (the hip flexes and extends through 30-40 deg per
   stride, Perry & Burnfield, *Gait Analysis*, 2010): where the gyroscope
   shows the phone does not swing (swing RMS below ``gyro_min_rms_rads``,
   stage 2b) the ceiling does not apply, so a phone held steady by a slow
   walker with a strong bounce keeps its slow steps. A slow step must also be in
   deep anti-phase at its half (autocorrelation there at most
   ``slow_step_max_half_correlation``, -0.5): a one-leg stride of a gentle
   walk (a trouser pocket) has no such anti-phase, both heel strikes reach
   the phone, and stays a stride. A slow-step window whose
   neighbours (``SLOW_STEP_CONTEXT`` windows either side, mostly not slow) walk
   at twice its cadence is a stride too: a walker's cadence does not halve for
   one window.
   The peak correlation is the window's *periodicity*; the lag is refined to a
   fraction of a sample by a parabola through the peak.
2b. **Gyroscope check** (where the recording has one; :func:`gyro_stride_or_step`).
   Every rotation of the body that carries the phone (arm swing, thigh swing,
   pelvis and trunk rotation) completes one cycle per stride and reverses
   between the left and the right step, so the phone's swing rate (the
   gyroscope on its principal axis) is in anti-phase one step later. A step
   period at which the swing is in phase, with anti-phase at its half, is a
   stride (a running arm or thigh); a period halved from a stride at which
   the swing is not in anti-phase but is at twice it is a step (a swinging
   hand's |acc| peaks at both ends of each swing, once per step).
2c. **Swing where |acc| is weak** (opt-in, with a gyroscope; :func:`gyro_swing_cadence`).
   A slow walker's trunk barely bounces, so |acc|'s periodicity can fall
   below ``min_periodicity`` while the phone still swings once per stride.
   With ``gyro_swing_min_periodicity`` > 0, where the swing is regular there
   (its stride period ``P``, the fundamental of its autocorrelation over two
   steps of the human range, correlates at least ``gyro_swing_min_periodicity``
   and the swing is in anti-phase at ``P / 2``, at most
   ``-gyro_swing_half_correlation``: it reverses between the left and the
   right step), the window's step period is ``P / 2`` and its periodicity the
   swing's. The steps themselves are still peaks of |acc| (stages 3-5). Off
   by default: a gesturing hand also turns the phone regularly, and with the
   swing as evidence more of its bursts pass as steps.
3. **Left/right fold.** With the local step period ``T`` each sample becomes
   ``(y(t - T) + 2 y(t) + y(t + T)) / 4``: a zero-phase comb that cancels the
   stride fundamental and its odd harmonics (the left/right asymmetry of a
   one-leg signal: ``y(t - T) + y(t + T) = -2 y(t)`` for them) and keeps the
   step frequency and its harmonics, so the weak step of the far leg becomes
   a peak like the near one without any amplitude threshold.
4. **Amplitude-free peak criterion.** A step is a local maximum of the folded
   signal that is positive and the highest within ``min_distance_ratio`` times
   the local step period on either side, where the motion is periodic
   (periodicity >= ``min_periodicity``) and above the sensor noise floor
   (RMS of the band-passed signal over one step period before the step and
   over one after it, both >= ``min_rms_ms2``). Opt-in (``min_rms_slow_ms2`` below
   ``min_rms_ms2``): where the local step period is longer than ``1 / slow_step_hz``
   the floor scales with the square of the step frequency (the same vertical
   excursion gives ``(2 pi f)^2`` times less acceleration at a slower step), down to
   ``min_rms_slow_ms2`` (:func:`slow_step_noise_floor`). Opt-in, with a gyroscope
   (``rhythm_min_periodicity`` above 0 and below ``min_periodicity``): a peak the periodicity
   floor alone removes is kept where its periodicity reaches
   ``rhythm_min_periodicity`` and the phone turns with a stride rhythm whose step
   matches the window's (:func:`rhythm_windows`): a calm hand-held walk's |acc|
   repeats weakly while the body that carries the phone still turns once per stride.

Each step gets a ``confidence`` in [0, 1]: the periodicity at the step times
the regularity of its timing (1 - |interval - T| / T, the mean interval to
its neighbours in the same bout against the local step period), halved where
the stride was inferred from the cadence range alone (no half-period
evidence). The per-window cadence is kept in ``cadence_``.

5. **Bout edges.** Steps form walking bouts: an interval longer than
   ``BOUT_GAP_RATIO`` (2) local step periods ends a bout (from 2 T on the
   timing regularity above is 0, so such an interval is no step interval; a
   step alone in its bout has no timing evidence and confidence 0). The
   leading and trailing steps of a bout whose confidence is below
   ``edge_confidence_ratio`` (0.5) times the bout's median confidence are
   dropped, up to the first (last) step that reaches it; steps inside a bout
   are kept whatever their confidence. Why: the cadence windows are 5 s long,
   so a window that straddles the start or end of a walk lends its
   periodicity to the seconds of non-walking beside it. There the peak picker
   finds regular-looking peaks at the walk's cadence: handling the phone
   before the first step, a neck pouch or bag that swings on after the last
   one (a pendulum whose |acc| oscillates at twice its swing frequency,
   about the step frequency for a 0.2-0.4 m strap). Such peaks fit the
   step period poorly and sit in windows only partly periodic, so their
   confidence is low against the bout's typical step; a true first or last
   step keeps most of it. 0.5 means "less than half the evidence of the
   bout's typical step"; being relative to the bout, it needs no absolute
   confidence scale and treats one-leg bouts (confidence halved by
   ``INFERRED_STRIDE_FACTOR``) like any other. Last, a bout counts once
   ``min_bout_steps`` (4) of its steps remain: two strides, the shortest run
   in which each foot's step repeats. Step counters hold back a new bout until
   a run of regular steps confirms it and then count the confirming steps
   too; here the whole confirmed bout counts, so only its weak fringe and
   unconfirmed fragments (handling, a bump between walks) are lost (the
   effect is measured in ``experiments/reports/steps-heldout.md``, section
   "Bout edges").

5a. **One octave per bout** (opt-in, with a gyroscope; :func:`bout_octave`).
   The 5 s cadence windows decide stride or step each on its own, so a slow
   walker whose |acc| shows two peaks per step (heel strike and push-off, the
   double hump of the vertical ground reaction force; Perry & Burnfield,
   *Gait Analysis*, 2010, ch. 4) may be read at half a step in some windows
   of a walk and at a step in others. With ``octave_swing_min_correlation``
   > 0, before the confidence and bout rules above, each bout (steps no more
   than ``BOUT_GAP_RATIO`` periods apart) is given one octave from the
   phone's swing pooled over the whole bout (one arm, thigh or trunk cycle
   per stride, reversing between the steps): where that swing is regular and
   twice the bout's median peak interval lies nearer the swing's step (half
   its stride period) than the interval itself, within
   ``octave_match_tolerance``, the bout's peaks are half-steps and its steps
   are picked again (stages 3-4 on the bout, the period fixed at twice its
   median peak interval, the higher of two peaks closer than
   ``min_distance_ratio`` of it kept). Such a bout, when short, passes the
   short-bout rule's amplitude test if its step intervals vary by at most
   ``max_short_bout_interval_cv``. Only half-steps are corrected here: one
   peak per stride is stage 2b's decision, and a phone that turns once per
   |acc| peak is what the gait check reads as a gesturing hand. Off by
   default: on the tyrex recordings it removes the extra steps (per-step
   F1 up) but lowers the count accuracy, whose over-counts offset misses
   elsewhere in the same walks (``experiments/reports/tyrex-steps.md``).

5b. **Walking episodes** (with a gyroscope; :func:`_episode_keep`,
   :func:`episode_steps_after_check`). A walker who slows, stops or turns
   breaks the rhythm for one or two steps, and the steps around the break
   form short bouts that the minimum-bout and short-bout rules drop. Bouts no
   more than ``episode_gap_ratio`` (3) local step periods apart are one
   walking episode, and a bout those rules drop is kept when its step
   intervals are regular (coefficient of variation at most
   ``max_bout_interval_cv``, 0.2; stride-time CV of healthy walking is 1-3 %,
   Hausdorff, *J. NeuroEng. Rehabil.* 2, 2005) and its episode holds a
   walking bout: one that passes the rules alone with at least
   ``episode_walk_steps`` (10) steps, the pedometers' confirmation. With
   ``edge_interval_match`` the edge rule also keeps a weak edge step whose
   interval to its neighbour is within ``max_bout_interval_cv`` of its
   bout's median interval (in bouts of ``episode_walk_steps``). The steps the
   stage adds are held back from the gait check: today's steps are checked,
   and a rescued bout joins only when a walking bout of its episode survived
   the check (an edge step: when its own bout did), so a rescued burst never
   outlives the walking that justified it. It runs only where the gait check
   reads a gyroscope; without one the step table is that of stages 1-5.
   Its settings were chosen leave-one-person-out on tyrex, admissible only
   if no simulated gesture or desk recording gets a step more (round 3,
   ``experiments/reports/tyrex-steps.md``, bouts and bouts2 sections, with
   the figures). Rounds 1-2 ran it before the gait check
   (``episode_before_gait_check``; it added gesture steps then). The fold (stage 3) pulls an irregular run's
   peaks towards the local period, so the picked intervals look more regular
   than the steps were.

Evaluated on the Oxford step counter optimisation recordings (Salvi et al.,
CC BY 4.0) in sample and leave-one-user-out (``gaitml evaluate
experiments/steps-real.toml``, ``experiments/reports/steps-heldout.md``).
"""

from __future__ import annotations

import warnings
from typing import ClassVar

import numpy as np
import pandas as pd
import scipy.signal

from gaitml._base import NON_NEGATIVE, NON_NEGATIVE_INTEGER, POSITIVE, POSITIVE_INTEGER, Interval
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.signal import bandpass, sliding_windows
from gaitml.steps._base import BaseStepDetector
from gaitml.steps._common import acc_magnitude, as_recording, segment_argmax
from gaitml.steps._gait_evidence import gait_check
from gaitml.steps._table import make_step_table

__all__ = [
    "RATE_FLOOR_HZ",
    "AdaptiveStepDetector",
    "local_cadence",
    "cadence_decimation",
    "cadence_hop_samples",
    "adaptive_steps",
    "episode_steps_after_check",
    "fold_steps",
    "slow_step_noise_floor",
    "window_autocorrelation",
    "swing_correlation",
    "gyro_stride_or_step",
    "gyro_swing_cadence",
    "swing_stride",
    "swing_rhythm",
    "rhythm_windows",
    "bout_octave",
    "octave_counts",
]

#: gait band of the band-pass (Hz): below the slowest stride, above the fastest step
BAND_HZ = (0.5, 4.0)
#: cadence windows (s)
WINDOW_S = 5.0
HOP_S = 1.0
#: human step frequencies, very slow walking to running (Hz). 0.75 Hz = 45 steps/min: walking cadence reaches
#: below 60 steps/min (CADENCE-Adults, Tudor-Locke et al., IJBNPA 17:137, 2020: the 95 % predictive interval
#: of the cadence at 3 METs reaches down to 54.9 steps/min; treadmill bouts from 0.5 mph, 0.22 m/s)
MIN_STEP_HZ = 0.75
MAX_STEP_HZ = 3.5
#: below this step frequency a period is a slow step only where the motion is gentle (see SLOW_STEP_MAX_RMS_MS2)
SLOW_STEP_HZ = 1.2
#: a window whose band-passed |acc| RMS exceeds this (m/s^2) cannot hold steps slower than SLOW_STEP_HZ: the
#: trunk's vertical acceleration is about (2 pi f)^2 times half its vertical excursion, at most ~0.85 m/s^2
#: amplitude (0.6 RMS) at 1.2 steps/s with the ~3 cm excursion of slow walking (Orendurff et al., J. Rehabil.
#: Res. Dev. 41, 2004); the ceiling allows 2.5 times that for the phone's own motion. A period there is a stride,
#: except where the gyroscope shows a phone that does not swing (no thigh or arm to make a one-leg stride)
SLOW_STEP_MAX_RMS_MS2 = 1.5
#: a slow step is in deep anti-phase at half its period: a period longer than 1 / SLOW_STEP_HZ whose
#: autocorrelation at its half is above this is a stride (a step period gives -0.55 to -0.98 at its half on every
#: Oxford recording; a one-leg stride, whose both heel strikes shake the phone, stays near 0)
SLOW_STEP_MAX_HALF_CORRELATION = -0.5
#: windows either side that must not contradict a slow-step reading (a slow window among windows of twice
#: its cadence is a stride of the same walk)
SLOW_STEP_CONTEXT = 3
#: an autocorrelation above this at half the fundamental period makes that period a stride
HALF_LAG_MIN_CORRELATION = 0.0
#: band of the gyroscope's swing (Hz): from below the slowest stride (0.375 Hz, two steps at MIN_STEP_HZ) to above
#: the fastest step
GYRO_BAND_HZ = (0.3, 4.0)
#: the gyroscope decides stride or step only where the phone turns more than this (rad/s RMS of the swing axis):
#: phone gyroscope noise is under 0.01 rad/s over the gait band; the trunk's rotation (pelvis +-4-5 deg once per
#: stride) turns a phone held in front by ~0.1-0.5 rad/s, an arm or thigh swing (+-20 deg) by 1-3.
#: Chosen leave-one-person-out on the tyrex recordings from 0.05 / 0.2 / 0.5 / 1.0 (experiments/reports/tyrex-steps.md)
GYRO_MIN_RMS_RADS = 0.2
#: a correlation of the swing rate at least this deep (negative) or high (positive) counts as anti-phase or in
#: phase. Chosen leave-one-person-out on the tyrex recordings from 0.3 / 0.5 / 0.7 (same report)
GYRO_PHASE_CORRELATION = 0.7
#: stage 2c (off by default, 0): where |acc|'s periodicity is below MIN_PERIODICITY, a swing whose autocorrelation at
#: its stride period reaches this sets the step period and periodicity. 0.3 (|acc|'s own floor) turns it on: the choice
#: of two of the three leave-one-person-out folds on the tyrex recordings (0.2 on the third) when the simulated non-gait
#: is not weighed (experiments/reports/tyrex-steps.md, where it is not adopted as the default: it adds steps to gestures)
GYRO_SWING_MIN_PERIODICITY = 0.0
#: stage 2c: the swing's autocorrelation at half its stride period must be at most minus this (0: negative; the swing
#: reverses between the left and the right step)
GYRO_SWING_HALF_CORRELATION = 0.0
#: stage 2c: |acc|'s autocorrelation at the swing's step period must reach this (the steps still repeat in |acc|,
#: however weakly); -1 is no test
GYRO_SWING_ACC_CORRELATION = -1.0
#: stage 2c: a walking bout with a step from a swing-set window counts only from this many steps (the pedometers'
#: ten-step confirmation, Bassett et al. 1996); 0 (or at most min_bout_steps) is no extra confirmation
GYRO_SWING_MIN_BOUT_STEPS = 0
#: steps only where the window's periodicity reaches this
MIN_PERIODICITY = 0.3
#: sensor noise floor (m/s^2 RMS of the band-passed magnitude): phone accelerometers ~0.01-0.05, walking > 0.5
MIN_RMS_MS2 = 0.2
#: the lowest the noise floor may scale to at steps slower than SLOW_STEP_HZ (m/s^2; opt-in, off at MIN_RMS_MS2): for
#: a given vertical excursion the trunk's vertical acceleration is (2 pi f)^2 times half of it (Orendurff et al., J.
#: Rehabil. Res. Dev. 41, 2004, as SLOW_STEP_MAX_RMS_MS2), so below SLOW_STEP_HZ the floor is MIN_RMS_MS2 x
#: (f / SLOW_STEP_HZ)^2, but not below this. Measured on tyrex (experiments/reports/tyrex-steps.md, texstep section)
MIN_RMS_SLOW_MS2 = MIN_RMS_MS2
#: stage 4's gyroscope relief of the periodicity floor (opt-in, with a gyroscope; 0: off, as at min_periodicity or above): a
#: peak that only the periodicity floor removes (|acc|'s periodicity below ``min_periodicity``) is kept when its
#: periodicity reaches this and the phone turns with a stride rhythm there whose step matches the window's
#: (:func:`swing_rhythm`, :data:`RHYTHM_STEP_TOLERANCE`). A calm hand-held walk's trunk barely bounces, so |acc| repeats
#: weakly, while the body that carries the phone still turns once per stride and reverses between the steps (Perry &
#: Burnfield, Gait Analysis, 2nd ed. 2010, ch. 10): a second sensor confirms the gait the weak |acc| rhythm suggests.
#: Unlike stage 2c the swing sets neither the step period nor the periodicity. Measured on tyrex
#: (experiments/reports/tyrex-steps.md, "perio" section)
RHYTHM_MIN_PERIODICITY = 0.0
#: the periodicity-floor relief: the swing's step (half its stride period) must lie within this fraction of the cadence
#: window's |acc| step period (a ratio of 0.75-1.25), so a window read at half a step (a push-off peak) or at a stride
#: finds no relief. The value of OCTAVE_MATCH_TOLERANCE, the "match" of the tyrex window diagnosis
#: (experiments/reports/tyrex-steps.md), which stage 5a reads on a log scale (0.8-1.25)
RHYTHM_STEP_TOLERANCE = 0.25
#: a step is the highest peak of the folded signal within this fraction of the step period either side
MIN_DISTANCE_RATIO = 0.6
#: a shorter lag whose autocorrelation peak reaches this fraction of the best is the fundamental period
#: (the multiples of a period correlate almost as well as the period itself)
OCTAVE_TOLERANCE = 0.9
#: the cadence autocorrelation runs at about this rate (decimated band-limited signal)
CADENCE_RATE_HZ = 25.0
#: the confidence factor of a step whose stride was inferred from the cadence range alone
INFERRED_STRIDE_FACTOR = 0.5
#: an interval longer than this many local step periods separates two walking bouts: the timing regularity
#: 1 - |interval - T| / T of a step is 0 from an interval of 2 T on, so such an interval is no step interval
BOUT_GAP_RATIO = 2.0
#: a bout's leading / trailing steps with less than this fraction of the bout's median confidence are dropped
#: (half the evidence of a typical step of the same bout; a ratio, so the same for one-leg bouts whose
#: confidence is halved by INFERRED_STRIDE_FACTOR)
EDGE_CONFIDENCE_RATIO = 0.5
#: a walking bout counts once it holds this many steps: two strides, the shortest run in which each foot's step
#: repeats (left, right, left, right), as the continuity rule of wrist step counters (Gu et al. 2017: 4 steps)
MIN_BOUT_STEPS = 4
#: a bout of fewer steps than this is short: it counts only if its steps repeat their strength (step-amplitude
#: coefficient of variation <= MAX_SHORT_BOUT_CV) and its steps' confidence is scaled by (steps / this). Ten steps:
#: the continuity rule of pedometers that hold back a new bout until about ten regular steps (Bassett et al.,
#: Med. Sci. Sports Exerc. 28, 1996, on the 10-step delay of spring-levered pedometers)
SHORT_BOUT_STEPS = 10
#: the largest step-amplitude coefficient of variation of a short bout: walking bouts repeat their steps' strength
#: (CV 0.13-0.36, 90th percentile per position on the Oxford walks) while a gesture burst waxes and wanes (~0.5)
MAX_SHORT_BOUT_CV = 0.4
#: stage 5a, the per-bout octave (with a gyroscope; 0: off): a bout's octave is decided from its swing where the swing,
#: pooled over the whole bout, correlates at least this at its stride period (one arm, thigh or trunk cycle per stride:
#: Perry & Burnfield, Gait Analysis, 2nd ed. 2010, ch. 10; Meyns, Bruijn & Duysens, Gait Posture 38, 2013)
OCTAVE_SWING_MIN_CORRELATION = 0.0
#: stage 5a: the pooled swing must be in anti-phase at half its stride period, its autocorrelation there at most
#: minus this (0: negative; the swing reverses between the left and the right step)
OCTAVE_SWING_HALF_CORRELATION = 0.0
#: stage 5a: a bout's median step interval is read at the octave (half, same, double) that brings it within this
#: fraction of the swing's step (half its stride period); outside every octave's tolerance the bout is left as it is.
#: 0.25 is the 0.8-1.25 "match" band of the tyrex window diagnosis (experiments/reports/tyrex-steps.md)
OCTAVE_MATCH_TOLERANCE = 0.25
#: stage 5a: a short bout whose octave the swing decided passes the short-bout rule without its amplitude test when
#: the coefficient of variation of its step intervals, at the decided octave, is at most this (0: no exemption).
#: Healthy step-time variability is a few per cent (stride-time CV 1-3 %, Hausdorff, J. NeuroEng. Rehabil. 2, 2005),
#: a few times that at slow speeds; a gesture burst's beats are not tied to a swing cycle
MAX_SHORT_BOUT_INTERVAL_CV = 0.0
#: stage 5b, walking episodes (0: off): two bouts whose separating interval is at most this many local step periods
#: are one walking episode. A walker who slows, stops or turns breaks the rhythm for one or two steps (the gap between
#: two bouts is over BOUT_GAP_RATIO periods once one step is missed; 3 periods: one or two steps missed). The detector's
#: default since round 3 (after the gait check, with a gyroscope only), chosen leave-one-person-out on tyrex over the
#: grid G in {3, 5} x C in {0.1, 0.2} x edge match, admissible on simulated non-gait seeds
#: (experiments/reports/tyrex-steps.md, "bouts2 helper"); :func:`adaptive_steps` alone keeps it off (0.0), as it has no
#: gait check
EPISODE_GAP_RATIO = 3.0
#: stage 5b: a bout the minimum-bout or short-bout rule would drop is kept when the coefficient of variation of its step
#: intervals is at most this (a bout of two steps: its interval within this fraction of the local step period) and its
#: episode holds a bout that passes those rules on its own. Healthy walking's stride-time CV is 1-3 % (Hausdorff,
#: J. NeuroEng. Rehabil. 2, 2005); 0.2 (round 3's choice, report above; 0.1 was the grid's other value) leaves room for
#: the jitter of a phone's peaks and slow walking
MAX_BOUT_INTERVAL_CV = 0.2
#: stage 5b: the edge rule also keeps a weak edge step whose interval to its neighbour is within MAX_BOUT_INTERVAL_CV
#: of its bout's median interval (off: the edge rule reads the confidence alone); on since round 3 (report above)
EDGE_INTERVAL_MATCH = True
#: stage 5b: the walking beside a bout is a bout that passes the bout rules alone with at least this many kept steps, and
#: the edge rule's interval match applies in bouts of at least this many steps: the ten regular steps with which
#: pedometers confirm a walk (Bassett et al., Med. Sci. Sports Exerc. 28, 1996; SHORT_BOUT_STEPS, and the step table's
#: CONFIDENT_BOUT_STEPS). 0: any bout that passes alone is walking, and the interval match applies in every bout
EPISODE_WALK_STEPS = 10


def window_autocorrelation(y: np.ndarray, length: int, hop: int, lags: np.ndarray) -> np.ndarray:
    """Normalised autocorrelation of every sliding window at ``lags``, each lag normalised by its own segments.

    For the window ``w`` (``length`` samples from ``i * hop``, its mean removed)
    and lag ``k``: ``sum(w[:-k] * w[k:]) / sqrt(sum(w[:-k] ** 2) * sum(w[k:] ** 2))``,
    so a lag of a periodic signal correlates as well as a short one (no
    ``(L - k) / L`` decay); 0 where a segment has no energy. Shape
    ``(n_windows, len(lags))``.
    """
    L = int(length)
    w = sliding_windows(np.asarray(y, dtype=float), L, int(hop))
    w = w - w.mean(axis=1, keepdims=True)
    c = np.concatenate([np.zeros((w.shape[0], 1)), np.cumsum(w * w, axis=1)], axis=1)
    r = np.zeros((w.shape[0], len(lags)))
    for j, k in enumerate(np.asarray(lags).tolist()):
        # direct products at the lags needed only: cheaper than an FFT of every window
        num = np.einsum("ij,ij->i", w[:, : L - k], w[:, k:])
        den = np.sqrt(c[:, L - k] * (c[:, L] - c[:, k]))
        r[:, j] = np.divide(num, den, out=np.zeros_like(num), where=den > 0)
    return r


def cadence_decimation(sampling_rate_hz: float) -> int:
    """The decimation factor of the cadence estimate: every ``q``-th sample, ``q = floor(fs / CADENCE_RATE_HZ)``
    (at least 1), so that the autocorrelation runs at about :data:`CADENCE_RATE_HZ` (module docstring, stage 2)."""
    return max(1, int(float(sampling_rate_hz) // CADENCE_RATE_HZ))


def cadence_hop_samples(sampling_rate_hz: float, hop_s: float = HOP_S) -> int:
    """The hop of :func:`adaptive_steps`' cadence windows in samples of its input.

    The windows are cut from the signal decimated by ``q`` (:func:`cadence_decimation`) every
    ``round(hop_s * fs / q)`` decimated samples, so window ``k`` starts at input sample ``k * hop``, with
    ``hop = round(hop_s * fs / q) * q`` (e.g. 90 samples at 90.09 Hz, not 90.09). A part of a longer
    signal whose first sample is a multiple of ``hop`` has its windows on the longer signal's grid (and
    decimates the same samples).
    """
    fs = float(sampling_rate_hz)
    q = cadence_decimation(fs)
    return max(1, int(round(hop_s * fs / q))) * q


def local_cadence(
    y: np.ndarray,
    sampling_rate_hz: float,
    *,
    window_s: float = WINDOW_S,
    hop_s: float = HOP_S,
    min_step_hz: float = MIN_STEP_HZ,
    max_step_hz: float = MAX_STEP_HZ,
    half_lag_min_correlation: float = HALF_LAG_MIN_CORRELATION,
    slow_step_hz: float = SLOW_STEP_HZ,
    slow_step_max_rms_ms2: float = SLOW_STEP_MAX_RMS_MS2,
    slow_step_max_half_correlation: float = SLOW_STEP_MAX_HALF_CORRELATION,
    still: np.ndarray | None = None,
) -> dict[str, np.ndarray]:
    """Step period per sliding window, with the stride-versus-step decision (module docstring, stage 2).

    Parameters
    ----------
    y : float array (n,)
        Band-passed signal (zero mean), e.g. the acceleration magnitude.
    sampling_rate_hz : float
    window_s, hop_s, min_step_hz, max_step_hz, half_lag_min_correlation, slow_step_hz, slow_step_max_rms_ms2,
    slow_step_max_half_correlation
        As :class:`AdaptiveStepDetector`.
    still : bool array (one per window), optional
        Windows where the gyroscope shows the phone does not swing (swing RMS
        below ``GYRO_MIN_RMS_RADS``): the motion ceiling
        ``slow_step_max_rms_ms2`` does not apply there (module docstring,
        stage 2). None (no gyroscope): it applies everywhere.

    Returns
    -------
    dict
        ``centre`` (int, window centre samples), ``period_s`` (step period, s),
        ``periodicity`` (the strongest autocorrelation peak, in [-1, 1]),
        ``step_correlation`` (autocorrelation at the step period),
        ``stride`` (bool: the strongest peak was a stride, not a step) and
        ``inferred`` (bool: the stride was inferred from the cadence range
        alone, without a half-period peak) and ``rms`` (band-passed RMS,
        m/s^2), one entry per window.

    Raises
    ------
    InputError
        If the signal is shorter than the longest stride searched.
    """
    fs = float(sampling_rate_hz)
    y = np.asarray(y, dtype=float)
    n = len(y)
    L = min(n, int(round(window_s * fs)))
    H = max(1, int(round(hop_s * fs)))
    lo = max(2, int(np.floor(fs / max_step_hz)))
    # strides are searched up to two steps at slow_step_hz: a longer lag holds three steps of a normal walk
    # (a 0.75 s step: 2.25 s) that may correlate better than the step itself; slow steps (up to 1 / min_step_hz)
    # lie inside this range
    hi = int(np.ceil(2.0 * fs / max(min_step_hz, slow_step_hz)))
    if hi + 2 >= L:
        raise InputError(
            f"the recording is too short for the adaptive cadence estimate: {n} samples ({n / fs:.2f} s); "
            f"it needs more than {(hi + 2) / fs:.2f} s (two steps at {max(min_step_hz, slow_step_hz)} Hz); use a longer recording."
        )
    n_win = (n - L) // H + 1
    centres = np.arange(n_win) * H + L // 2
    lags = np.arange(lo - 1, hi + 2)
    r = window_autocorrelation(y, L, H, lags)
    rows = np.arange(len(r))
    inner = np.arange(1, len(lags) - 1)  # the lags lo .. hi, with a neighbour on each side
    is_max = np.zeros_like(r, dtype=bool)
    is_max[:, inner] = (r[:, inner] >= r[:, inner - 1]) & (r[:, inner] > r[:, inner + 1])
    peaks = np.where(is_max, r, -np.inf)
    j = np.argmax(peaks, axis=1)
    none = ~np.isfinite(peaks[rows, j])
    j = np.where(none, 1 + np.argmax(r[:, inner], axis=1), j)
    periodicity = r[rows, j]
    # the fundamental: the shortest lag whose peak repeats nearly as well as the best one (multiples of a
    # period correlate about as well as the period itself once each lag is normalised by its own energies)
    near = peaks >= OCTAVE_TOLERANCE * periodicity[:, None]
    j = np.where(near.any(axis=1) & ~none, np.argmax(near, axis=1), j)

    def refined(jj):
        # sub-sample lag: parabola through the peak and its neighbours
        r0, rm, rp = r[rows, jj], r[rows, jj - 1], r[rows, jj + 1]
        den = rm - 2 * r0 + rp
        delta = np.divide(0.5 * (rm - rp), den, out=np.zeros_like(den), where=den < 0)
        return lags[jj] + np.clip(delta, -0.5, 0.5)

    def r_at(lag_f):
        # the autocorrelation at a fractional lag (linear interpolation between lags)
        x = np.clip(lag_f - lags[0], 0, len(lags) - 1.000001)
        i0 = np.floor(x).astype(int)
        f = x - i0
        return r[rows, i0] * (1 - f) + r[rows, i0 + 1] * f

    lag = refined(j)
    stride = np.zeros(len(r), dtype=bool)
    # half-period structure: the signal shifted by half the period still resembles itself (correlation above
    # half_lag_min_correlation) -> two similar events per period, the period is a stride; the step period is the
    # local maximum near the half lag, or the half lag itself when the autocorrelation has a plateau there
    for _ in range(3):
        half = lag / 2.0
        take = (half >= lo) & (r_at(half) > half_lag_min_correlation)
        if not take.any():
            break
        ok_lag = (lags[None, :] >= np.maximum(lo, 0.85 * half)[:, None]) & (lags[None, :] <= 1.15 * half[:, None])
        cand = np.where(ok_lag & is_max, r, -np.inf)
        jh = np.argmax(cand, axis=1)
        near_max = np.isfinite(cand[rows, jh]) & (cand[rows, jh] > half_lag_min_correlation)
        lag = np.where(take, np.where(near_max, refined(jh), half), lag)
        stride |= take
    # still longer than any human step: a stride whose other step is not visible; slower than slow_step_hz with
    # more motion than a slow walker makes (window RMS over slow_step_max_rms_ms2): a stride too
    rms = np.sqrt(np.mean(sliding_windows(y, L, H)[:n_win] ** 2, axis=1))
    half_correlation = r_at(lag / 2.0)
    # not in deep anti-phase at its half: a one-leg stride
    slower = lag > fs / slow_step_hz
    # the motion ceiling stands for a one-leg stride of normal walking, whose phone swings with the thigh or arm:
    # where the gyroscope shows a phone that does not swing, that alternative is gone and the ceiling is lifted
    ceiling = rms > slow_step_max_rms_ms2
    if still is not None:
        ceiling &= ~np.asarray(still, dtype=bool)[:n_win]
    inferred = (lag > fs / min_step_hz) | (slower & (ceiling | (half_correlation > slow_step_max_half_correlation)))
    # a slow step must persist: a slow reading among windows of twice that cadence (within SLOW_STEP_CONTEXT
    # windows either side) is a stride of the same walk (cadence does not halve for a window)
    slow = (lag > fs / slow_step_hz) & ~inferred & ~stride
    if slow.any():
        k = SLOW_STEP_CONTEXT
        for i in np.flatnonzero(slow):
            nb = np.r_[max(0, i - k) : i, i + 1 : min(len(lag), i + k + 1)]
            nb = nb[~slow[nb]]
            if len(nb) and len(nb) >= (min(len(lag), i + k + 1) - max(0, i - k) - 1) / 2:
                inferred[i] = abs(np.median(lag[nb]) / (lag[i] / 2.0) - 1.0) < 0.2
    lag = np.where(inferred, lag / 2.0, lag)
    return {
        "centre": centres,
        "period_s": lag / fs,
        "periodicity": periodicity,
        "step_correlation": r_at(lag),
        "stride": stride | inferred,
        "inferred": inferred,
        "rms": rms,
        "half_correlation": half_correlation,
    }


def swing_correlation(gyr: np.ndarray, length: int, hop: int, n_windows: int, lags: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The phone's swing rate per cadence window and its normalised autocorrelation at fractional ``lags``.

    In each window (``length`` samples from ``i * hop``) the band-passed
    angular rate ``gyr`` (n, 3) is projected on its principal axis (the axis
    the phone swings or rocks about most); ``rms`` is that projection's RMS
    (rad/s) and ``corr[i, j]`` its autocorrelation at ``lags[i, j]`` samples
    (each lag normalised by its own segments, as
    :func:`window_autocorrelation`; linear between integer lags; NaN where a
    lag leaves fewer than two samples).
    """
    proj, rms = swing_projection(gyr, length, hop, n_windows)
    return rms, projection_correlation(proj, lags)


def swing_projection(gyr: np.ndarray, length: int, hop: int, n_windows: int) -> tuple[np.ndarray, np.ndarray]:
    """Per window: the band-passed angular rate projected on its principal axis (n_windows, length) and its RMS."""
    w = sliding_windows(np.asarray(gyr, dtype=float), int(length), int(hop))[:n_windows]
    w = w - w.mean(axis=1, keepdims=True)
    cov = np.einsum("nlc,nld->ncd", w, w)
    axis = np.linalg.eigh(cov)[1][:, :, -1]
    proj = np.einsum("nlc,nc->nl", w, axis)
    return proj, np.sqrt(np.mean(proj**2, axis=1))


def projection_correlation(proj: np.ndarray, lags: np.ndarray) -> np.ndarray:
    """Normalised autocorrelation of each window's projection at fractional ``lags`` (see :func:`swing_correlation`)."""
    lags = np.asarray(lags, dtype=float)
    L = proj.shape[1]
    k0 = np.floor(lags).astype(np.int64)
    valid = (k0 >= 1) & (k0 + 1 <= L - 2)
    corr = np.full(lags.shape, np.nan)
    if not valid.any():
        return corr
    kmax = int(k0[valid].max()) + 1
    # each lag normalised by its own two segments, as window_autocorrelation; every window at every lag up to kmax
    c = np.concatenate([np.zeros((proj.shape[0], 1)), np.cumsum(proj * proj, axis=1)], axis=1)
    r = np.zeros((proj.shape[0], kmax + 1))
    for k in range(1, kmax + 1):
        num = np.einsum("ij,ij->i", proj[:, : L - k], proj[:, k:])
        den = np.sqrt(c[:, L - k] * (c[:, L] - c[:, k]))
        r[:, k] = np.divide(num, den, out=np.zeros_like(num), where=den > 0)
    rows = np.broadcast_to(np.arange(lags.shape[0])[:, None], lags.shape)
    ka = np.where(valid, k0, 1)
    f = lags - ka
    corr = np.where(valid, (1.0 - f) * r[rows, ka] + f * r[rows, np.minimum(ka + 1, kmax)], np.nan)
    return corr


def gyro_stride_or_step(
    cadence: dict[str, np.ndarray],
    gyr: np.ndarray,
    sampling_rate_hz: float,
    length: int,
    hop: int,
    *,
    min_step_hz: float = MIN_STEP_HZ,
    max_step_hz: float = MAX_STEP_HZ,
    min_rms_rads: float = GYRO_MIN_RMS_RADS,
    phase_correlation: float = GYRO_PHASE_CORRELATION,
    projection: tuple[np.ndarray, np.ndarray] | None = None,
) -> dict[str, np.ndarray]:
    """Correct the stride-versus-step decision of :func:`local_cadence` with the gyroscope (module docstring, stage 2b).

    Every rotation of the body that carries the phone completes one cycle per
    stride and reverses between the left and the right step: the arm swing
    (Meyns, Bruijn & Duysens, Gait Posture 38, 2013: one arm cycle per stride
    in normal walking), the thigh swing that turns a trouser-pocket phone, and
    the pelvis and trunk rotation and sway that rock a phone held in front of
    the body (Perry & Burnfield, Gait Analysis, 2nd ed. 2010, ch. 10: one
    rotation cycle per gait cycle). So the swing rate (the gyroscope on its
    principal axis, :func:`swing_correlation`) is in anti-phase one step
    later and in phase one stride later, whatever the phone's |acc| shows.
    With the window's step period ``T``:

    - ``T`` kept as read (no stride found) while the swing is in phase at
      ``T`` and in anti-phase at ``T / 2`` (correlations beyond
      +-``phase_correlation``): ``T`` is a stride, the step is ``T / 2``
      (a running arm or thigh whose |acc| shows one event per stride);
    - ``T`` halved from a stride while the swing is not in anti-phase at
      ``T`` but is at ``2 T``: ``2 T`` is the step (a swinging hand's |acc|
      peaks at both ends of each swing, once per step, with more motion
      than the slow-step rule allows a slow walker).

    Applied only where the swing's RMS reaches ``min_rms_rads`` and the new
    period stays within the human step range; the other windows keep the
    accelerometer's decision. ``projection``: :func:`swing_projection` of
    ``gyr`` on the same windows, if already computed. Returns a copy of ``cadence`` with ``period_s``,
    ``stride`` and ``inferred`` corrected and ``gyro`` (+1: halved, -1:
    doubled, 0: unchanged) and the swing's ``gyro_rms`` added (``step_correlation``
    stays the accelerometer's autocorrelation at the period it chose).
    """
    fs = float(sampling_rate_hz)
    out = dict(cadence)
    T = np.asarray(cadence["period_s"], dtype=float) * fs
    n_win = len(T)
    lags = np.column_stack([T / 2.0, T, 2.0 * T])
    if projection is None:  # (proj, rms) of swing_projection on the same windows, when the caller has it
        projection = swing_projection(gyr, length, hop, n_win)
    proj, rms = projection
    c = projection_correlation(proj, lags)
    c = np.nan_to_num(c, nan=0.0)
    rho = float(phase_correlation)
    moving = rms >= min_rms_rads
    stride = np.asarray(cadence["stride"], dtype=bool)
    halve = moving & ~stride & (c[:, 1] >= rho) & (c[:, 0] <= -rho) & (T / 2.0 >= fs / max_step_hz)
    double = moving & stride & (c[:, 1] > -rho) & (c[:, 2] <= -rho) & (2.0 * T <= fs / min_step_hz)
    out["period_s"] = np.where(halve, T / 2.0, np.where(double, 2.0 * T, T)) / fs
    out["stride"] = (stride | halve) & ~double
    out["inferred"] = np.asarray(cadence["inferred"], dtype=bool) & ~halve & ~double
    out["gyro"] = halve.astype(np.int64) - double.astype(np.int64)
    out["gyro_rms"] = rms
    return out


def swing_stride(proj: np.ndarray, sampling_rate_hz: float, *, min_step_hz: float = MIN_STEP_HZ, max_step_hz: float = MAX_STEP_HZ):
    """The swing's stride period per window: ``(period samples, correlation there, correlation at its half)``.

    Over the stride lags ``2 / max_step_hz`` .. ``2 / min_step_hz`` (two steps
    of the human range) the shortest autocorrelation peak of the swing
    projection (:func:`swing_projection`) within ``OCTAVE_TOLERANCE`` of the
    strongest one, as stage 2 picks |acc|'s fundamental. NaN period where no
    peak lies inside the range.
    """
    fs = float(sampling_rate_hz)
    n_win, L = proj.shape
    lo, hi = int(np.floor(2.0 * fs / max_step_hz)), int(np.ceil(2.0 * fs / min_step_hz))
    lags = np.arange(max(lo - 1, 1), min(hi + 2, L - 2))
    if len(lags) < 3 or n_win == 0:
        nan = np.full(n_win, np.nan)
        return nan, nan.copy(), nan.copy()
    r = np.nan_to_num(projection_correlation(proj, np.broadcast_to(lags.astype(float), (n_win, len(lags)))), nan=-1.0)
    inner = np.arange(1, len(lags) - 1)
    is_max = np.zeros_like(r, dtype=bool)
    is_max[:, inner] = (r[:, inner] >= r[:, inner - 1]) & (r[:, inner] > r[:, inner + 1])
    peaks = np.where(is_max, r, -np.inf)
    best = peaks.max(axis=1)
    near = is_max & (peaks >= OCTAVE_TOLERANCE * best[:, None])
    j = np.argmax(near, axis=1)
    ok = np.isfinite(best)
    period = np.where(ok, lags[j].astype(float), np.nan)
    corr = np.where(ok, r[np.arange(n_win), j], np.nan)
    half = projection_correlation(proj, np.where(ok, period / 2.0, 2.0)[:, None])[:, 0]
    return period, corr, np.where(ok, half, np.nan)


def swing_rhythm(
    proj: np.ndarray,
    rms: np.ndarray,
    sampling_rate_hz: float,
    *,
    min_step_hz: float = MIN_STEP_HZ,
    max_step_hz: float = MAX_STEP_HZ,
    min_rms_rads: float = GYRO_MIN_RMS_RADS,
    min_correlation: float = MIN_PERIODICITY,
    half_correlation: float = GYRO_SWING_HALF_CORRELATION,
) -> tuple[np.ndarray, np.ndarray]:
    """Per window of the swing projection (:func:`swing_projection`, ``proj`` and its ``rms``): does the phone turn
    with a stride rhythm? Returns ``(rhythm, period)``, ``period`` the swing's stride period in samples
    (:func:`swing_stride`, NaN where none).

    The body that carries the phone rotates once per stride and reverses between the left and the right step (Perry &
    Burnfield, *Gait Analysis*, 2nd ed. 2010, ch. 10); a standing body's sway has no stride period and reverses at no
    half-stride. A rhythm: the swing's RMS reaches ``min_rms_rads``, its stride period ``P`` correlates at least
    ``min_correlation``, the swing is in anti-phase at ``P / 2`` (correlation at most ``-half_correlation``) and
    ``P / 2`` is a step of the human range. The test of :func:`gaitml.models.stride_rhythm` (predict's
    ``still_unsure`` mark), which calls this; the periodicity floor's relief in :func:`adaptive_steps` reads it on the
    cadence windows.
    """
    ok, period, _ = _rhythm_test(
        proj,
        rms,
        float(sampling_rate_hz),
        min_step_hz=min_step_hz,
        max_step_hz=max_step_hz,
        min_rms_rads=min_rms_rads,
        min_correlation=min_correlation,
        half_correlation=half_correlation,
    )
    return ok, period


def _rhythm_test(
    proj: np.ndarray,
    rms: np.ndarray,
    fs: float,
    *,
    min_step_hz: float,
    max_step_hz: float,
    min_rms_rads: float,
    min_correlation: float,
    half_correlation: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`swing_rhythm`'s test, also giving the swing's correlation at its stride period: ``(rhythm, period,
    corr)``. Stage 2c (:func:`gyro_swing_cadence`) takes the correlation as the window's periodicity."""
    rms = np.asarray(rms, dtype=float)
    period, corr, half = swing_stride(proj, fs, min_step_hz=min_step_hz, max_step_hz=max_step_hz)
    ok = (rms >= min_rms_rads) & np.isfinite(period)
    ok &= np.nan_to_num(corr, nan=-1.0) >= min_correlation
    ok &= np.nan_to_num(half, nan=1.0) <= -half_correlation
    step = period / 2.0
    with np.errstate(invalid="ignore"):
        ok &= (step >= fs / max_step_hz) & (step <= fs / min_step_hz)
    return ok, period, corr


def rhythm_windows(
    cadence: dict[str, np.ndarray],
    projection: tuple[np.ndarray, np.ndarray],
    sampling_rate_hz: float,
    *,
    min_step_hz: float = MIN_STEP_HZ,
    max_step_hz: float = MAX_STEP_HZ,
    min_rms_rads: float = GYRO_MIN_RMS_RADS,
    min_periodicity: float = MIN_PERIODICITY,
    step_tolerance: float = RHYTHM_STEP_TOLERANCE,
) -> np.ndarray:
    """The cadence windows where the periodicity floor's relief may keep a peak (:data:`RHYTHM_MIN_PERIODICITY`).

    A window qualifies when its |acc| periodicity is below ``min_periodicity`` (the floor removes its peaks), the
    phone turns there with a stride rhythm (:func:`swing_rhythm` on the window's swing ``projection``, with |acc|'s
    floor ``min_periodicity`` as the swing's correlation floor, as :func:`gaitml.models.stride_rhythm`) and the
    swing's step, half its stride period, lies within ``step_tolerance`` of the window's step period. ``cadence``:
    :func:`local_cadence`'s windows (``period_s``, ``periodicity``) at ``sampling_rate_hz``, the rate of
    ``projection``.
    """
    fs = float(sampling_rate_hz)
    T = np.asarray(cadence["period_s"], dtype=float) * fs
    weak = np.asarray(cadence["periodicity"], dtype=float) < min_periodicity
    out = np.zeros(len(T), dtype=bool)
    idx = np.flatnonzero(weak)
    if len(idx) == 0:
        return out
    proj, rms = projection
    ok, P = swing_rhythm(
        proj[idx],
        rms[idx],
        fs,
        min_step_hz=min_step_hz,
        max_step_hz=max_step_hz,
        min_rms_rads=min_rms_rads,
        min_correlation=min_periodicity,
    )
    with np.errstate(invalid="ignore"):
        ok &= np.abs(P / 2.0 - T[idx]) <= step_tolerance * T[idx]
    out[idx] = ok
    return out


def gyro_swing_cadence(
    cadence: dict[str, np.ndarray],
    projection: tuple[np.ndarray, np.ndarray],
    sampling_rate_hz: float,
    acc_windows: np.ndarray | None = None,
    *,
    min_step_hz: float = MIN_STEP_HZ,
    max_step_hz: float = MAX_STEP_HZ,
    min_rms_rads: float = GYRO_MIN_RMS_RADS,
    swing_min_periodicity: float = GYRO_SWING_MIN_PERIODICITY,
    swing_half_correlation: float = GYRO_SWING_HALF_CORRELATION,
    acc_step_correlation: float = GYRO_SWING_ACC_CORRELATION,
    min_periodicity: float = MIN_PERIODICITY,
) -> dict[str, np.ndarray]:
    """The phone's swing as the periodicity evidence where |acc|'s is weak (module docstring, stage 2c).

    A slow walker's trunk barely bounces: the vertical excursion of the
    centre of mass shrinks with the speed (Orendurff et al., J. Rehabil. Res.
    Dev. 41, 2004), so |acc|'s periodicity can fall below ``min_periodicity``
    and stage 4 finds no step, while the body that carries the phone still
    rotates once per stride and reverses between the left and the right step
    (arm and thigh swing, pelvis and trunk rotation; Perry & Burnfield, Gait
    Analysis, 2nd ed. 2010, ch. 10; Meyns, Bruijn & Duysens, Gait Posture 38,
    2013). Where |acc|'s periodicity is below ``min_periodicity`` and the
    swing (:func:`swing_projection`, RMS at least ``min_rms_rads``) is
    *regular*: its stride period ``P`` (:func:`swing_stride`) correlates at
    least ``swing_min_periodicity`` and the swing is in anti-phase at ``P /
    2`` (correlation at most ``-swing_half_correlation``), the window's step
    period becomes ``P / 2`` and its periodicity the swing's correlation at
    ``P``. Steps are still the peaks of the folded |acc| above the noise floor
    (stages 3-4) and pass the bout rules (stage 5).

    ``acc_windows`` (the band-passed |acc| of the same cadence windows,
    ``(n_windows, length)``), if given, adds one test: |acc|'s own
    autocorrelation at ``P / 2`` must reach ``acc_step_correlation`` (the
    steps still repeat in |acc|, however weakly).

    ``swing_min_periodicity`` 0 disables the rule. Returns a copy of
    ``cadence`` with ``period_s``, ``periodicity``, ``stride`` (True where
    the swing set the window: its period was a stride) and ``inferred``
    updated and ``swing`` added (True where the swing set the window).
    """
    fs = float(sampling_rate_hz)
    out = dict(cadence)
    T = np.asarray(cadence["period_s"], dtype=float) * fs
    n_win = len(T)
    periodicity = np.asarray(cadence["periodicity"], dtype=float)
    weak = np.zeros(n_win, dtype=bool)
    if swing_min_periodicity > 0 and n_win:
        proj, rms = projection
        weak = (periodicity < min_periodicity) & (rms[:n_win] >= min_rms_rads)
        if weak.any():
            idx = np.flatnonzero(weak)
            ok, P, corr = _rhythm_test(
                proj[idx],
                rms[idx],
                fs,
                min_step_hz=min_step_hz,
                max_step_hz=max_step_hz,
                min_rms_rads=min_rms_rads,
                min_correlation=swing_min_periodicity,
                half_correlation=swing_half_correlation,
            )
            if acc_windows is not None:
                w = acc_windows[idx] - acc_windows[idx].mean(axis=1, keepdims=True)
                acc_step = np.nan_to_num(projection_correlation(w, np.where(np.isfinite(P), P / 2.0, 2.0)[:, None])[:, 0], nan=-1.0)
                ok &= acc_step >= acc_step_correlation
            weak[idx[~ok]] = False
            T = T.copy()
            T[idx[ok]] = P[ok] / 2.0
            periodicity = periodicity.copy()
            periodicity[idx[ok]] = corr[ok]
    out["period_s"] = T / fs
    out["periodicity"] = periodicity
    out["stride"] = np.asarray(cadence["stride"], dtype=bool) | weak
    out["inferred"] = np.asarray(cadence["inferred"], dtype=bool) & ~weak
    out["swing"] = weak
    return out


def fold_steps(y: np.ndarray, period_samples: np.ndarray) -> np.ndarray:
    """The left/right fold ``(y(t - T) + 2 y(t) + y(t + T)) / 4`` with a per-sample step period ``T`` (samples).

    Zero-phase; cancels every component periodic in ``2 T`` with odd harmonics
    (a one-leg stride) and keeps those periodic in ``T`` (steps). At the edges
    the missing neighbour is replaced by the other one.
    """
    y = np.asarray(y, dtype=float)
    n = len(y)
    i = np.arange(n)
    k = np.maximum(np.rint(np.asarray(period_samples, dtype=float)).astype(np.int64), 1)
    a = i - k
    b = i + k
    a = np.where(a < 0, np.minimum(b, n - 1), a)
    b = np.where(b >= n, np.maximum(a, 0), b)
    return (y[a] + 2.0 * y + y[b]) / 4.0


def bout_edge_keep(
    bout: np.ndarray,
    confidence: np.ndarray,
    ratio: float,
    peaks: np.ndarray | None = None,
    interval_tolerance: float = 0.0,
    min_match_steps: int = 0,
) -> np.ndarray:
    """Keep mask that trims the weak steps at both ends of every walking bout (module docstring, stage 5).

    Parameters
    ----------
    bout : int array (n,)
        Bout number of each step, non-decreasing (steps in time order).
    confidence : float array (n,)
        Step confidence in [0, 1].
    ratio : float
        Leading and trailing steps of a bout whose confidence is below
        ``ratio`` times the bout's median confidence are dropped, up to the
        first (last) step that reaches it; the steps inside a bout are kept
        whatever their confidence.
    peaks : int array (n,), optional
        Step samples; with ``interval_tolerance`` > 0 a weak step one of whose
        intervals to its neighbours in the bout lies within
        ``interval_tolerance`` of the bout's median interval counts as
        strong (stage 5b: an edge step at the walk's own rhythm is a step).
    interval_tolerance : float, default 0
        0: the confidence alone decides (stage 5).
    min_match_steps : int, default 0
        The interval match applies only in bouts of at least this many steps.

    Returns
    -------
    bool array (n,)
    """
    bout = np.asarray(bout)
    conf = np.asarray(confidence, dtype=float)
    n = len(conf)
    if n == 0:
        return np.zeros(0, dtype=bool)
    starts = np.flatnonzero(np.r_[True, bout[1:] != bout[:-1]])
    size = np.diff(np.r_[starts, n])
    member = np.repeat(np.arange(len(starts)), size)  # 0 .. n_bouts - 1 per step
    # the median of each bout: its confidences sorted within the bout (the bouts stay in their blocks)
    srt = conf[np.lexsort((conf, member))]
    median = (srt[starts + (size - 1) // 2] + srt[starts + size // 2]) / 2.0
    idx = np.arange(n)
    strong = conf >= ratio * median[member]
    if peaks is not None and interval_tolerance > 0 and n > 1:
        d = np.diff(np.asarray(peaks, dtype=float))
        same = bout[1:] == bout[:-1]
        # each bout's median interval (intervals inside it only)
        med = np.full(len(starts), np.nan)
        for b in np.unique(member[1:][same]):
            med[b] = np.median(d[same & (member[1:] == b)])
        mb = med[member[1:]]
        good = same & (np.abs(d - mb) <= interval_tolerance * mb) & (size[member[1:]] >= min_match_steps)
        strong |= np.r_[good, False] | np.r_[False, good]
    # strong is never empty in a bout: at least half of it reaches its median, and ratio <= 1
    first = np.minimum.reduceat(np.where(strong, idx, n), starts)
    last = np.maximum.reduceat(np.where(strong, idx, -1), starts)
    return (idx >= first[member]) & (idx <= last[member])


def _bout_numbers(pk: np.ndarray, period: np.ndarray) -> np.ndarray:
    """Walking-bout number of every peak (non-decreasing from 0): a gap over :data:`BOUT_GAP_RATIO` local step
    periods (the larger of its two peaks' ``period``, samples) ends one bout and starts the next."""
    if len(pk) == 0:
        return np.zeros(0, dtype=np.int64)
    gap = np.diff(pk).astype(float) > BOUT_GAP_RATIO * np.maximum(period[:-1], period[1:])
    return np.concatenate([[0], np.cumsum(gap)]).astype(np.int64)


def slow_step_noise_floor(period_s: np.ndarray, min_rms_ms2: float, min_rms_slow_ms2: float, slow_step_hz: float) -> np.ndarray:
    """Stage 4's noise floor (m/s^2) at local step periods ``period_s`` (s): ``min_rms_ms2`` at steps of
    ``slow_step_hz`` or faster; slower, ``min_rms_ms2 x (f / slow_step_hz)^2`` (the same vertical excursion gives
    ``(2 pi f)^2`` times less acceleration), not below ``min_rms_slow_ms2``. With ``min_rms_slow_ms2 >= min_rms_ms2``
    it is ``min_rms_ms2`` everywhere."""
    T = np.asarray(period_s, dtype=float)
    if min_rms_slow_ms2 >= min_rms_ms2:
        return np.full(T.shape, float(min_rms_ms2))
    scale = np.minimum(1.0, 1.0 / np.maximum(slow_step_hz * T, 1e-12) ** 2)
    return np.maximum(float(min_rms_slow_ms2), float(min_rms_ms2) * scale)


def _step_noise_floor(cs: np.ndarray, pk: np.ndarray, k, n: int) -> np.ndarray:
    """The noise floor of stage 4 at each peak: the RMS of the band-passed signal over ``k`` samples (one step
    period, a scalar or one per peak) before the peak and over ``k`` after it, the smaller of the two. ``cs`` is the
    cumulative sum of the squared signal with a leading 0, ``n`` the signal's length."""
    a, b = np.maximum(pk - k, 0), np.minimum(pk + k + 1, n)
    before = np.sqrt((cs[pk + 1] - cs[a]) / np.maximum(pk + 1 - a, 1))
    after = np.sqrt((cs[b] - cs[pk]) / np.maximum(b - pk, 1))
    return np.minimum(before, after)


def bout_octave(
    pk: np.ndarray,
    bout: np.ndarray,
    g: np.ndarray,
    q: int,
    sampling_rate_hz: float,
    min_length: int,
    *,
    min_step_hz: float = MIN_STEP_HZ,
    max_step_hz: float = MAX_STEP_HZ,
    min_rms_rads: float = GYRO_MIN_RMS_RADS,
    swing_min_correlation: float = OCTAVE_SWING_MIN_CORRELATION,
    swing_half_correlation: float = OCTAVE_SWING_HALF_CORRELATION,
    tolerance: float = OCTAVE_MATCH_TOLERANCE,
) -> tuple[np.ndarray, np.ndarray]:
    """The octave of every walking bout from its swing pooled over the bout (module docstring, stage 5a).

    Every rotation of the body that carries the phone completes one cycle per
    stride and reverses between the left and the right step (arm swing:
    Meyns, Bruijn & Duysens, Gait Posture 38, 2013; thigh, pelvis and trunk:
    Perry & Burnfield, Gait Analysis, 2nd ed. 2010, ch. 10), whatever |acc|
    shows. A slow step's |acc| has two peaks (heel strike and push-off: the
    double hump of the vertical ground reaction force, Perry & Burnfield ch.
    4), which the 5 s cadence windows may take for two steps in some windows
    and not in others. Over the whole bout instead of a window: the band-passed
    angular rate ``g`` (decimated by ``q``, at ``sampling_rate_hz / q``) from one
    step interval before the bout's first peak to one after its last (at
    least ``min_length`` decimated samples, centred on the bout) is projected
    on its principal axis (:func:`swing_projection`); where its RMS reaches
    ``min_rms_rads``, its stride period ``P`` (:func:`swing_stride`)
    correlates at least ``swing_min_correlation`` and it is in anti-phase at
    ``P / 2`` (at most ``-swing_half_correlation``), the bout's median peak
    interval ``d`` is compared with the swing's step ``P / 2`` at two octaves:
    ``2 d`` (each step holds two peaks: half-steps) and ``d`` (steps). The
    octave within ``tolerance`` of ``P / 2`` (the nearer, on a log scale) is
    the bout's. One peak per stride (``d / 2`` near the step) is not
    decided here: it is stage 2b's case (the swing in phase at the window's
    period), and a phone that turns once per |acc| peak is also what a
    gesturing hand looks like (the gait check's case).

    Parameters
    ----------
    pk : int array (n,)
        Peak samples (at ``sampling_rate_hz``), in time order.
    bout : int array (n,)
        Bout number of each peak, non-decreasing.

    Returns
    -------
    octave : int array (n_bouts,)
        Per bout: 2 (half-steps: two peaks per step), 1 (steps) or 0
        (undecided: no regular swing, a bout of fewer than three peaks, or no
        octave within ``tolerance``).
    step : float array (n_bouts,)
        The swing's step (half its stride period) in samples at
        ``sampling_rate_hz``; NaN where undecided.
    """
    fs = float(sampling_rate_hz)
    fd = fs / q
    n_bouts = int(bout[-1]) + 1 if len(bout) else 0
    out = np.zeros(n_bouts, dtype=np.int64)
    steps = np.full(n_bouts, np.nan)
    if swing_min_correlation <= 0 or n_bouts == 0:
        return out, steps
    starts = np.flatnonzero(np.r_[True, bout[1:] != bout[:-1]])
    ends = np.r_[starts[1:], len(bout)]
    for b, (i0, i1) in enumerate(zip(starts, ends, strict=True)):
        if i1 - i0 < 3:
            continue
        d = float(np.median(np.diff(pk[i0:i1])))
        a, e = (pk[i0] - d) / q, (pk[i1 - 1] + d) / q
        if e - a < min_length:  # at least one cadence window, centred on the bout
            mid = (a + e) / 2.0
            a, e = mid - min_length / 2.0, mid + min_length / 2.0
        a, e = int(max(0, np.floor(a))), int(min(len(g), np.ceil(e)))
        if e - a < 3:
            continue
        proj, rms = swing_projection(g[a:e], e - a, 1, 1)
        if rms[0] < min_rms_rads:
            continue
        P, corr, half = swing_stride(proj, fd, min_step_hz=min_step_hz, max_step_hz=max_step_hz)
        if not (np.isfinite(P[0]) and corr[0] >= swing_min_correlation and np.nan_to_num(half[0], nan=1.0) <= -swing_half_correlation):
            continue
        step = P[0] / 2.0 * q  # the swing's step, in samples at fs
        miss = {k: abs(np.log(d * k / step)) for k in (2, 1)}
        k = min(miss, key=miss.get)
        if miss[k] <= np.log(1.0 + tolerance):
            out[b], steps[b] = k, step
    return out, steps


def octave_counts(octave) -> dict[str, int]:
    """Stage 5a's decisions counted (``steps_.attrs['octave']``): bouts read as half-steps (2), as
    steps (1) and undecided (0), from per-bout octaves as :func:`bout_octave` returns them."""
    o = np.asarray(octave).reshape(-1)
    return {"half_steps": int(np.sum(o == 2)), "steps": int(np.sum(o == 1)), "undecided": int(np.sum(o == 0))}


def _bout_interval_cv(pk: np.ndarray, bout: np.ndarray, ok: np.ndarray, nb: int) -> np.ndarray:
    """Per bout, the coefficient of variation of the intervals between its consecutive kept steps (``inf`` with fewer
    than two intervals)."""
    same = (bout[1:] == bout[:-1]) & ok[1:] & ok[:-1]
    di = np.diff(pk).astype(float)[same]
    bi = bout[1:][same]
    c1 = np.bincount(bi, minlength=nb)
    mu = np.bincount(bi, weights=di, minlength=nb) / np.maximum(c1, 1)
    sd = np.sqrt(np.maximum(np.bincount(bi, weights=di**2, minlength=nb) / np.maximum(c1, 1) - mu**2, 0.0))
    return np.where(c1 >= 2, sd / np.where(mu > 0, mu, np.inf), np.inf)


def _episodes(pk: np.ndarray, T: np.ndarray, bout: np.ndarray, ok: np.ndarray, nb: int, gap_ratio: float) -> np.ndarray:
    """Stage 5b: per bout, its walking episode's number (-1 for a bout without kept steps, ``ok``): consecutive bouts
    whose separating interval (last kept step of one to first kept step of the next) is at most ``gap_ratio`` times the
    larger local step period ``T`` of those two steps share an episode."""
    out = np.full(nb, -1, dtype=np.int64)
    idx = np.flatnonzero(ok)
    if len(idx) == 0:
        return out
    b = bout[idx]
    first = np.flatnonzero(np.r_[True, b[1:] != b[:-1]])
    last = np.r_[first[1:] - 1, len(idx) - 1]
    gaps = pk[idx[first[1:]]] - pk[idx[last[:-1]]]
    lim = gap_ratio * np.maximum(T[idx[first[1:]]], T[idx[last[:-1]]])
    out[b[first]] = np.r_[0, np.cumsum(gaps > lim)]
    return out


def _episode_keep(
    pk: np.ndarray,
    T: np.ndarray,
    bout: np.ndarray,
    ok: np.ndarray,
    alone: np.ndarray,
    walking: np.ndarray,
    nb: int,
    gap_ratio: float,
    max_cv: float,
) -> np.ndarray:
    """Stage 5b (module docstring): per bout, whether it is kept as part of a walking episode although the
    minimum-bout or short-bout rule drops it.

    Bouts with kept steps (``ok``) whose separating interval (last kept step of one to first kept step of the next) is
    at most ``gap_ratio`` times the larger local step period ``T`` of those two steps form one episode. A bout that does
    not pass alone (``alone``) is kept when its episode holds a walking bout (``walking``: passes alone with enough
    steps) and its own intervals are regular: coefficient of
    variation at most ``max_cv``, or, with a single interval, that interval within ``max_cv`` of the local step period.
    A bout with one kept step has no interval and is never kept this way.
    """
    idx = np.flatnonzero(ok)
    keep = np.zeros(nb, dtype=bool)
    if len(idx) < 2:
        return keep
    b = bout[idx]
    # each bout's kept steps: first and last (bouts without kept steps do not join episodes)
    first = np.flatnonzero(np.r_[True, b[1:] != b[:-1]])
    last = np.r_[first[1:] - 1, len(idx) - 1]
    ids = b[first]
    episode = _episodes(pk, T, bout, ok, nb, gap_ratio)[ids]
    has_walk = np.bincount(episode, weights=walking[ids].astype(float)) > 0
    icv = _bout_interval_cv(pk, bout, ok, nb)[ids]
    single = (last - first) == 1
    d1 = (pk[idx[np.minimum(first + 1, len(idx) - 1)]] - pk[idx[first]]).astype(float)
    t1 = T[idx[first]]
    regular = np.where(single, np.abs(d1 - t1) <= max_cv * t1, icv <= max_cv)
    keep[ids] = has_walk[episode] & regular & ~alone[ids]
    return keep


def episode_steps_after_check(today: dict, added: dict, survived_peaks: np.ndarray) -> np.ndarray:
    """Round 3 of stage 5b (module docstring): which of the steps stage 5b added join the step table after the gait check.

    ``today`` and ``added`` are :func:`adaptive_steps`' ``'today'`` and ``'stage5b'`` accounts (``peak``, ``bout``,
    ``episode``, ``walking`` per step) and ``survived_peaks`` the peaks of today's steps that the gait check kept. A
    rescued bout's step (its bout is not walking) joins when a step of a walking bout of its episode survived; an edge
    step that the interval match kept (in a walking bout) joins when a step of its own bout survived. So a rescued bout
    never outlives the walking that justified it (experiments/reports/tyrex-steps.md, bouts section: seed 112).
    Returns a bool mask over ``added``.
    """
    survived = np.isin(today["peak"], survived_peaks)
    walk_ep = np.unique(today["episode"][survived & today["walking"]])
    live_bout = np.unique(today["bout"][survived])
    return np.where(added["walking"], np.isin(added["bout"], live_bout), np.isin(added["episode"], walk_ep))


def adaptive_steps(
    acc_mag_ms2: np.ndarray,
    sampling_rate_hz: float,
    *,
    band_hz: tuple[float, float] = BAND_HZ,
    window_s: float = WINDOW_S,
    hop_s: float = HOP_S,
    min_step_hz: float = MIN_STEP_HZ,
    max_step_hz: float = MAX_STEP_HZ,
    half_lag_min_correlation: float = HALF_LAG_MIN_CORRELATION,
    slow_step_hz: float = SLOW_STEP_HZ,
    slow_step_max_rms_ms2: float = SLOW_STEP_MAX_RMS_MS2,
    slow_step_max_half_correlation: float = SLOW_STEP_MAX_HALF_CORRELATION,
    min_periodicity: float = MIN_PERIODICITY,
    min_rms_ms2: float = MIN_RMS_MS2,
    min_rms_slow_ms2: float = MIN_RMS_SLOW_MS2,
    rhythm_min_periodicity: float = RHYTHM_MIN_PERIODICITY,
    rhythm_step_tolerance: float = RHYTHM_STEP_TOLERANCE,
    min_distance_ratio: float = MIN_DISTANCE_RATIO,
    fold: bool = True,
    edge_confidence_ratio: float = EDGE_CONFIDENCE_RATIO,
    min_bout_steps: int = MIN_BOUT_STEPS,
    short_bout_steps: int = SHORT_BOUT_STEPS,
    max_short_bout_cv: float = MAX_SHORT_BOUT_CV,
    min_confidence: float = 0.0,
    gyr_rads: np.ndarray | None = None,
    gyro_min_rms_rads: float = GYRO_MIN_RMS_RADS,
    gyro_phase_correlation: float = GYRO_PHASE_CORRELATION,
    gyro_swing_half_correlation: float = GYRO_SWING_HALF_CORRELATION,
    gyro_swing_min_periodicity: float = GYRO_SWING_MIN_PERIODICITY,
    gyro_swing_acc_correlation: float = GYRO_SWING_ACC_CORRELATION,
    gyro_swing_min_bout_steps: int = GYRO_SWING_MIN_BOUT_STEPS,
    octave_swing_min_correlation: float = OCTAVE_SWING_MIN_CORRELATION,
    octave_swing_half_correlation: float = OCTAVE_SWING_HALF_CORRELATION,
    octave_match_tolerance: float = OCTAVE_MATCH_TOLERANCE,
    max_short_bout_interval_cv: float = MAX_SHORT_BOUT_INTERVAL_CV,
    episode_gap_ratio: float = 0.0,
    max_bout_interval_cv: float = MAX_BOUT_INTERVAL_CV,
    edge_interval_match: bool = EDGE_INTERVAL_MATCH,
    episode_walk_steps: int = EPISODE_WALK_STEPS,
) -> dict[str, np.ndarray]:
    """Detect steps in |acc| (m/s^2) with the five stages of the module docstring.

    ``gyr_rads`` (n, 3), the angular rate on the same samples, turns on the
    gyroscope's stride-versus-step check (stage 2b, :func:`gyro_stride_or_step`)
    and, with ``gyro_swing_min_periodicity`` > 0, the swing where |acc| is weak
    (stage 2c, :func:`gyro_swing_cadence`; the ``gyro_swing_*`` settings as
    :class:`AdaptiveStepDetector`).

    Returns
    -------
    dict
        ``peak`` (step samples), ``y`` (band-passed magnitude), ``s`` (folded
        signal), and at each peak: ``period_s`` (local step period),
        ``correlation`` (periodicity), ``confidence``; plus ``cadence``, the
        per-window dict of :func:`local_cadence`; ``octave``, stage 5a's decisions counted
        (:func:`octave_counts`), and ``octave_bouts``, per bout it decided on: ``first_peak``
        (sample) and ``octave`` (:func:`bout_octave`; empty where the stage is off).
        ``today`` and ``stage5b``: the steps of the rules without stage 5b
        and the steps stage 5b adds, each a dict of ``peak``, ``period_s``,
        ``correlation``, ``confidence``, ``bout``, ``episode`` and ``walking``
        (the detector runs the gait check on ``today`` and adds the ``stage5b``
        steps after it, :func:`episode_steps_after_check`).

    Stage 5b is off here by default (``episode_gap_ratio=0.0``): this
    function has no gait check, and the detector turns the stage on
    (:data:`EPISODE_GAP_RATIO`) only where the gait check reads a gyroscope.
    With ``episode_gap_ratio`` > 0, ``peak`` holds the steps of rounds 1-2
    (stage 5b before any gait check).
    """
    x = np.asarray(acc_mag_ms2, dtype=float)
    fs = float(sampling_rate_hz)
    n = len(x)
    y = bandpass(x - np.median(x), band_hz[0], band_hz[1], fs, order=2)
    # the cadence estimate runs on the band-limited signal decimated to about CADENCE_RATE_HZ
    q = cadence_decimation(fs)
    still = None
    if gyr_rads is not None:
        g = np.asarray(gyr_rads, dtype=float)
        g = bandpass(g - g.mean(axis=0), GYRO_BAND_HZ[0], min(GYRO_BAND_HZ[1], 0.45 * fs), fs, order=2)[::q]
        L = min(len(g), int(round(window_s * fs / q)))
        H = max(1, int(round(hop_s * fs / q)))
        n_win = (len(g) - L) // H + 1
        # the phone's swing per cadence window: below gyro_min_rms_rads it rides no swinging thigh or arm
        swing = swing_projection(g, L, H, n_win)
        still = swing[1] < gyro_min_rms_rads
    cad = local_cadence(
        y[::q],
        fs / q,
        window_s=window_s,
        hop_s=hop_s,
        min_step_hz=min_step_hz,
        max_step_hz=max_step_hz,
        half_lag_min_correlation=half_lag_min_correlation,
        slow_step_hz=slow_step_hz,
        slow_step_max_rms_ms2=slow_step_max_rms_ms2,
        slow_step_max_half_correlation=slow_step_max_half_correlation,
        still=still,
    )
    if gyr_rads is not None:
        cad = gyro_stride_or_step(
            cad,
            g,
            fs / q,
            L,
            H,
            min_step_hz=min_step_hz,
            max_step_hz=max_step_hz,
            min_rms_rads=gyro_min_rms_rads,
            phase_correlation=gyro_phase_correlation,
            projection=swing,
        )
        if gyro_swing_min_periodicity > 0:
            cad = gyro_swing_cadence(
                cad,
                swing,
                fs / q,
                sliding_windows(y[::q], L, H)[: len(cad["period_s"])],
                min_step_hz=min_step_hz,
                max_step_hz=max_step_hz,
                min_rms_rads=gyro_min_rms_rads,
                swing_min_periodicity=gyro_swing_min_periodicity,
                swing_half_correlation=gyro_swing_half_correlation,
                acc_step_correlation=gyro_swing_acc_correlation,
                min_periodicity=min_periodicity,
            )
    centres = cad["centre"] * q
    cad["centre"] = centres
    period_n = np.interp(np.arange(n), centres, cad["period_s"]) * fs
    s = fold_steps(y, period_n) if fold else y
    pk = scipy.signal.find_peaks(s)[0]
    T = period_n[pk]
    w = np.rint(min_distance_ratio * T).astype(np.int64)
    dominant = segment_argmax(s, np.maximum(pk - w, 0), np.minimum(pk + w + 1, n)) == pk
    R = np.interp(pk, centres, cad["periodicity"])
    inferred = np.interp(pk, centres, cad["inferred"].astype(float)) > 0.5
    by_swing = np.interp(pk, centres, cad["swing"].astype(float)) > 0.5 if "swing" in cad else np.zeros(len(pk), dtype=bool)
    # noise floor: RMS of y over one step period before the step and over one after it, the smaller of the two
    # (motion on both sides: the fold spreads a step by one period, and a one-sided test keeps the last step of a
    # walk from lending its energy to a phantom step one period later)
    cs = np.concatenate([[0.0], np.cumsum(y * y)])
    rms = _step_noise_floor(cs, pk, np.maximum(np.rint(T).astype(np.int64), 1), n)
    floor_ms2 = slow_step_noise_floor(T / fs, min_rms_ms2, min_rms_slow_ms2, slow_step_hz)
    periodic = R >= min_periodicity
    relieved = np.zeros(len(pk), dtype=bool)
    weak = np.zeros(len(pk), dtype=bool)
    if gyr_rads is not None and 0 < rhythm_min_periodicity < min_periodicity and len(pk):
        # the periodicity floor's relief: a weakly periodic peak where the phone turns with a stride rhythm whose step
        # matches the window's (rhythm_windows); the swing sets neither the period nor the periodicity
        nw = len(cad["period_s"])
        rhythm = rhythm_windows(
            cad,
            (swing[0][:nw], swing[1][:nw]),
            fs / q,
            min_step_hz=min_step_hz,
            max_step_hz=max_step_hz,
            min_rms_rads=gyro_min_rms_rads,
            min_periodicity=min_periodicity,
            step_tolerance=rhythm_step_tolerance,
        )
        weak = ~periodic & (R >= rhythm_min_periodicity)
        relieved = weak & (np.interp(pk, centres, rhythm.astype(float)) > 0.5)
    keep = dominant & (s[pk] > 0) & (periodic | relieved) & (rms >= floor_ms2)
    # the relief's account: the peaks only the periodicity floor removed above rhythm_min_periodicity, and those it kept
    candidate = dominant & (s[pk] > 0) & weak & (rms >= floor_ms2)
    n_weak, n_relieved = int(candidate.sum()), int((candidate & relieved).sum())
    rhythm_peaks = {"peak": pk[candidate], "relieved": relieved[candidate]}
    pk, T, R, inferred, by_swing = pk[keep], T[keep], R[keep], inferred[keep], by_swing[keep]
    amp = s[pk]
    # stage 5a: one octave per walking bout, from the swing pooled over the bout (bout_octave)
    decided = np.zeros(len(pk), dtype=bool)
    octave = octave_counts([])
    octave_bouts = {"first_peak": np.zeros(0, dtype=np.int64), "octave": np.zeros(0, dtype=np.int64)}
    if gyr_rads is not None and octave_swing_min_correlation > 0 and len(pk) >= 3:
        bout0 = _bout_numbers(pk, T)
        octv, swing_step = bout_octave(
            pk,
            bout0,
            g,
            q,
            fs,
            L,
            min_step_hz=min_step_hz,
            max_step_hz=max_step_hz,
            min_rms_rads=gyro_min_rms_rads,
            swing_min_correlation=octave_swing_min_correlation,
            swing_half_correlation=octave_swing_half_correlation,
            tolerance=octave_match_tolerance,
        )
        octave = octave_counts(octv)
        # each bout's decision at its first peak (a chunked run counts the bouts that start in a chunk's core)
        octave_bouts = {"first_peak": pk[np.flatnonzero(np.r_[True, bout0[1:] != bout0[:-1]])].astype(np.int64), "octave": octv}
        decided = octv[bout0] == 2
        redo = np.flatnonzero(octv == 2)
        if len(redo):
            # two peaks per step (heel strike, push-off): the bout's steps are picked again at twice its median peak
            # interval (stages 3-4 on the bout with that period fixed), replacing the peaks found at half a step
            out = ~np.isin(bout0, redo)
            parts = [(pk[out], T[out], R[out], inferred[out], by_swing[out], decided[out], amp[out])]
            for b in redo:
                idx = np.flatnonzero(bout0 == b)
                # the swing decides the octave; the bout's own peaks give the period at that octave (two peak intervals)
                st = 2.0 * float(np.median(np.diff(pk[idx])))
                a, e = max(0, int(pk[idx[0]] - st / 2)), min(n, int(pk[idx[-1]] + st / 2) + 1)
                sb = fold_steps(y[a:e], np.full(e - a, st))
                # the highest peaks at least min_distance_ratio steps apart (the lower of two closer peaks is dropped
                # first, so a push-off peak that loses to its heel strike cannot in turn suppress the next step)
                c = scipy.signal.find_peaks(sb, distance=max(1, int(round(min_distance_ratio * st))))[0]
                c = c[sb[c] > 0]
                pc = a + c
                floor = _step_noise_floor(cs, pc, max(1, int(round(st))), n)
                c, pc = c[floor >= min_rms_ms2], pc[floor >= min_rms_ms2]
                near = idx[np.clip(np.searchsorted(pk[idx], pc), 0, len(idx) - 1)]
                parts.append(
                    (pc, np.full(len(pc), st), R[near], np.zeros(len(pc), dtype=bool), by_swing[near], np.ones(len(pc), dtype=bool), sb[c])
                )
            pk, T, R, inferred, by_swing, decided, amp = (np.concatenate(v) for v in zip(*parts, strict=True))
            order = np.argsort(pk, kind="stable")
            pk, T, R, inferred, by_swing, decided, amp = (v[order] for v in (pk, T, R, inferred, by_swing, decided, amp))
    conf = np.clip(R, 0.0, 1.0)
    bout = np.zeros(len(pk), dtype=np.int64)
    if len(pk):  # one step alone gets no interval, hence regularity 0, like a lone step inside a longer signal
        d = np.diff(pk).astype(float)
        # a gap over BOUT_GAP_RATIO local step periods is not a step interval (its timing regularity would be 0):
        # it ends one walking bout and starts the next, and a step's regularity uses its intervals inside its bout
        bout = _bout_numbers(pk, T)
        gap = bout[1:] != bout[:-1]
        prev = np.concatenate([[np.nan], np.where(gap, np.nan, d)])
        nxt = np.concatenate([np.where(gap, np.nan, d), [np.nan]])
        interval = np.where(np.isnan(prev), nxt, np.where(np.isnan(nxt), prev, (prev + nxt) / 2.0))
        # a step alone in its bout has no interval: no timing evidence
        regularity = np.where(np.isnan(interval), 0.0, np.clip(1.0 - np.abs(interval - T) / T, 0.0, 1.0))
        conf = conf * regularity
    conf = np.where(inferred, INFERRED_STRIDE_FACTOR * conf, conf)
    # stage 5b's account (round 3, applied after the gait check by the detector): today's steps and the steps stage 5b
    # adds, each with its bout, its episode and whether its bout is walking (passes alone with episode_walk_steps steps)
    mark = {k: np.zeros(len(pk), dtype=bool) for k in ("today", "stage5b", "walking")}
    episode_of, conf_today = np.full(len(pk), -1, dtype=np.int64), conf

    def sure(c: np.ndarray) -> np.ndarray:
        return c >= min_confidence if min_confidence > 0 else np.ones(len(c), dtype=bool)

    if len(pk):
        nb = int(bout[-1]) + 1
        on5b = episode_gap_ratio > 0 and max_bout_interval_cv > 0

        def bouts_alone(ok: np.ndarray) -> np.ndarray:
            # a bout counts once it is confirmed by min_bout_steps steps (after its weak edges are dropped)
            size = np.bincount(bout[ok], minlength=nb)
            alone = size >= min_bout_steps
            if gyro_swing_min_bout_steps > min_bout_steps and by_swing.any():
                swung = np.bincount(bout[ok & by_swing], minlength=nb) > 0
                alone &= ~(swung & (size < gyro_swing_min_bout_steps))
            # a short bout must repeat its steps' strength (gait); a burst that waxes and wanes (a gesture) does not
            if short_bout_steps > 0:
                live = ok & alone[bout]
                cnt = np.bincount(bout[live], minlength=nb)
                mean = np.bincount(bout[live], weights=amp[live], minlength=nb) / np.maximum(cnt, 1)
                var = np.bincount(bout[live], weights=amp[live] ** 2, minlength=nb) / np.maximum(cnt, 1) - mean**2
                cv = np.sqrt(np.maximum(var, 0.0)) / np.where(mean > 0, mean, np.inf)
                short = cnt < short_bout_steps
                exempt = np.zeros(nb, dtype=bool)
                if max_short_bout_interval_cv > 0 and decided.any():
                    # stage 5a: a bout whose octave the swing decided passes when its steps are regular at that octave
                    icv = _bout_interval_cv(pk, bout, live, nb)
                    exempt = (np.bincount(bout[live & decided], minlength=nb) > 0) & (icv <= max_short_bout_interval_cv)
                alone &= ~(short & (cv > max_short_bout_cv) & ~exempt)
            return alone

        def confirmed(ok: np.ndarray) -> np.ndarray:
            # the fewer steps confirm a bout, the less sure it is gait
            if short_bout_steps <= 0:
                return conf
            return conf * np.minimum(1.0, np.bincount(bout[ok], minlength=nb)[bout] / short_bout_steps)

        edge = (
            (lambda tol: bout_edge_keep(bout, conf, edge_confidence_ratio, pk, tol, episode_walk_steps))
            if edge_confidence_ratio > 0
            else None
        )
        ok0 = edge(0.0) if edge is not None else np.ones(len(pk), dtype=bool)
        today = ok0 & bouts_alone(ok0)[bout]
        ok = today
        if on5b:
            ok = edge(max_bout_interval_cv) if (edge is not None and edge_interval_match) else ok0
            alone = bouts_alone(ok)
            # stage 5b: a regular bout beside walking (one episode with a bout that passes alone) is walking too
            walking = alone & (np.bincount(bout[ok], minlength=nb) >= episode_walk_steps)
            alone |= _episode_keep(pk, T, bout, ok, alone, walking, nb, episode_gap_ratio, max_bout_interval_cv)
            episode_of = _episodes(pk, T, bout, ok, nb, episode_gap_ratio)[bout]
            mark["walking"] = walking[bout] & ok
            ok = ok & alone[bout]
        conf_today = confirmed(today)
        conf = confirmed(ok)
        mark["today"] = today & sure(conf_today)
        mark["stage5b"] = ok & ~today & sure(conf)
        ok &= sure(conf)
    else:
        ok = sure(conf)
        mark["today"] = ok
    account = {}
    for k, sel in (("today", mark["today"]), ("stage5b", mark["stage5b"])):
        c = conf_today if k == "today" else conf
        account[k] = {
            "peak": pk[sel].astype(np.int64),
            "period_s": T[sel] / fs,
            "correlation": R[sel],
            "confidence": c[sel],
            "bout": bout[sel],
            "episode": episode_of[sel],
            "walking": mark["walking"][sel],
        }
    pk, T, R, conf = pk[ok], T[ok], R[ok], conf[ok]
    return {
        "peak": pk.astype(np.int64),
        "y": y,
        "s": s,
        "period_s": T / fs,
        "correlation": R,
        "confidence": conf,
        "cadence": cad,
        "octave": octave,
        "octave_bouts": octave_bouts,
        "rhythm_peaks": n_relieved,
        "rhythm_candidates": n_weak,
        "rhythm_peak_table": rhythm_peaks,
        "today": account["today"],
        "stage5b": account["stage5b"],
    }


#: lowest recording rate (Hz) adaptive's count holds at: the floor rule of :mod:`gaitml.steps._rate` on tyrex, the
#: highest floor any leave-one-person-out fold gives (the figures: experiments/reports/tyrex-steps.md, 'rate floors')
RATE_FLOOR_HZ = 15.0


class AdaptiveStepDetector(BaseStepDetector):
    """Step detector for any carrying position: band-pass, cadence with stride/step disambiguation, left/right fold, peaks, bout edges.

    Every setting is a physiological range, a dimensionless ratio or a noise
    floor (module docstring); none was fitted per carrying position.

    Parameters
    ----------
    band_hz : (float, float), default (0.5, 4.0)
        Gait band of the zero-phase 2nd-order Butterworth band-pass (Hz):
        below the slowest stride frequency (0.6 Hz), above the fastest step
        (3.5 Hz).
    window_s : float, default 5.0
        Length of the cadence windows (s): several strides at the slowest cadence.
    hop_s : float, default 1.0
        Hop between cadence windows (s).
    min_step_hz : float, default 0.75
        Slowest step frequency of human walking (Hz; 45 steps/min; walking
        cadence reaches below 60 steps/min: CADENCE-Adults, Tudor-Locke et al.
        2020). A dominant period longer than ``1 / min_step_hz`` is taken for a stride.
    max_step_hz : float, default 3.5
        Fastest step frequency (Hz; running, 210 steps/min): the shortest step
        period searched.
    half_lag_min_correlation : float, default 0.0
        An autocorrelation above this at half the fundamental period makes
        that period a stride and its half the step period (two similar
        events per period: left and right step).
    slow_step_hz : float, default 1.2
        A period longer than ``1 / slow_step_hz`` (and without half-period
        evidence) is a slow step only in a window whose band-passed RMS is at
        most ``slow_step_max_rms_ms2``; otherwise a stride.
    slow_step_max_rms_ms2 : float, default 1.5
        The most motion a walker slower than ``slow_step_hz`` makes at the
        phone (m/s^2 RMS): the trunk's vertical acceleration at 1.2 steps/s and
        a ~3 cm excursion (Orendurff et al. 2004) is ~0.6 RMS; 2.5 times that.
        Not applied where the gyroscope shows the phone does not swing (swing
        RMS below ``gyro_min_rms_rads``).
    slow_step_max_half_correlation : float, default -0.5
        A period longer than ``1 / slow_step_hz`` is a slow step only where the
        autocorrelation at its half is at most this (a step is in deep
        anti-phase at half its period: -0.55 to -0.98 on every Oxford
        recording); above it the period is a one-leg stride whose other step
        shakes the phone too (a trouser pocket on a slow walk).
    min_periodicity : float, default 0.3
        Steps only where the window's strongest autocorrelation peak reaches
        this (periodic motion; dimensionless).
    min_rms_ms2 : float, default 0.2
        Noise floor (m/s^2): RMS of the band-passed magnitude over one step
        period before a step and over one after it (both must reach it); phone accelerometer noise is about
        0.01-0.05 m/s^2, walking above 0.5.
    min_rms_slow_ms2 : float, default 0.2 (= ``min_rms_ms2``: off)
        Below it (opt-in), where the local step period is longer than
        ``1 / slow_step_hz`` the noise floor is ``min_rms_ms2 x (f / slow_step_hz)^2``
        at step frequency ``f``, but not below this (:func:`slow_step_noise_floor`):
        a slow step of the same vertical excursion carries less acceleration.
    rhythm_min_periodicity : float, default 0.0 (off)
        Above 0 and below ``min_periodicity`` (opt-in, with a gyroscope), the periodicity
        floor's relief: a peak that only the periodicity floor removes is kept
        where its periodicity reaches this and the phone turns with a stride
        rhythm whose step matches the window's (:func:`rhythm_windows`).
        Without a gyroscope (or with ``use_gyroscope=False``) it cannot run: one
        warning says so and the steps are those of the default.
    rhythm_step_tolerance : float, default 0.25
        The relief's match: the swing's step (half its stride period) within
        this fraction of the window's step period.
    min_distance_ratio : float, default 0.6
        A step is the highest peak of the folded signal within this fraction
        of the local step period on either side.
    fold : bool, default True
        Apply the left/right fold (stage 3); ``False`` picks peaks of the
        band-passed signal itself.
    edge_confidence_ratio : float, default 0.5
        Bout-edge rule (stage 5): the leading and trailing steps of a walking
        bout whose confidence is below this fraction of the bout's median
        confidence are dropped (dimensionless, in [0, 1]; 0 keeps them). Not
        in ``param_grid``: a ratio chosen by reasoning, not a setting to fit.
    min_bout_steps : int, default 4
        A walking bout counts once this many of its steps remain after the
        bout-edge rule (stage 5): two strides, left/right seen twice. 1 keeps
        every bout, a single step included.
    short_bout_steps : int, default 10
        A bout of fewer steps is short (no gait): it is dropped when its
        step amplitudes vary more than ``max_short_bout_cv``, and every kept
        bout's confidence is scaled by ``min(1, steps / short_bout_steps)``.
        0 disables both.
    max_short_bout_cv : float, default 0.4
        Largest coefficient of variation of the step amplitudes (folded signal
        at the steps) of a short bout: a walk repeats its steps' strength, a
        gesture burst waxes and wanes.
    min_confidence : float, default 0.0
        Drop steps whose confidence is below this (0: keep every step and let
        the caller filter on the ``confidence`` column).
    use_gyroscope : bool, default True
        Where the recording has a gyroscope, check the stride-versus-step
        decision against the phone's swing (stage 2b,
        :func:`gyro_stride_or_step`); ``False`` (or no gyroscope) uses the
        accelerometer alone.
    gyro_min_rms_rads : float, default 0.2
        The gyroscope decides only where the swing axis turns at least this
        much (rad/s RMS): above the sensor noise and the sway of a still
        body, below the rotation of a walking trunk.
    gyro_phase_correlation : float, default 0.7
        Correlation of the swing rate that counts as in phase (>=) or in
        anti-phase (<= its negative).
    gyro_swing_min_periodicity : float, default 0.0
        Stage 2c (0: off): where |acc|'s periodicity is below
        ``min_periodicity``, a swing whose autocorrelation at its stride period
        reaches this sets the step period (half the stride) and the
        periodicity. 0.3, |acc|'s own floor, turns it on for recordings known
        to hold walking (a slow walker); off by default because it lets more
        of a gesturing hand's bursts through as steps. It reads the
        gyroscope: without one (or with ``use_gyroscope=False``) it does not
        run, and ``detect`` says so (a ``UserWarning``, and
        ``cadence_.attrs['swing_stage']``).
    gyro_swing_half_correlation : float, default 0.0
        Stage 2c: the swing must be in anti-phase at half its stride period,
        its autocorrelation there at most minus this (0: negative; the
        swing reverses between the left and the right step).
    gyro_swing_acc_correlation : float, default -1.0
        Stage 2c: |acc|'s autocorrelation at the swing's step period must
        reach this (the steps still repeat in |acc|); -1 is no test.
    gyro_swing_min_bout_steps : int, default 0
        Stage 2c: a walking bout with a step from a swing-set window counts
        only from this many steps (10: the pedometers' ten-step
        confirmation); at most ``min_bout_steps`` is no extra test.
    octave_swing_min_correlation : float, default 0.0
        Stage 5a (0: off; needs the gyroscope): a walking bout's octave is
        decided once for the whole bout from the phone's swing pooled over
        it (:func:`bout_octave`) where that swing's autocorrelation at its
        stride period reaches this: a bout whose peaks come two per swing step
        (heel strike and push-off) has its steps picked again at twice its
        median peak interval. Off by default (it lowers the tyrex count
        accuracy; ``experiments/reports/tyrex-steps.md``). The decisions are
        counted in ``steps_.attrs['octave']``. Asked for without a gyroscope (or with
        ``use_gyroscope=False``) it does not run, and a warning says so.
    octave_swing_half_correlation : float, default 0.0
        Stage 5a: the pooled swing must be in anti-phase at half its stride
        period, its autocorrelation there at most minus this.
    octave_match_tolerance : float, default 0.25
        Stage 5a: the bout's median peak interval, at the octave chosen, lies
        within this fraction of the swing's step (half its stride period);
        no octave within it leaves the bout undecided and as it is.
    max_short_bout_interval_cv : float, default 0.0
        Stage 5a: a short bout whose octave the swing decided passes the
        short-bout rule without the amplitude test when its step intervals
        vary by at most this coefficient of variation (0: no exemption).
    episode_gap_ratio : float, default 3.0
        Stage 5b (with a gyroscope and the gait check): bouts whose separating
        interval is at most this many local step periods are one walking
        episode, and a bout that the minimum-bout or short-bout rule drops is
        kept when its intervals are regular and its episode holds a walking
        bout that survived the gait check (0: off).
    max_bout_interval_cv : float, default 0.2
        Stage 5b: the largest coefficient of variation of a kept bout's step
        intervals (a two-step bout: its interval within this fraction of the
        local step period); also the edge match's tolerance.
    edge_interval_match : bool, default True
        Stage 5b: the edge rule keeps a weak edge step whose interval matches
        its bout's median interval (only with ``episode_gap_ratio`` > 0).
    episode_walk_steps : int, default 10
        Stage 5b: a walking bout passes the rules alone with at least this
        many steps (the pedometers' ten-step confirmation); the edge match
        applies in bouts of at least this many steps.
    episode_before_gait_check : bool, default False
        Stage 5b's rounds 1-2 (lab, to reproduce them): its steps go through
        the gait check with the others, and it runs without a gyroscope too.
        False (round 3): stage 5b runs only where the gait check runs on a
        gyroscope, and the steps it adds join the table after the check,
        only beside walking that survived it
        (:func:`episode_steps_after_check`). Without a gyroscope (or with
        ``gait_check=False``) it does not run and the step table is that of
        the rules without it; asked for with settings other than the defaults,
        a warning says so. ``steps_.attrs['episode']``: ``ran``, and the
        steps it ``added`` and ``withheld`` (added by its rules, no walking
        beside them survived the gait check).
    gait_check : bool, default True
        Leave out the bouts of fewer than 30 steps whose phone rotates at the
        step frequency as no walker's does (a gesturing hand; a longer bout is
        gait whatever its rotation; :mod:`gaitml.steps._gait_evidence`);
        needs a gyroscope (without one nothing is tested). The account is in
        ``steps_.attrs['gait_check']``.
    gait_check_vertical_fraction : float or None, default None
        The gait check's opt-in vertical-symmetry test: a bout of fewer than
        30 steps with more than this share of its vertical acceleration's
        variance at the stride frequency is left out too
        (:data:`~gaitml.steps._gait_evidence.MAX_STRIDE_VERTICAL_FRACTION`,
        0.4, opts in). None: off, because a phone in a swinging hand puts
        much of its vertical acceleration at the stride frequency (the arm
        swings once per stride) and a short walk so carried would lose its
        steps.

    Attributes
    ----------
    steps_ : DataFrame
        ``peak`` the step peak of the folded band-passed magnitude
        (``attrs['event'] = 't_peak_s'``), ``start`` / ``end`` = peak -/+ half
        the local period, ``period_s`` = local step period, ``cadence_hz`` =
        1 / ``period_s``, ``correlation`` (the window's periodicity) and
        ``confidence`` in [0, 1].
    cadence_ : DataFrame
        One row per cadence window: ``t_s`` (window centre), ``cadence_hz``
        (steps per second), ``period_s``, ``periodicity``, ``stride`` (the
        dominant period was a stride), ``inferred`` (from the cadence
        range alone), ``gyro`` (+1 where the gyroscope halved the
        period, -1 where it doubled it, 0 elsewhere) and ``swing`` (True where
        the swing set the period and periodicity, stage 2c).
        ``attrs['swing_stage']``: ``requested`` (``gyro_swing_min_periodicity``
        > 0) and ``ran`` (requested and a gyroscope was read).
    unchecked_steps_ : DataFrame or None
        The step table the gait check read (stage 5b's steps not in it; see
        ``episode_before_gait_check``); None with ``gait_check=False``.
        Chunked runs read it for the check's account
        (:mod:`gaitml.chunked_run`).
    octave_bouts_ : DataFrame
        Stage 5a's decision per walking bout: ``first_peak`` (sample of the
        bout's first peak) and ``octave`` (2 half-steps, 1 steps, 0
        undecided; :func:`bout_octave`); empty where the stage is off.
        ``steps_.attrs['octave']`` counts them (:func:`octave_counts`).
    rhythm_peaks_ : DataFrame
        The periodicity floor's relief (``rhythm_min_periodicity``): per stage-4
        peak only the periodicity floor removed above that periodicity, its
        ``peak`` (sample) and whether the relief kept it (``relieved``); empty
        where the relief is off. ``steps_.attrs['rhythm']`` counts them
        (chunked runs count the peaks of each chunk's core, :mod:`gaitml.chunked_run`).

    Notes
    -----
    Our own detector (module docstring). Figures in sample and
    leave-one-user-out on the Oxford optimisation recordings:
    ``experiments/reports/steps-heldout.md``.

    Known limits, by construction:

    - A walker slower than ``min_step_hz`` (45 steps/min) is taken to show
      strides and is over-counted; one slower than ``slow_step_hz`` who moves
      the phone more than ``slow_step_max_rms_ms2`` too.
    - Where a stride and a step period are both plausible (stride 0.57-0.83 s:
      running strides or walking steps), only the half-period correlation
      decides. A one-leg signal whose far-leg step leaves no positive
      correlation at half the stride (a dominant thigh swing while running,
      synthetic tests) is counted one step per stride. Untested on real
      running data (none in the shared data).
    """

    name = "adaptive"
    rate_floor_hz = RATE_FLOOR_HZ
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "window_s": [POSITIVE],
        "hop_s": [POSITIVE],
        "min_step_hz": [POSITIVE],
        "max_step_hz": [POSITIVE],
        "min_distance_ratio": [POSITIVE],
        "min_bout_steps": [POSITIVE_INTEGER],
        "min_rms_ms2": [NON_NEGATIVE],
        "min_rms_slow_ms2": [NON_NEGATIVE],
        "edge_confidence_ratio": [Interval(0, 1, closed="both")],
        "min_confidence": [NON_NEGATIVE],
        "fold": ["boolean"],
        "slow_step_hz": [POSITIVE],
        "slow_step_max_rms_ms2": [NON_NEGATIVE],
        "slow_step_max_half_correlation": [Interval(-1, 1, closed="both")],
        "short_bout_steps": [NON_NEGATIVE_INTEGER],
        "max_short_bout_cv": [NON_NEGATIVE],
        "use_gyroscope": ["boolean"],
        "gyro_min_rms_rads": [NON_NEGATIVE],
        "gyro_phase_correlation": [Interval(0, 1, closed="both")],
        "gyro_swing_half_correlation": [Interval(0, 1, closed="both")],
        "gyro_swing_min_periodicity": [Interval(0, 1, closed="both")],
        "rhythm_min_periodicity": [Interval(0, 1, closed="both")],
        "rhythm_step_tolerance": [Interval(0, 1, closed="both")],
        "gyro_swing_acc_correlation": [Interval(-1, 1, closed="both")],
        "gyro_swing_min_bout_steps": [NON_NEGATIVE_INTEGER],
        "octave_swing_min_correlation": [Interval(0, 1, closed="both")],
        "octave_swing_half_correlation": [Interval(0, 1, closed="both")],
        "octave_match_tolerance": [Interval(0, 1, closed="both")],
        "max_short_bout_interval_cv": [NON_NEGATIVE],
        "episode_gap_ratio": [NON_NEGATIVE],
        "max_bout_interval_cv": [NON_NEGATIVE],
        "edge_interval_match": ["boolean"],
        "episode_walk_steps": [NON_NEGATIVE_INTEGER],
        "episode_before_gait_check": ["boolean"],
        "gait_check": ["boolean"],
        "gait_check_vertical_fraction": [Interval(0, None, closed="left"), None],
    }
    #: settings the evaluation may choose on training users (``gaitml.pipeline.steps_real``); the defaults are not fitted
    param_grid: ClassVar[dict[str, tuple]] = {"min_periodicity": (0.2, 0.3, 0.4), "min_confidence": (0.0, 0.2, 0.4)}

    def __init__(
        self,
        *,
        band_hz: tuple[float, float] = BAND_HZ,
        window_s: float = WINDOW_S,
        hop_s: float = HOP_S,
        min_step_hz: float = MIN_STEP_HZ,
        max_step_hz: float = MAX_STEP_HZ,
        half_lag_min_correlation: float = HALF_LAG_MIN_CORRELATION,
        slow_step_hz: float = SLOW_STEP_HZ,
        slow_step_max_rms_ms2: float = SLOW_STEP_MAX_RMS_MS2,
        slow_step_max_half_correlation: float = SLOW_STEP_MAX_HALF_CORRELATION,
        min_periodicity: float = MIN_PERIODICITY,
        min_rms_ms2: float = MIN_RMS_MS2,
        min_rms_slow_ms2: float = MIN_RMS_SLOW_MS2,
        rhythm_min_periodicity: float = RHYTHM_MIN_PERIODICITY,
        rhythm_step_tolerance: float = RHYTHM_STEP_TOLERANCE,
        min_distance_ratio: float = MIN_DISTANCE_RATIO,
        fold: bool = True,
        edge_confidence_ratio: float = EDGE_CONFIDENCE_RATIO,
        min_bout_steps: int = MIN_BOUT_STEPS,
        short_bout_steps: int = SHORT_BOUT_STEPS,
        max_short_bout_cv: float = MAX_SHORT_BOUT_CV,
        min_confidence: float = 0.0,
        use_gyroscope: bool = True,
        gyro_min_rms_rads: float = GYRO_MIN_RMS_RADS,
        gyro_phase_correlation: float = GYRO_PHASE_CORRELATION,
        gyro_swing_half_correlation: float = GYRO_SWING_HALF_CORRELATION,
        gyro_swing_min_periodicity: float = GYRO_SWING_MIN_PERIODICITY,
        gyro_swing_acc_correlation: float = GYRO_SWING_ACC_CORRELATION,
        gyro_swing_min_bout_steps: int = GYRO_SWING_MIN_BOUT_STEPS,
        octave_swing_min_correlation: float = OCTAVE_SWING_MIN_CORRELATION,
        octave_swing_half_correlation: float = OCTAVE_SWING_HALF_CORRELATION,
        octave_match_tolerance: float = OCTAVE_MATCH_TOLERANCE,
        max_short_bout_interval_cv: float = MAX_SHORT_BOUT_INTERVAL_CV,
        episode_gap_ratio: float = EPISODE_GAP_RATIO,
        max_bout_interval_cv: float = MAX_BOUT_INTERVAL_CV,
        edge_interval_match: bool = EDGE_INTERVAL_MATCH,
        episode_walk_steps: int = EPISODE_WALK_STEPS,
        episode_before_gait_check: bool = False,
        gait_check: bool = True,
        gait_check_vertical_fraction: float | None = None,
    ):
        self.band_hz = band_hz
        self.window_s = window_s
        self.hop_s = hop_s
        self.min_step_hz = min_step_hz
        self.max_step_hz = max_step_hz
        self.half_lag_min_correlation = half_lag_min_correlation
        self.slow_step_hz = slow_step_hz
        self.slow_step_max_rms_ms2 = slow_step_max_rms_ms2
        self.slow_step_max_half_correlation = slow_step_max_half_correlation
        self.min_periodicity = min_periodicity
        self.min_rms_ms2 = min_rms_ms2
        self.min_rms_slow_ms2 = min_rms_slow_ms2
        self.rhythm_min_periodicity = rhythm_min_periodicity
        self.rhythm_step_tolerance = rhythm_step_tolerance
        self.min_distance_ratio = min_distance_ratio
        self.fold = fold
        self.edge_confidence_ratio = edge_confidence_ratio
        self.min_bout_steps = min_bout_steps
        self.short_bout_steps = short_bout_steps
        self.max_short_bout_cv = max_short_bout_cv
        self.min_confidence = min_confidence
        self.use_gyroscope = use_gyroscope
        self.gyro_min_rms_rads = gyro_min_rms_rads
        self.gyro_phase_correlation = gyro_phase_correlation
        self.gyro_swing_half_correlation = gyro_swing_half_correlation
        self.gyro_swing_min_periodicity = gyro_swing_min_periodicity
        self.gyro_swing_acc_correlation = gyro_swing_acc_correlation
        self.gyro_swing_min_bout_steps = gyro_swing_min_bout_steps
        self.octave_swing_min_correlation = octave_swing_min_correlation
        self.octave_swing_half_correlation = octave_swing_half_correlation
        self.octave_match_tolerance = octave_match_tolerance
        self.max_short_bout_interval_cv = max_short_bout_interval_cv
        self.episode_gap_ratio = episode_gap_ratio
        self.max_bout_interval_cv = max_bout_interval_cv
        self.edge_interval_match = edge_interval_match
        self.episode_walk_steps = episode_walk_steps
        self.episode_before_gait_check = episode_before_gait_check
        self.gait_check = gait_check
        self.gait_check_vertical_fraction = gait_check_vertical_fraction

    def cadence_hop_samples(self, sampling_rate_hz: float) -> int:
        """The hop of the cadence windows (``cadence_``) in samples at ``sampling_rate_hz``
        (:func:`cadence_hop_samples` with this detector's ``hop_s``)."""
        return cadence_hop_samples(sampling_rate_hz, float(self.hop_s))

    def detect(self, recording: Recording) -> AdaptiveStepDetector:
        """Detect steps in ``recording``; results in ``steps_`` and ``cadence_``."""
        params = self._validate_params()
        check = params.pop("gait_check")
        vertical = params.pop("gait_check_vertical_fraction")
        rec = as_recording(recording, "adaptive step detection", min_duration_s=2.0)
        fs = rec.sampling_rate_hz
        lo, hi = (float(v) for v in self.band_hz)
        if 0 < lo < hi and hi >= fs / 2:  # a valid band that the recording's rate cannot carry
            raise InputError(
                f"adaptive step detection needs a rate above twice its band's upper edge ({hi:g} Hz), got a recording at {fs:g} Hz; "
                f"record at {RATE_FLOOR_HZ:g} Hz or more (the lowest rate its count was measured to hold at), or give "
                f"`band_hz` an upper edge below {fs / 2:g} Hz."
            )
        if not 0 < lo < hi < fs / 2:
            raise InputError(f"`band_hz` must be (low, high) with 0 < low < high < {fs / 2:g} Hz (half the rate), got {self.band_hz!r}.")
        if self.min_step_hz >= self.max_step_hz:
            raise InputError(f"`min_step_hz` ({self.min_step_hz}) must be below `max_step_hz` ({self.max_step_hz}).")
        use_gyr = params.pop("use_gyroscope")
        gyr = rec.gyr if use_gyr and rec.has_gyr else None
        swing_requested = float(self.gyro_swing_min_periodicity) > 0
        if swing_requested and gyr is None:
            # stage 2c reads the gyroscope: without one (or with use_gyroscope=False) it cannot run
            why = "use_gyroscope is False" if rec.has_gyr else "the recording has no gyroscope"
            warnings.warn(
                f"adaptive: the swing stage (gyro_swing_min_periodicity={self.gyro_swing_min_periodicity}) did not run: {why}; "
                "steps are detected from |acc| alone.",
                UserWarning,
                stacklevel=2,
            )
        if float(self.octave_swing_min_correlation) > 0 and gyr is None:
            # stage 5a reads the gyroscope too: without one it cannot run (attrs['octave'] stays all 0)
            why = "use_gyroscope is False" if rec.has_gyr else "the recording has no gyroscope"
            warnings.warn(
                f"adaptive: the per-bout octave stage (octave_swing_min_correlation={self.octave_swing_min_correlation}) did not run: "
                f"{why}; steps are detected without it.",
                UserWarning,
                stacklevel=2,
            )
        rhythm_requested = 0 < float(self.rhythm_min_periodicity) < float(self.min_periodicity)
        if rhythm_requested and gyr is None:
            # the periodicity floor's relief reads the gyroscope: without one it cannot run (the default's steps)
            why = "use_gyroscope is False" if rec.has_gyr else "the recording has no gyroscope"
            warnings.warn(
                f"adaptive: the periodicity floor's gyroscope relief (rhythm_min_periodicity={self.rhythm_min_periodicity}) did not run: "
                f"{why}; steps are detected without it.",
                UserWarning,
                stacklevel=2,
            )
        before = params.pop("episode_before_gait_check")
        episode_requested = float(self.episode_gap_ratio) > 0 and float(self.max_bout_interval_cv) > 0
        # stage 5b reads the gait check's verdict, which needs the gyroscope (round 3; rounds 1-2 ran it before the check)
        after = episode_requested and not before
        episode_ran = episode_requested and (before or (check and rec.gyr is not None))
        explicit = (self.episode_gap_ratio, self.max_bout_interval_cv, self.edge_interval_match, self.episode_walk_steps) != (
            EPISODE_GAP_RATIO,
            MAX_BOUT_INTERVAL_CV,
            EDGE_INTERVAL_MATCH,
            EPISODE_WALK_STEPS,
        )
        if after and not episode_ran and explicit:
            why = "gait_check is False" if rec.gyr is not None else "the recording has no gyroscope"
            warnings.warn(
                f"adaptive: the walking-episode stage (episode_gap_ratio={self.episode_gap_ratio}) did not run: {why} (it keeps "
                "only bouts beside walking that passed the gyroscope's gait check); steps are detected without it.",
                UserWarning,
                stacklevel=2,
            )
        if not episode_ran:
            params["episode_gap_ratio"] = 0.0
        r = adaptive_steps(acc_magnitude(rec), fs, gyr_rads=gyr, **params)

        def table(v: dict) -> pd.DataFrame:
            p, per = v["peak"], v["period_s"]
            half = np.rint(per * fs / 2).astype(np.int64)
            return make_step_table(
                np.maximum(p - half, 0),
                p,
                np.minimum(p + half, rec.n_samples),
                fs,
                event="t_peak_s",
                period_s=per,
                cadence_hz=1.0 / per if len(per) else np.zeros(0),
                correlation=v["correlation"],
                confidence=v["confidence"],
            )

        # round 3 of stage 5b: today's table goes through the gait check; the steps stage 5b adds wait until after it
        self.steps_: pd.DataFrame = table(r["today"] if after else r)
        self.unchecked_steps_: pd.DataFrame | None = self.steps_ if check else None
        if check:  # bouts without gait evidence (a gesturing hand) are left out
            # the acceleration only feeds the opt-in vertical test: not measured when it is off
            acc = rec.acc if vertical is not None else None
            self.steps_ = gait_check(self.steps_, rec.gyr, fs, acc=acc, max_stride_vertical_fraction=vertical)
        if after and not episode_ran:
            self.steps_.attrs["episode"] = {"ran": False, "added": 0, "withheld": 0}
        elif after:
            join = episode_steps_after_check(r["today"], r["stage5b"], self.steps_["peak"].to_numpy())
            if join.any():
                new = {k: r["stage5b"][k][join] for k in ("peak", "period_s", "correlation", "confidence")}
                old = {k: self.steps_[k].to_numpy() for k in ("peak", "period_s", "correlation", "confidence")}
                both = {k: np.concatenate([old[k], new[k]]) for k in old}
                order = np.argsort(both["peak"], kind="stable")
                attrs = dict(self.steps_.attrs)
                self.steps_ = table({k: v[order] for k, v in both.items()})
                self.steps_.attrs.update(attrs)
            self.steps_.attrs["episode"] = {"ran": True, "added": int(join.sum()), "withheld": int((~join).sum())}
        # stage 5a's per-bout octave decisions (all 0 where it is off or there is no gyroscope)
        self.steps_.attrs["octave"] = dict(r["octave"])
        # the periodicity floor's relief: whether it ran and how many peaks it kept past stage 4 (before stage 5)
        self.steps_.attrs["rhythm"] = {
            "ran": rhythm_requested and gyr is not None,
            "candidates": int(r["rhythm_candidates"]),
            "peaks": int(r["rhythm_peaks"]),
        }
        self.octave_bouts_ = pd.DataFrame(r["octave_bouts"])
        self.rhythm_peaks_ = pd.DataFrame(r["rhythm_peak_table"])
        cad = r["cadence"]
        self.cadence_: pd.DataFrame = pd.DataFrame(
            {
                "t_s": cad["centre"] / fs,
                "cadence_hz": 1.0 / cad["period_s"],
                "period_s": cad["period_s"],
                "periodicity": cad["periodicity"],
                "stride": cad["stride"],
                "inferred": cad["inferred"],
                "gyro": cad.get("gyro", np.zeros(len(cad["period_s"]), dtype=np.int64)),
                "swing": cad.get("swing", np.zeros(len(cad["period_s"]), dtype=bool)),
            }
        )
        # whether the opt-in swing stage (2c) was asked for and whether it ran (it needs the gyroscope)
        self.cadence_.attrs["swing_stage"] = {"requested": swing_requested, "ran": swing_requested and gyr is not None}
        return self
