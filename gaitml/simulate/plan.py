"""Step planning: which mode, when each step happens, how long and where it goes.

:func:`mode_schedule` lays out mode segments in time (each 8-20 s by
default, consecutive segments differ, every mode appears before any repeats,
optional pauses in between). :func:`plan_steps` walks a :class:`Path` with a
subject's gait under that schedule and returns the true steps and the time
intervals the signal generator evaluates:

- a step interval runs from the previous step event (or the start of a
  walking bout) to this step's event; the step phase ``u`` goes 0 -> 1
  (0.5 -> 1 for the first step of a bout, which starts from rest with an
  amplitude ramp);
- a tail interval of half a step follows the last step of a bout (phase
  0 -> 0.5, amplitude ramping down: the body settles);
- a pause interval (label ``stand``) has no gait motion;
- a rest interval fills the last second or so of a fixed-duration recording
  after the final tail (no motion, labelled with the last step's mode, so
  recordings without pauses carry only the five mode labels).

Step durations scatter with the subject's ``step_jitter`` and alternate by
``1 +/- asymmetry_time`` between the left and right foot; step lengths
scatter with the same coefficient of variation. A slow speed drift
(``speed_drift_cv`` over ``speed_drift_time_s``,
:func:`gaitml.simulate.variability.speed_drift`) scales the step length by
``sqrt(factor)`` and the step duration by ``1 / sqrt(factor)``; each step's
speed relative to the subject's usual speed in that mode (jitter and drift,
without the asymmetry or the turning stretch) is kept in ``speed_rel`` for the
amplitude of the body acceleration. The direction of travel of
a step is the path heading half way along the step (a chord of the path);
the facing heading is that minus the mode's offset. When the mode changes
to one with another offset (e.g. walk -> side_right: the body turns 90 deg
to keep travelling along the path), the first step of the new mode lasts
``1 + |turn| / pi`` times longer (up to twice for a 180 deg turn), which keeps
the turning rate of the body at a few rad/s.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.simulate.modes import MODE_OFFSET_RAD, STAND, check_modes, mode_gait
from gaitml.simulate.route import Path
from gaitml.simulate.subject import Subject
from gaitml.simulate.variability import speed_drift

__all__ = ["StepPlan", "mode_schedule", "plan_steps", "SEGMENT_S", "PAUSE_S"]

#: Default duration range of one mode segment (s): long enough that 1.5 s
#: windows (paper 003 sec. 3.3) mostly hold one mode.
SEGMENT_S = (8.0, 20.0)
#: Default duration range of a pause (s).
PAUSE_S = (2.0, 5.0)

INTERVAL_STEP, INTERVAL_TAIL, INTERVAL_PAUSE, INTERVAL_REST = 0, 1, 2, 3


def mode_schedule(
    rng: np.random.Generator,
    modes,
    total_s: float,
    *,
    segment_s: tuple[float, float] = SEGMENT_S,
    pauses: bool = False,
    pause_s: tuple[float, float] = PAUSE_S,
    pause_probability: float = 0.5,
) -> pd.DataFrame:
    """Mode segments covering ``[0, total_s)``: DataFrame ``mode, t_start_s, t_end_s``.

    Modes come in shuffled rounds (each mode once per round, no mode twice in
    a row); with ``pauses`` a pause (mode ``stand``) follows a segment with
    probability ``pause_probability``.
    """
    modes = check_modes(modes)
    lo, hi = segment_s
    if not 0 < lo <= hi:
        raise InputError(f"segment_s must be (min, max) with 0 < min <= max, got {segment_s!r}.")
    rows = []
    t = 0.0
    last = None
    while t < total_s:
        order = list(rng.permutation(len(modes)))
        if len(order) > 1 and modes[order[0]] == last:
            order.append(order.pop(0))
        for i in order:
            d = rng.uniform(lo, hi)
            rows.append((modes[i], t, t + d))
            t += d
            last = modes[i]
            if pauses and rng.uniform() < pause_probability:
                d = rng.uniform(*pause_s)
                rows.append((STAND, t, t + d))
                t += d
            if t >= total_s:
                break
    return pd.DataFrame(rows, columns=["mode", "t_start_s", "t_end_s"])


@dataclasses.dataclass(frozen=True)
class StepPlan:
    """The true steps and the signal intervals of one recording.

    ``steps``: one row per step: ``t_start_s, t_s`` (the step event), ``mode``,
    ``step_length_m``, ``heading_rad`` (facing, clockwise from north),
    ``direction_rad`` (of travel), ``foot``, ``u0`` (start phase), ``index``
    (global step count, for the left/right alternation), ``prev_mode``
    (mode of the previous step in the same bout, for the blended transition),
    ``speed_rel`` (the step's speed relative to the subject's usual speed in
    its mode, before the turning stretch).
    ``intervals``: ``kind, t_a, t_b, u_a, u_b, step`` (row of ``steps``).
    """

    steps: pd.DataFrame
    intervals: pd.DataFrame
    duration_s: float


def plan_steps(
    subject: Subject,
    path: Path,
    schedule: pd.DataFrame,
    rng: np.random.Generator,
    *,
    duration_s: float | None = None,
    follow_to_end: bool = False,
) -> StepPlan:
    """Walk ``path`` with ``subject``'s gait under ``schedule``.

    Parameters
    ----------
    duration_s : float, optional
        Stop before this time (the recording length). Required unless
        ``follow_to_end``.
    follow_to_end : bool
        Walk until the end of the path (the last step is shortened to land
        exactly on it); the duration follows.
    """
    if duration_s is None and not follow_to_end:
        raise InputError("plan_steps needs duration_s or follow_to_end=True.")
    gaits = {m: mode_gait(subject, m) for m in MODE_OFFSET_RAD}
    seg_mode = schedule["mode"].to_numpy()
    seg_end = schedule["t_end_s"].to_numpy(dtype=float)
    total_len = path.total_length_m
    jit = subject.step_jitter
    drift = speed_drift(rng, float(seg_end[-1]) + 10.0, subject.speed_drift_cv, subject.speed_drift_time_s)

    steps: list[tuple] = []
    intervals: list[tuple] = []
    t = 0.0
    s = 0.0
    k = 0
    in_bout = False
    prev_mode = None
    last_T = 0.5

    def end_bout():
        nonlocal t, in_bout
        if in_bout:
            tail = 0.5 * last_T
            intervals.append((INTERVAL_TAIL, t, t + tail, 0.0, 0.5, len(steps) - 1))
            t += tail
            in_bout = False

    while True:
        i_seg = min(int(np.searchsorted(seg_end, t, side="right")), len(seg_end) - 1)
        mode = seg_mode[i_seg]
        if mode == STAND:
            end_bout()
            t_end = max(seg_end[i_seg], t + 0.5)
            if duration_s is not None and t_end > duration_s:
                t_end = max(duration_s, t)
            intervals.append((INTERVAL_PAUSE, t, t_end, 0.0, 0.0, max(len(steps) - 1, 0)))
            t = t_end
            prev_mode = None
            if duration_s is not None and t >= duration_s - 1e-9:
                break
            continue
        g = gaits[mode]
        side = mode in ("side_left", "side_right")
        foot = ("left" if mode == "side_left" else "right") if side else ("left" if k % 2 == 0 else "right")
        asym = 1.0 + (subject.asymmetry_time if foot == "left" else -subject.asymmetry_time)
        z1, z2 = rng.standard_normal(2)
        sq = float(np.sqrt(drift(t)))
        T = min(max(asym / g.cadence_hz * (1.0 + jit * z1) / sq, 0.6 / g.cadence_hz), 1.4 / g.cadence_hz)
        L = min(max(g.step_length_m * (1.0 + jit * z2) * sq, 0.5 * g.step_length_m), 1.5 * g.step_length_m)
        speed_rel = (L / g.step_length_m) / (T * g.cadence_hz / asym)
        first = not in_bout
        u0 = 0.5 if first else 0.0
        if prev_mode is not None and prev_mode != mode:
            # the body turns to face the new mode's way (up to 180 deg): that step takes longer
            turn = abs(np.angle(np.exp(1j * (g.offset_rad - gaits[prev_mode].offset_rad))))
            T *= 1.0 + turn / np.pi
        if follow_to_end:
            remaining = total_len - s
            if remaining < 0.15:
                break
            if remaining < L * 1.25:
                L = remaining
        if duration_s is not None and t + T + 0.5 * T > duration_s:
            break
        steps.append((t, t + T, mode, L, s + L / 2, foot, u0, k, prev_mode if prev_mode is not None else mode, speed_rel))
        intervals.append((INTERVAL_STEP, t, t + T, u0, 1.0, len(steps) - 1))
        t += T
        s += L
        k += 1
        last_T = T
        in_bout = True
        prev_mode = mode
    if not steps:
        raise InputError(f"the recording is too short to hold one step (duration_s={duration_s}); use at least 2 s.")
    end_bout()
    if duration_s is not None:
        if t < duration_s:
            intervals.append((INTERVAL_REST, t, duration_s, 0.0, 0.0, len(steps) - 1))
        total = float(duration_s)
    else:
        total = t
    steps_df = pd.DataFrame(
        steps,
        columns=["t_start_s", "t_s", "mode", "step_length_m", "s_mid_m", "foot", "u0", "index", "prev_mode", "speed_rel"],
    )
    # direction of travel: the path heading half way along the step; facing = that - offset,
    # unwrapped (continuous, no 2 pi jumps between steps)
    offset = steps_df["mode"].map(MODE_OFFSET_RAD).to_numpy(dtype=float)
    theta = np.unwrap(path.heading_at(steps_df.pop("s_mid_m").to_numpy()) - offset)
    steps_df.insert(4, "heading_rad", theta)
    steps_df.insert(5, "direction_rad", theta + offset)
    iv = pd.DataFrame(intervals, columns=["kind", "t_a", "t_b", "u_a", "u_b", "step"])
    iv = iv[iv["t_b"] > iv["t_a"]].reset_index(drop=True)
    return StepPlan(steps_df, iv, total)
