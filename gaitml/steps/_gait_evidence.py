"""Gait evidence per bout of steps: do the phone's rotation, its vertical motion and its context show a walker?

A step detector finds a run of regular peaks in the acceleration magnitude. A
hand that gestures while its owner stands and talks makes such runs too:
beats, the rhythmic strokes of speech-accompanying gesture, repeat at 1-3 Hz
in bursts of a few seconds (McNeill, *Hand and Mind*, 1992, ch. 3), inside the
cadence range of walking. Their acceleration alone looks like steps; their
rotation does not.

**The physics.** Walking is a two-step cycle. Every segment a phone can ride
on rotates chiefly once per *stride*: the thigh flexes and extends once per
gait cycle, the arm swings once per gait cycle as a pendulum, the pelvis and
trunk rotate and tilt to the left and back to the right once per gait cycle
(Perry & Burnfield, *Gait Analysis: Normal and Pathological Function*, 2nd
ed., 2010, ch. 2-7). At the *step* frequency only the trunk's pitch and roll
nod with each heel strike, by a few degrees (Thorstensson et al., "Trunk
movements in human locomotion", Acta Physiol. Scand. 121, 1984). A phone that
rotates strongly at the step frequency itself, and more than at the stride
frequency, is turned by a hand that beats, not carried by a walker.

**The test.** Steps are grouped into bouts (an interval longer than
``gap_ratio`` step periods ends a bout, as in :mod:`gaitml.steps.adaptive`).
Over each bout (its first step minus half a step period to its last step plus
half) one least-squares fit of sinusoids at the step frequency
``f = 1 / median step interval`` and at the stride frequency ``f / 2``, plus a
constant and a linear trend, to each gyroscope axis gives the amplitude of the
rotation rate at each frequency (the vector norm of the three axes'
amplitudes, rad/s; the rotation rate averaged in blocks down to about 25
Hz). The fit holds one frequency over the whole bout: over a long walk the cadence wanders and the fitted amplitudes shrink, which errs on
the side of keeping steps; a gesture burst lasts seconds and stays in phase. A bout has **no gait evidence** when

- its rotation at the step frequency exceeds ``max_step_rotation_rad_s``
  (default 0.7 rad/s, 40 deg/s: a trunk nod of 3 degrees at 2 steps/s is
  0.66 rad/s);
- it exceeds the rotation at the stride frequency (``step_over_stride_ratio``
  = 1): the gait's segments turn once per stride, a beating hand once per beat;
- and it holds fewer than ``long_bout_steps`` (default 30) steps.

**Long bouts are gait whatever the rotation.** A phone hanging in a bag does
rotate at the step frequency: a shoulder bag or handbag is a pendulum on its
strap (0.25-0.4 m, natural frequency 0.8-1 Hz) driven above its resonance by
the trunk's fore-aft acceleration, about 2 m/s^2 at the step frequency
(Zijlstra & Hof, Gait Posture 18, 2003), so it pitches by
``(a / L) / (w^2 - g / L)`` = 2-4 degrees every step: 0.5-0.9 rad/s at 2
steps/s before the hip knocks it, at or above the trunk's nod. What a bag
walk keeps, and a gesturing hand does not, is its length: beats come in bursts
of 0.5-4 s (McNeill 1992), at most 14 beats at the 3.5 Hz top of the step
band, while a walk repeats its steps for tens of steps. A bout of at least
``long_bout_steps`` regular steps (no interval over ``gap_ratio`` step
periods) therefore keeps its steps whatever its rotation: 30 steps is three times
the ten-step confirmation of pedometers (Bassett et al., Med. Sci. Sports
Exerc. 28, 1996) and 15 s of walking at 2 steps/s, twice the longest burst
of beats counted at the top of the step band.

**Vertical symmetry: the body rises once per step.** The rotation test reads
the rotation at the steps' own frequency, so it cannot reject a bout whose
period was set by a rotation (a beat that turns the phone once per stroke
while |acc| peaks twice looks like a stride of two steps). A second test needs
no rotation: in walking the centre of mass rises and falls once per *step*
(the inverted-pendulum gait: Zijlstra & Hof, Gait Posture 18, 2003), left and
right steps alike, so the vertical acceleration repeats with the step period
(step regularity close to stride regularity: Moe-Nilssen & Helbostad, J.
Biomech. 37, 2004) and little of it varies at the stride frequency (the
difference between a left and a right step). A hand that strokes once per two
|acc| peaks moves up and down once per stroke: its vertical acceleration
varies at the "stride". With ``max_stride_vertical_fraction`` set (opt-in;
:data:`MAX_STRIDE_VERTICAL_FRACTION` = 0.4 is the value chosen on whole
recordings) a bout below ``long_bout_steps`` has **no gait evidence** either
when more than that share of the variance of its vertical acceleration is at
half its step frequency (:func:`vertical_stride_fraction`; the vertical is the
acceleration averaged over a stride). It runs with the rotation test (a
recording with a gyroscope, given its acceleration). It is **off by default**
(``max_stride_vertical_fraction=None``) because a hand that swings the phone
while walking breaks the symmetry it reads: the arm swings once per *stride*
as a pendulum whose forward and backward swings differ (Perry & Burnfield
2010, ch. 7), so a large share of a swinging hand's vertical acceleration is
at half the step frequency, and a short walk with the phone in a swinging
hand loses its steps.

**A few steps alone (opt-in).** A phone handled at a desk (picked up,
tapped, put down) gives runs of 4-14 regular |acc| peaks with little rotation
and a symmetric vertical: nothing in the motion itself tells them from a few
steps of a walker. What can tell them apart is what surrounds them:
pedometers count nothing until ten steps in a row (Bassett et al. 1996) for
that reason. With ``confirm_bout_steps`` = 10 a bout of fewer steps has **no
gait evidence** unless it and the bouts that reach within ``context_s`` (30 s)
of its first or last step hold at least ``context_steps`` (20) steps, where only
bouts that stand on their own count as context (at least ``confirm_bout_steps``
steps, passing the rotation and vertical tests): a walk broken by turns keeps
the short pieces that lie near a piece of ten steps or more, a run of a few
steps alone is left out, and so are several such runs near one another (desk
handling repeated every few seconds). It is **off by default**
(``confirm_bout_steps`` = 0) because a slow, halting walk whose steps the detector finds only in short pieces (the tyrex
AR walks, a phone held up in front) loses them too. The rule is for Python
callers of :func:`gait_check`: a long input run in chunks
(:func:`gaitml.chunked_run.long_steps`) refuses its settings.

Bouts of one step (no interval, no frequency) are not tested by the rotation
and vertical tests; recordings without a gyroscope are not tested at all:
they keep their steps, and the result says the test could not run. The
rotation thresholds were set on simulated gestures (seeds 0-39) and on the
tyrex walks of two of its three people; ``max_stride_vertical_fraction``,
``context_s`` and ``context_steps`` on simulated gestures and desk handling
(seeds 0-39) and the tyrex walks (AR included), leave-one-person-out; the
figures, in sample and held out, are in ``experiments/reports/nongait.md``.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = [
    "GAP_RATIO",
    "MAX_STEP_ROTATION_RAD_S",
    "STEP_OVER_STRIDE_RATIO",
    "LONG_BOUT_STEPS",
    "MAX_STRIDE_VERTICAL_FRACTION",
    "CONFIRM_BOUT_STEPS",
    "CONTEXT_S",
    "CONTEXT_STEPS",
    "MAX_STEP_INTERVAL_S",
    "step_bouts",
    "rotation_amplitude",
    "vertical_stride_fraction",
    "gait_evidence",
    "gait_check",
    "gait_check_recording",
]

#: an interval longer than this many step periods ends a bout (no step interval: its timing regularity would be 0)
GAP_RATIO = 2.0
#: an interval longer than this (s) always ends a bout: two steps at the slowest walking cadence, 0.75 steps/s
MAX_STEP_INTERVAL_S = 2.0 / 0.75
#: the most rotation (rad/s amplitude) a walker's phone shows at the step frequency itself: the trunk's nod with
#: each heel strike, a few degrees (Thorstensson et al. 1984): 3 deg at 2 steps/s is 0.66 rad/s
MAX_STEP_ROTATION_RAD_S = 0.7
#: the fit runs on the rotation rate averaged down to about this rate (Hz): steps are at most 3.5 Hz
FIT_RATE_HZ = 25.0
#: a bout without gait evidence also rotates more at the step frequency than this times at the stride frequency
#: (a gait's segments rotate once per stride; Perry & Burnfield 2010)
STEP_OVER_STRIDE_RATIO = 1.0
#: a bout of at least this many regular steps is gait whatever its rotation (a bag swinging on its strap turns once
#: per step; a burst of beats lasts 0.5-4 s, McNeill 1992): three times the pedometers' ten-step confirmation
#: (Bassett et al. 1996), 15 s at 2 steps/s. The limit of this rule: a phone waved or shaken in a steady rhythm
#: for that long is counted as steps (and as confident gait); only shorter bursts are left out
LONG_BOUT_STEPS = 30
#: the vertical-symmetry test's opt-in threshold (the default, ``max_stride_vertical_fraction=None``, is off: a
#: swinging hand's arm swings once per stride; module docstring): with it, a bout below ``long_bout_steps`` has no gait
#: evidence when more than this share of the variance of its vertical acceleration is at the stride frequency (half
#: the step frequency): a body's vertical acceleration repeats every step, left and right alike (Zijlstra & Hof 2003;
#: Moe-Nilssen & Helbostad 2004); a hand that strokes once per two |acc| peaks puts its vertical swing at the
#: "stride". A pure stride sinusoid gives 1
MAX_STRIDE_VERTICAL_FRACTION = 0.4
#: the short-bout context rule is off by default (0): it costs real slow walks (module docstring). Opt in with
#: ``confirm_bout_steps=10`` (the pedometers' ten-step confirmation, Bassett et al. 1996): a bout of fewer steps ...
CONFIRM_BOUT_STEPS = 0
#: ... shows gait only when the bouts within this many seconds of its first and last step ...
CONTEXT_S = 30.0
#: ... hold, with its own, at least this many steps
CONTEXT_STEPS = 20


def step_bouts(t_s: np.ndarray, period_s: np.ndarray | None = None, *, gap_ratio: float = GAP_RATIO) -> np.ndarray:
    """Bout number of every step (0, 1, ...): a new bout after an interval that is no step interval.

    An interval ends a bout when it is longer than ``gap_ratio`` times the
    step period of either step beside it (``period_s``, when given) or longer
    than :data:`MAX_STEP_INTERVAL_S`. ``t_s`` must be sorted.
    """
    t = np.asarray(t_s, dtype=float)
    if len(t) == 0:
        return np.zeros(0, dtype=np.int64)
    d = np.diff(t)
    gap = d > MAX_STEP_INTERVAL_S
    if period_s is not None:
        p = np.asarray(period_s, dtype=float)
        gap |= d > gap_ratio * np.maximum(p[:-1], p[1:])
    return np.concatenate([[0], np.cumsum(gap)]).astype(np.int64)


def rotation_amplitude(x: np.ndarray, sampling_rate_hz: float, *freqs_hz: float) -> np.ndarray:
    """Amplitude (vector norm over the columns) of the sinusoid at each of ``freqs_hz`` in ``x`` (n, k).

    One least-squares fit holds ``sin`` and ``cos`` at every frequency, a
    constant and a linear trend per column, so a slow drift of the rotation
    rate does not leak into the amplitudes and the step and stride
    frequencies, not orthogonal over a short bout, are separated.
    """
    x = np.asarray(x, dtype=float)
    n = len(x)
    t = np.arange(n) / float(sampling_rate_hz)
    rows = []
    for f in freqs_hz:
        w = 2.0 * np.pi * float(f) * t
        rows += [np.sin(w), np.cos(w)]
    M = np.vstack([*rows, np.ones(n), t - t.mean()])  # (columns of the fit, n): contiguous rows for the products
    # normal equations (a few unknowns): as exact as the SVD here and far cheaper on a long bout
    try:
        coef = np.linalg.solve(M @ M.T, M @ x)
    except np.linalg.LinAlgError:  # a degenerate span (shorter than a cycle): the least-squares solver
        coef = np.linalg.lstsq(M.T, x, rcond=None)[0]
    k = len(freqs_hz)
    return np.sqrt(np.sum(coef[: 2 * k].reshape(k, 2, -1) ** 2, axis=(1, 2)))


def vertical_stride_fraction(acc: np.ndarray, sampling_rate_hz: float, start: int, end: int, step_hz: float) -> float:
    """Share of the variance of the vertical acceleration over samples ``start:end`` at the stride frequency.

    The vertical is the direction of gravity, the acceleration (n, 3; m/s^2,
    gravity included) averaged over one stride (``2 / step_hz``) around each
    sample: a moving mean one stride long removes the stride frequency and its
    harmonics, so it leaves the attitude's slower drift. The acceleration along
    it, averaged in blocks down to about :data:`FIT_RATE_HZ`, is fitted with
    sinusoids at ``step_hz / 2``, ``step_hz`` and ``2 * step_hz`` plus a
    constant and a trend (:func:`rotation_amplitude`); the result is the power
    of the stride sinusoid (amplitude^2 / 2) over the variance of the vertical
    acceleration, in [0, 1] up to the fit's leakage; NaN when the span holds
    fewer than 8 blocks or the vertical acceleration does not vary.
    """
    from scipy.ndimage import uniform_filter1d

    x = np.asarray(acc, dtype=float)
    fs = float(sampling_rate_hz)
    f = float(step_hz)
    w = max(1, int(round(2.0 * fs / f)))
    a0, e0 = max(0, start - w), min(len(x), end + w)
    grav = uniform_filter1d(x[a0:e0], w, axis=0, mode="nearest")[start - a0 : end - a0]
    up = grav / np.maximum(np.linalg.norm(grav, axis=1, keepdims=True), 1e-9)
    vert = np.sum(x[start:end] * up, axis=1, keepdims=True)
    q = max(1, int(fs // FIT_RATE_HZ))
    m = len(vert) // q
    if m < 8:
        return float("nan")
    v = vert[: m * q].reshape(m, q, -1).mean(axis=1)
    var = float(np.var(v))
    if not np.isfinite(var) or var <= 0:
        return float("nan")
    half = float(rotation_amplitude(v, fs / q, f / 2.0, f, 2.0 * f)[0])
    return half**2 / 2.0 / var


def gait_evidence(
    gyr: np.ndarray | None,
    sampling_rate_hz: float,
    steps: pd.DataFrame,
    *,
    acc: np.ndarray | None = None,
    event: str | None = None,
    cadence: tuple[np.ndarray, np.ndarray] | None = None,
    gap_ratio: float = GAP_RATIO,
    max_step_rotation_rad_s: float = MAX_STEP_ROTATION_RAD_S,
    step_over_stride_ratio: float = STEP_OVER_STRIDE_RATIO,
    long_bout_steps: int = LONG_BOUT_STEPS,
    max_stride_vertical_fraction: float | None = None,
    confirm_bout_steps: int = CONFIRM_BOUT_STEPS,
    context_s: float = CONTEXT_S,
    context_steps: int = CONTEXT_STEPS,
) -> pd.DataFrame:
    """One row per bout of ``steps``: its rotation, vertical acceleration and neighbours, and whether it shows gait.

    Parameters
    ----------
    gyr : float array (n, 3) or None
        Rotation rate (rad/s) of the recording the steps were found in; None:
        no test (every bout ``tested = False``, ``gait = True``).
    sampling_rate_hz : float
    steps : DataFrame
        A step table (DESIGN sec. 2): sample index column ``peak`` (or the
        column of ``event``), ``period_s`` used for the bout gaps.
    acc : float array (n, 3), optional
        Acceleration (m/s^2, gravity included) of the same recording: the
        vertical share (:func:`vertical_stride_fraction`) is measured only
        with it (None: column NaN, the vertical-symmetry test passes every
        bout).
    event : str, optional
        The time column standing for a step (default ``steps.attrs['event']``,
        else ``t_peak_s``).
    cadence : (t_s, step_hz) arrays, optional
        A local step frequency to test at instead of the bout's own median
        step interval (the median of ``step_hz`` over the bout's span), e.g.
        ``adaptive``'s ``cadence_``, whose stride-versus-step decision holds
        where a detector that counts one step per stride would put the step
        frequency at the stride's and its gait's stride rotation at the
        "step" frequency.
    gap_ratio, max_step_rotation_rad_s, step_over_stride_ratio, context_s : float
        Module docstring.
    max_stride_vertical_fraction : float or None
        The vertical-symmetry test (module docstring): None, the default, is
        off (the share is still measured and returned given ``acc``);
        :data:`MAX_STRIDE_VERTICAL_FRACTION` opts in.
    long_bout_steps : int
        A bout of at least this many steps shows gait whatever its rotation
        and vertical acceleration (module docstring); its rotation is still
        measured and returned, its vertical share is not (NaN).
    confirm_bout_steps, context_steps : int
        A bout of fewer than ``confirm_bout_steps`` steps has no gait evidence
        unless it and the bouts within ``context_s`` of it that stand on their
        own (at least ``confirm_bout_steps`` steps, passing the rotation and
        vertical tests) hold at least ``context_steps`` steps
        (``confirm_bout_steps`` 0, the default: rule off; 10 opts in).

    Returns
    -------
    DataFrame
        ``bout``, ``first`` / ``last`` (row positions in ``steps``), ``n_steps``,
        ``t_start_s`` / ``t_end_s``, ``step_hz``, ``rotation_step_rad_s``,
        ``rotation_stride_rad_s``, ``stride_vertical_fraction`` (NaN where
        untested and on long bouts), ``context_steps`` (its steps and those of the
        bouts within ``context_s`` of it that stand on their own), ``tested``, ``long_bout`` (at
        least ``long_bout_steps`` steps), ``unconfirmed`` (a short bout without
        the context), ``reason`` (``''``, ``'rotation'``, ``'vertical'``,
        ``'unconfirmed'``: the first rule that rejects the bout) and ``gait``.
    """
    cols = [
        "bout",
        "first",
        "last",
        "n_steps",
        "t_start_s",
        "t_end_s",
        "step_hz",
        "rotation_step_rad_s",
        "rotation_stride_rad_s",
        "stride_vertical_fraction",
        "context_steps",
        "tested",
        "long_bout",
        "unconfirmed",
        "reason",
        "gait",
    ]
    if len(steps) == 0:
        return pd.DataFrame({c: [] for c in cols})
    fs = float(sampling_rate_hz)
    ev = event or steps.attrs.get("event", "t_peak_s")
    t = steps[ev].to_numpy(dtype=float)
    period = steps["period_s"].to_numpy(dtype=float) if "period_s" in steps.columns else None
    bout = step_bouts(t, period, gap_ratio=gap_ratio)
    g = None if gyr is None else np.asarray(gyr, dtype=float)
    x = None if acc is None else np.asarray(acc, dtype=float)
    q = max(1, int(fs // FIT_RATE_HZ))
    nb = int(bout[-1]) + 1
    # first and last step time and size of every bout: the context of the short ones
    size = np.bincount(bout, minlength=nb)
    starts = np.concatenate([[0], np.cumsum(size)[:-1]])
    t_first, t_last = t[starts], t[starts + size - 1]
    rows = []
    for b in range(nb):
        idx = np.flatnonzero(bout == b)
        tb = t[idx]
        row = {
            "bout": b,
            "first": int(idx[0]),
            "last": int(idx[-1]),
            "n_steps": len(idx),
            "t_start_s": float(tb[0]),
            "t_end_s": float(tb[-1]),
        }
        f = 1.0 / float(np.median(np.diff(tb))) if len(idx) >= 2 else np.nan
        if cadence is not None and len(idx) >= 2 and len(cadence[0]):
            ct, cf = (np.asarray(v, dtype=float) for v in cadence)
            inside = (ct >= tb[0]) & (ct <= tb[-1])
            f = float(np.median(cf[inside])) if inside.any() else float(np.interp(0.5 * (tb[0] + tb[-1]), ct, cf))
        row["step_hz"] = f
        rs = rr = vf = np.nan
        tested = g is not None and len(idx) >= 2 and np.isfinite(f) and f > 0
        if tested:
            half = 0.5 / f
            a = max(0, int(np.floor((tb[0] - half) * fs)))
            e = min(len(g), int(np.ceil((tb[-1] + half) * fs)) + 1)
            # block means of q samples down to about FIT_RATE_HZ (a box anti-alias filter): the fit needs 3.5 Hz at most
            m = (e - a) // q
            seg = g[a : a + m * q].reshape(m, q, -1).mean(axis=1)
            tested = len(seg) >= 8 and bool(np.all(np.isfinite(seg)))
            if tested:
                rs, rr = (float(v) for v in rotation_amplitude(seg, fs / q, f, f / 2.0))
                if x is not None and len(idx) < long_bout_steps:  # a long bout is gait whatever its vertical: not measured
                    vf = vertical_stride_fraction(x, fs, a, min(e, len(x)), f)
        row["rotation_step_rad_s"] = rs
        row["rotation_stride_rad_s"] = rr
        row["stride_vertical_fraction"] = vf
        row["tested"] = bool(tested)
        long_bout = len(idx) >= long_bout_steps
        beats = tested and rs > max_step_rotation_rad_s and rs > step_over_stride_ratio * rr
        strokes = max_stride_vertical_fraction is not None and tested and np.isfinite(vf) and vf > max_stride_vertical_fraction
        row["long_bout"] = long_bout
        row["reason"] = "rotation" if beats and not long_bout else ("vertical" if strokes and not long_bout else "")
        rows.append(row)
    # the context of a short bout: itself and the bouts near it that stand on their own (they pass the
    # rotation and vertical tests and hold at least confirm_bout_steps steps), so that short runs do not
    # confirm one another
    standing = np.array([r["reason"] == "" for r in rows]) & (size >= max(1, confirm_bout_steps))
    for b, row in enumerate(rows):
        near = (t_last > t_first[b] - context_s) & (t_first < t_last[b] + context_s) & standing
        near[b] = False
        row["context_steps"] = int(size[b] + size[near].sum())
        unconfirmed = g is not None and size[b] < confirm_bout_steps and row["context_steps"] < context_steps
        row["unconfirmed"] = bool(unconfirmed)
        if row["reason"] == "" and unconfirmed:
            row["reason"] = "unconfirmed"
        row["gait"] = row["reason"] == ""
    return pd.DataFrame(rows, columns=cols)


def gait_check(steps: pd.DataFrame, gyr: np.ndarray | None, sampling_rate_hz: float, **kwargs) -> pd.DataFrame:
    """``steps`` without the bouts that show no gait evidence (:func:`gait_evidence`), with the account in ``attrs``.

    ``kwargs`` go to :func:`gait_evidence` (pass ``acc=`` and
    ``max_stride_vertical_fraction=`` for the opt-in vertical-symmetry test). The returned table keeps the input's ``attrs``
    and adds ``attrs['gait_check']``: ``tested`` (False without a gyroscope),
    ``n_steps_rejected``, ``n_bouts_rejected``, ``n_bouts`` and
    ``rejected_t_s`` (the left-out steps' times, for plots and logs); which
    rule left a bout out is :func:`gait_evidence`'s ``reason``.
    """
    attrs = dict(steps.attrs)
    ev = gait_evidence(gyr, sampling_rate_hz, steps, **kwargs)
    keep = np.ones(len(steps), dtype=bool)
    for r in ev.itertuples(index=False):
        if not r.gait:
            keep[r.first : r.last + 1] = False
    out = steps.loc[keep].reset_index(drop=True)
    out.attrs.update(attrs)
    event = attrs.get("event", "t_peak_s")
    out.attrs["gait_check"] = {
        "tested": gyr is not None,
        "n_bouts": len(ev),
        "n_bouts_rejected": int((~ev["gait"].astype(bool)).sum()) if len(ev) else 0,
        "n_steps_rejected": int((~keep).sum()),
        "rejected_t_s": steps[event].to_numpy(dtype=float)[~keep].tolist() if len(steps) else [],
    }
    return out


def gait_check_recording(steps: pd.DataFrame, recording, **kwargs) -> pd.DataFrame:
    """:func:`gait_check` of any detector's ``steps`` on ``recording``, tested at ``adaptive``'s local step frequency.

    ``adaptive`` (gait check off) gives the cadence (its stride-versus-step
    decision); where it cannot run (a recording too short for its cadence
    windows) each bout's own median step interval is used. ``kwargs`` go to
    :func:`gait_evidence` (e.g. ``max_stride_vertical_fraction``).
    """
    from gaitml.errors import InputError
    from gaitml.steps import get_detector

    cadence = None
    if recording.gyr is not None and len(steps):
        try:
            cad = get_detector("adaptive", gait_check=False).detect(recording).cadence_
            cadence = (cad["t_s"].to_numpy(), cad["cadence_hz"].to_numpy())
        except InputError:
            cadence = None
    return gait_check(steps, recording.gyr, recording.sampling_rate_hz, acc=recording.acc, cadence=cadence, **kwargs)
