"""Signal synthesis and the public entry points: recordings, data sets, routes, files.

:func:`synthesize` turns a :class:`~gaitml.simulate.plan.StepPlan` into a
:class:`~gaitml.recording.Recording` in one vectorised pass over the samples
(no per-sample Python loop): step phase -> body acceleration in the person's
frame (right, forward, up) -> navigation frame -> phone frame with gravity,
plus the gyroscope from the same attitude, sensor bias, noise and rounding.
:func:`simulate_dataset`, :func:`simulate_route` and :func:`write_simulation`
are the public API (also behind ``gaitml simulate``).
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from pathlib import Path as FsPath

import numpy as np
import pandas as pd
import scipy.interpolate

from gaitml.consts import MOTION_MODES
from gaitml.errors import InputError
from gaitml.io import write_csv, write_gaitml_csv, write_manifest
from gaitml.recording import Recording
from gaitml.simulate.modes import (
    MODE_OFFSET_RAD,
    STAND,
    check_modes,
    displacement_fraction,
    gait_table,
    motion_acceleration,
    vertical_waveform,
)
from gaitml.simulate.plan import (
    INTERVAL_PAUSE,
    INTERVAL_REST,
    INTERVAL_STEP,
    INTERVAL_TAIL,
    SEGMENT_S,
    StepPlan,
    mode_schedule,
    plan_steps,
)
from gaitml.simulate.positions import (
    HAND_POSITIONS,
    POSITIONS,
    Placement,
    carried_signals,
    check_positions,
    quaternions,
    rotation_matrices,
    stance_gate,
)
from gaitml.simulate.route import ROUTES, make_path
from gaitml.simulate.sensor import (
    ACC_RESOLUTION_MS2,
    GYR_RESOLUTION_RADS,
    band_noise,
    body_rates,
    smooth_noise,
    specific_force,
)
from gaitml.simulate.subject import POSES, Subject, sample_subjects
from gaitml.simulate.variability import interpolate_knots, speed_gain, step_knots

__all__ = ["synthesize", "simulate_recording", "simulate_dataset", "simulate_route", "write_simulation", "SAMPLING_RATE_RANGE_HZ"]

#: Sampling rates the simulator accepts (phones log at 15-200 Hz, paper 003 sec. 2.1).
SAMPLING_RATE_RANGE_HZ = (20.0, 500.0)

_MODE_INDEX = {m: i for i, m in enumerate(MOTION_MODES)}
_STEP_COLUMNS = ["t_s", "mode", "step_length_m", "heading_rad", "foot", "t_start_s", "x_m", "y_m"]


#: Longest recording the simulator makes (argument validation: 24 h at 50 Hz is 4.3 M samples).
MAX_DURATION_S = 24 * 3600.0


def _check_seed(seed) -> None:
    parts = [seed] if isinstance(seed, int | np.integer) else list(seed)
    if not parts or any(int(p) != p or p < 0 for p in parts):
        raise InputError(f"seed must be a non-negative integer (or a sequence of them), got {seed!r}; use e.g. seed=0.")


def _check_rate(fs: float) -> float:
    fs = float(fs)
    lo, hi = SAMPLING_RATE_RANGE_HZ
    if not np.isfinite(fs) or not lo <= fs <= hi:
        raise InputError(f"sampling_rate_hz must be within {lo:g}-{hi:g} Hz, got {fs!r}; phones log at 50-200 Hz.")
    return fs


def _wrap(a: np.ndarray) -> np.ndarray:
    """Wrap angles to [-pi, pi)."""
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def _smooth_angle(t_knots: np.ndarray, values: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Monotone-cubic (PCHIP) interpolation of an angle and its rate; constant outside the knots."""
    if len(t_knots) == 1:
        return np.full_like(t, values[0]), np.zeros_like(t)
    f = scipy.interpolate.PchipInterpolator(t_knots, values, extrapolate=False)
    tc = np.clip(t, t_knots[0], t_knots[-1])
    rate = f.derivative()(tc)
    rate[(t < t_knots[0]) | (t > t_knots[-1])] = 0.0
    return f(tc), rate


def _pattern(tab: dict, m: np.ndarray, u, phi, du_dt, u0, length_m, asym_amp, var: dict):
    """Person-frame body acceleration (right, forward, up) and phone bobbing for modes ``m``.

    ``var`` holds the per-sample step-to-step factors (:mod:`.variability`):
    ``gain`` (vertical amplitude), ``shape`` (n, 3: 2nd, 3rd harmonic,
    shoulder), ``lateral`` (sway) and ``swing`` (forward speed swing ``c1``,
    ``c2``; constant within a step).
    """
    g = {k: v[m] for k, v in tab.items()}
    harm = g["harmonics"] * np.column_stack([np.ones(len(m)), var["shape"][:, 0], var["shape"][:, 1]])
    a_up = vertical_waveform(
        u,
        amplitude_ms2=g["vertical_ms2"],
        harmonics=harm,
        skew=g["skew"],
        mean=g["vertical_mean"],
        shoulder=g["shoulder"] * var["shape"][:, 2],
        is_run=g["is_run"] > 0,
        duty=g["duty"],
        flight_unload=g["flight_unload"],
    )
    a_up = a_up * (1.0 + asym_amp * np.cos(np.pi * phi)) * var["gain"]
    c1, c2 = g["speed_c1"] * var["swing"], g["speed_c2"] * var["swing"]
    a_m = motion_acceleration(u, u0, du_dt, length_m, c1, g["speed_d1"], c2, g["speed_d2"])
    sway = g["sway_ms2"] * var["lateral"] * (np.cos(np.pi * phi) + g["sway_harmonic3"] * np.cos(3 * np.pi * phi))
    off = g["offset_rad"]
    a_right = a_m * np.sin(off) + sway
    a_fwd = a_m * np.cos(off)
    pitch_b = g["pitch_bob_rad"] * np.cos(2 * np.pi * phi)
    roll_b = g["roll_bob_rad"] * np.cos(np.pi * phi)
    yaw_b = g["yaw_bob_rad"] * np.sin(np.pi * phi)
    return np.stack([a_right, a_fwd, a_up, pitch_b, roll_b, yaw_b])


def _step_variation(subject: Subject, st: pd.DataFrame, k: np.ndarray, phi: np.ndarray, rng: np.random.Generator) -> dict:
    """Per-sample step-to-step factors (see :mod:`gaitml.simulate.variability`)."""
    idx = st["index"].to_numpy(np.int64)
    speed_rel = st["speed_rel"].to_numpy(float) if "speed_rel" in st else np.ones(len(st))
    gain_k = speed_gain(speed_rel)
    gain = interpolate_knots(phi, step_knots(rng, idx, subject.step_amp_cv, base=gain_k))[:, 0]
    shape = interpolate_knots(phi, step_knots(rng, idx, subject.step_shape_cv, n_channels=3))
    lateral = interpolate_knots(phi, step_knots(rng, idx, subject.step_lateral_cv))[:, 0]
    swing_k = np.exp(subject.step_lateral_cv * rng.standard_normal(len(st)))
    return {"gain": gain, "shape": shape, "lateral": lateral, "swing": swing_k[k], "gain_step": gain_k, "swing_step": swing_k}


def _not_running_gain(gain: float, w_cur: np.ndarray, mode_cur: np.ndarray, mode_prev: np.ndarray) -> np.ndarray:
    """Per-sample factor ``gain`` in every mode but running (1 there: its flight phase is free
    fall whatever the gain), ramped across a mode change with the step pattern's weight ``w_cur``."""
    g_mode = np.where(np.arange(len(MOTION_MODES)) == _MODE_INDEX["run"], 1.0, gain)
    return w_cur * g_mode[mode_cur] + (1.0 - w_cur) * g_mode[mode_prev]


def synthesize(
    subject: Subject,
    plan: StepPlan,
    *,
    sampling_rate_hz: float = 50.0,
    rng: np.random.Generator,
    meta: dict | None = None,
    placement: Placement | None = None,
    carry_rng: np.random.Generator | None = None,
) -> Recording:
    """Turn a step plan into a recording with full ground truth (see the package docstring).

    ``placement`` carries the phone on a body segment (:mod:`.positions`; None: in the hand,
    the subject's pose); ``carry_rng`` draws its noise (default:
    ``rng``); the hand-held path (``placement=None``) keeps its random stream unchanged.
    """
    fs = _check_rate(sampling_rate_hz)
    n = int(round(plan.duration_s * fs))
    if n < int(2 * fs):
        raise InputError(f"the recording would have {n} samples; use a duration of at least 2 s.")
    t = np.arange(n) / fs
    iv = plan.intervals
    st = plan.steps
    tb = iv["t_b"].to_numpy(float)
    j = np.clip(np.searchsorted(tb, t, side="right"), 0, len(iv) - 1)
    kind = iv["kind"].to_numpy()[j]
    ta_s, tb_s = iv["t_a"].to_numpy(float)[j], tb[j]
    ua, ub = iv["u_a"].to_numpy(float)[j], iv["u_b"].to_numpy(float)[j]
    x = np.clip((t - ta_s) / (tb_s - ta_s), 0.0, 1.0)
    u = ua + x * (ub - ua)
    du_dt = (ub - ua) / (tb_s - ta_s)
    k = iv["step"].to_numpy()[j]

    mode_cur = st["mode"].map(_MODE_INDEX).to_numpy()
    mode_prev = st["prev_mode"].map(_MODE_INDEX).to_numpy()
    L = st["step_length_m"].to_numpy(float)
    T = (st["t_s"] - st["t_start_s"]).to_numpy(float)
    u0_step = st["u0"].to_numpy(float)
    gidx = st["index"].to_numpy(float)
    is_step = kind == INTERVAL_STEP
    is_tail = kind == INTERVAL_TAIL
    moving = is_step | is_tail
    # continuous step count: phi = k at the event of global step k (left foot on even k)
    phi = np.where(is_step, gidx[k] - 1.0 + u, gidx[k] + np.where(is_tail, u, 0.5))
    u0 = np.where(is_step, u0_step[k], 0.0)
    first = is_step & (u0_step[k] > 0)
    env = np.where(first, 0.5 * (1 - np.cos(np.pi * x)), 1.0)
    env = np.where(is_tail, 0.5 * (1 + np.cos(np.pi * x)), env)
    env = np.where(moving, env, 0.0)
    w_cur = np.where(is_step & (mode_prev[k] != mode_cur[k]), x, 1.0)

    tab = gait_table(subject, MOTION_MODES)
    var = _step_variation(subject, st, k, phi, rng)
    args = (u, phi, du_dt, u0, L[k], subject.asymmetry_amp, var)
    pat = _pattern(tab, mode_cur[k], *args)
    change = w_cur < 1.0
    if change.any():
        pat_prev = _pattern(tab, mode_prev[k], *args)
        pat = w_cur * pat + (1.0 - w_cur) * pat_prev
    pat *= env
    a_right, a_fwd, a_up, pitch_b, roll_b, yaw_b = pat
    # the varying gain and shape leave a small mean over each steady step: remove it with a
    # sin^2 window (zero at the events, so the event stays the peak), no net vertical velocity
    steady = is_step & ~first
    if steady.any():
        cnt = np.bincount(k[steady], minlength=len(st))
        off_k = np.bincount(k[steady], weights=a_up[steady], minlength=len(st)) / np.maximum(cnt, 1)
        a_up = a_up - np.where(steady, 2.0 * off_k[k] * np.sin(np.pi * u) ** 2, 0.0)

    # heel-strike impact: a narrow vertical spike centred on each step event (so the event
    # stays the peak), its area removed again over the step (no net vertical velocity)
    t_ev = st["t_s"].to_numpy(float)
    sig = subject.impact_width_s
    b_imp = subject.impact_ms2 * tab["impact_scale"][mode_cur] * rng.uniform(0.6, 1.4, len(st)) * var["gain_step"]
    jn = np.clip(np.searchsorted(t_ev, t), 1, len(t_ev) - 1) if len(t_ev) > 1 else np.zeros(n, dtype=int)
    if len(t_ev) > 1:
        jn = np.where(np.abs(t - t_ev[jn - 1]) < np.abs(t - t_ev[jn]), jn - 1, jn)
    if placement is None:
        a_up = a_up + b_imp[jn] * np.exp(-0.5 * ((t - t_ev[jn]) / sig) ** 2)
        a_up = a_up - np.where(is_step, b_imp[k] * sig * np.sqrt(2 * np.pi) / T[k], 0.0)
        if subject.hand_gain != 1.0:  # the arm passes on part of the trunk's motion (not in running: see HAND_GAIN_RANGE)
            gain = _not_running_gain(subject.hand_gain, w_cur, mode_cur[k], mode_prev[k])
            a_right, a_fwd, a_up = a_right * gain, a_fwd * gain, a_up * gain
    else:  # the trunk bounce and the impact at the carrying segment
        # a phone on one leg feels that leg's heel strikes and stance far more than the other's
        crng = carry_rng if carry_rng is not None else rng
        own = st["foot"].to_numpy() == ("right" if placement.side > 0 else "left")
        b_leg = b_imp * np.where(own, 1.0, placement.other_leg_impact) * np.exp(placement.impact_cv * crng.standard_normal(len(st)))
        spike = b_leg[jn] * np.exp(-0.5 * ((t - t_ev[jn]) / sig) ** 2)
        spike = spike - np.where(is_step, b_leg[k] * sig * np.sqrt(2 * np.pi) / T[k], 0.0)
        leg0 = 0.0 if placement.side < 0 else 1.0
        bounce = placement.vertical_gain * (1.0 + placement.leg_asymmetry * np.cos(np.pi * (phi - leg0)))
        bounce = bounce * np.exp(placement.impact_cv * smooth_noise(crng, n, fs, 0.5)[:, 0])
        if placement.stance_gate > 0:  # back pocket: the gluteal tissue passes the trunk's motion in its own leg's step
            gate = stance_gate(phi, placement.side, placement.stance_gate)
            bounce, a_right, a_fwd = bounce * gate, a_right * gate, a_fwd * gate
        a_up = bounce * a_up + placement.impact_gain * spike
        spike = placement.impact_gain * spike
        if placement.vigour != 1.0:  # the walker's intensity at the segment (not in running, as the hand gain)
            gain = _not_running_gain(placement.vigour, w_cur, mode_cur[k], mode_prev[k])
            a_right, a_fwd, a_up, spike = a_right * gain, a_fwd * gain, a_up * gain, spike * gain

    # facing heading and direction of travel: smooth through the step midpoints
    t_mid = 0.5 * (st["t_start_s"].to_numpy(float) + st["t_s"].to_numpy(float))
    theta, theta_rate = _smooth_angle(t_mid, st["heading_rad"].to_numpy(float), t)
    psi_k = st["direction_rad"].to_numpy(float)
    _, psi_rate = _smooth_angle(t_mid, np.unwrap(psi_k), t)
    off = np.array([MODE_OFFSET_RAD[m] for m in MOTION_MODES])[mode_cur[k]]
    v_mean = np.where(moving, L[k] / T[k], 0.0) * env
    a_c = v_mean * psi_rate  # centripetal, towards the right of the direction of travel
    a_right = a_right + a_c * np.cos(off)
    a_fwd = a_fwd - a_c * np.sin(off)
    ct, sn = np.cos(theta), np.sin(theta)
    acc_nav = np.column_stack([a_right * ct + a_fwd * sn, -a_right * sn + a_fwd * ct, a_up])

    if placement is None:
        # phone attitude: pose + slow wander + gait bobbing; yaw = -theta (see sensor.py)
        wander = smooth_noise(rng, n, fs, subject.wander_time_s, 3) * subject.wander_rad
        pitch = subject.pitch_rad + wander[:, 0] + pitch_b
        roll = subject.roll_rad + wander[:, 1] + roll_b
        yaw_extra = 0.5 * wander[:, 2] + yaw_b
        yaw = -theta + yaw_extra
        dt = 1.0 / fs
        yaw_rate = -theta_rate + np.gradient(yaw_extra, dt)
        gyr = body_rates(yaw_rate, pitch, np.gradient(pitch, dt), roll, np.gradient(roll, dt))
        acc = specific_force(acc_nav, yaw, pitch, roll)

        # hand/arm vibration while moving (3-15 Hz), some tremor while standing
        shake = (0.15 + 0.85 * env) * np.where(moving, tab["jitter_scale"][mode_cur[k]], 1.0)
        shake = shake * np.exp(subject.hand_jitter_drift * smooth_noise(rng, n, fs, 2.0)[:, 0])
        acc = acc + band_noise(rng, n, fs, 3.0, 15.0, 3) * (subject.hand_jitter_ms2 * shake)[:, None]
        gyr = gyr + band_noise(rng, n, fs, 3.0, 15.0, 3) * (0.1 * subject.hand_jitter_ms2 * shake)[:, None]

        attitude = rotation_matrices(yaw, pitch, roll)
    else:
        carried = carried_signals(
            placement, fs=fs, phi=phi, mode_idx=mode_cur[k], env=env,
            theta=theta, theta_rate=theta_rate, acc_person=np.column_stack([a_right, a_fwd, a_up]), rng=crng,
            impact=spike, impact_step=jn,
        )  # fmt: skip
        acc, gyr, attitude = carried["acc"], carried["gyr"], carried["attitude"]
        # soft tissue / fabric vibration while moving (3-15 Hz), slowly modulated
        shake = (0.1 + 0.9 * env) * np.exp(0.3 * smooth_noise(crng, n, fs, 2.0)[:, 0])
        acc = acc + band_noise(crng, n, fs, 3.0, 15.0, 3) * (placement.vibration_ms2 * shake)[:, None]
        gyr = gyr + band_noise(crng, n, fs, 3.0, 15.0, 3) * (0.1 * placement.vibration_ms2 * shake)[:, None]

    # sensor errors
    acc_bias = np.array([subject.acc_bias_x_ms2, subject.acc_bias_y_ms2, subject.acc_bias_z_ms2])
    gyr_bias = np.array([subject.gyr_bias_x_rads, subject.gyr_bias_y_rads, subject.gyr_bias_z_rads])
    acc = acc + acc_bias + subject.acc_noise_ms2 * rng.standard_normal((n, 3))
    gyr = gyr + gyr_bias + subject.gyr_noise_rads * rng.standard_normal((n, 3))
    acc = np.round(acc / ACC_RESOLUTION_MS2) * ACC_RESOLUTION_MS2
    gyr = np.round(gyr / GYR_RESOLUTION_RADS) * GYR_RESOLUTION_RADS
    acc = np.round(acc, 4) + 0.0
    gyr = np.round(gyr, 5) + 0.0

    # ground truth: positions from the same displacement profile as the forward acceleration
    d = np.column_stack([L * np.sin(psi_k), L * np.cos(psi_k)])
    p_end = np.cumsum(d, axis=0)
    p_start = np.vstack([[0.0, 0.0], p_end[:-1]])
    gk = {kk: v[mode_cur[k]] for kk, v in tab.items() if kk.startswith("speed_")}
    sw = var["swing"]
    frac = displacement_fraction(np.where(is_step, u, 1.0), u0, gk["speed_c1"] * sw, gk["speed_d1"], gk["speed_c2"] * sw, gk["speed_d2"])
    frac = np.where(is_step, frac, 1.0)
    pos = p_start[k] + frac[:, None] * (p_end[k] - p_start[k])
    labels = np.where(kind == INTERVAL_PAUSE, STAND, st["mode"].to_numpy()[k])
    labels = np.where(kind == INTERVAL_REST, st["mode"].to_numpy()[k], labels)

    steps = pd.DataFrame(
        {
            "t_s": np.round(st["t_s"].to_numpy(float), 6),
            "mode": st["mode"].to_numpy(),
            "step_length_m": np.round(L, 6),
            "heading_rad": np.round(_wrap(st["heading_rad"].to_numpy(float)), 6),
            "foot": st["foot"].to_numpy(),
            "t_start_s": np.round(st["t_start_s"].to_numpy(float), 6),
            "x_m": np.round(p_end[:, 0], 6),
            "y_m": np.round(p_end[:, 1], 6),
        }
    )
    steps = steps[steps["t_s"] < n / fs].reset_index(drop=True)
    trajectory = pd.DataFrame(
        {"t": t, "x_m": np.round(pos[:, 0], 4), "y_m": np.round(pos[:, 1], 4), "heading_rad": np.round(_wrap(theta), 5)}
    )
    reference = {
        "steps": steps,
        "steps_t_s": steps["t_s"].to_numpy(float),
        "n_steps_true": len(steps),
        "trajectory": trajectory,
        "attitude_wxyz": quaternions(attitude),
    }
    position = f"hand-{subject.pose}" if placement is None else placement.position
    m = {"source": "gaitml.simulate", "format": "simulated", "device": "simulated phone", "position": position}
    m.update(subject.to_dict())
    if placement is not None:
        m.update(placement.to_dict())
    m.update(meta or {})
    return Recording(acc=acc, gyr=gyr, labels=labels, sampling_rate_hz=fs, meta=m, reference=reference)


def simulate_recording(
    subject: Subject,
    *,
    route: str = "straight",
    duration_s: float | None = 120.0,
    modes: Sequence[str] = MOTION_MODES,
    sampling_rate_hz: float = 50.0,
    seed: int | Sequence[int] = 0,
    pauses: bool = False,
    segment_s: tuple[float, float] = SEGMENT_S,
    meta: dict | None = None,
    placement: Placement | None = None,
) -> Recording:
    """Simulate one recording of ``subject`` along ``route``.

    ``duration_s=None`` walks a closed route (rectangle, arc) to its end.
    ``seed`` may be a sequence (it seeds a ``numpy`` ``SeedSequence``).
    ``placement`` carries the phone on a body segment (:class:`~gaitml.simulate.positions.Placement`;
    None: in the hand, in the subject's pose); its noise comes from a fifth child of the seed.
    """
    modes = check_modes(modes)
    fs = _check_rate(sampling_rate_hz)
    if route not in ROUTES:
        raise InputError(f"unknown route {route!r}; choose from {', '.join(ROUTES)}.")
    if duration_s is not None and (not np.isfinite(duration_s) or not 2.0 <= duration_s <= MAX_DURATION_S):
        raise InputError(f"duration_s must be within 2-{MAX_DURATION_S:g} s (24 h), got {duration_s!r}.")
    _check_seed(seed)
    if duration_s is None and route not in ("rectangle", "arc"):
        raise InputError(f"route {route!r} has no end; give duration_s.")
    ss = np.random.SeedSequence(list(seed) if not isinstance(seed, int | np.integer) else int(seed))
    r_path, r_sched, r_plan, r_sig = (np.random.default_rng(s) for s in ss.spawn(4))
    est_len = (duration_s if duration_s is not None else 1000.0) * 4.0 + 50.0
    path = make_path(route, r_path, min_length_m=est_len)
    total_s = duration_s if duration_s is not None else path.total_length_m / 0.3 + 60.0
    schedule = mode_schedule(r_sched, modes, total_s, segment_s=segment_s, pauses=pauses)
    plan = plan_steps(subject, path, schedule, r_plan, duration_s=duration_s, follow_to_end=duration_s is None)
    m = {"route": route, "route_length_m": round(path.total_length_m, 3) if path.closed else None, "pauses": bool(pauses)}
    m = {k: v for k, v in m.items() if v is not None}
    m.update(meta or {})
    carry_rng = None if placement is None else np.random.default_rng(ss.spawn(1)[0])
    return synthesize(subject, plan, sampling_rate_hz=fs, rng=r_sig, meta=m, placement=placement, carry_rng=carry_rng)


def simulate_dataset(
    n_subjects: int = 8,
    duration_s: float = 120.0,
    modes: Sequence[str] = MOTION_MODES,
    *,
    sampling_rate_hz: float = 50.0,
    seed: int = 0,
    pose: str = "flat",
    route: str = "straight",
    n_sessions: int = 1,
    pauses: bool = False,
    segment_s: tuple[float, float] = SEGMENT_S,
    subjects: Sequence[Subject] | None = None,
    positions: Sequence[str] | str | None = None,
) -> list[Recording]:
    """Simulate ``n_subjects`` x ``n_sessions`` recordings of mixed motion modes.

    Session 1 of a subject uses the subject as drawn; later sessions use
    :meth:`Subject.session_variant` (about 3 % other cadence and step length,
    6 % other amplitude, another grip). Each recording walks ``route`` for
    ``duration_s`` with mode segments of
    ``segment_s`` (8-20 s) in shuffled rounds (every mode in ``modes`` once
    per round, transitions inside the recording). Labels are the mode names;
    with ``pauses=True`` pauses labelled ``stand`` occur between segments.

    Parameters
    ----------
    pose : {'flat', 'tilted', 'mixed'}
        How every subject holds the phone; 'mixed' draws it per subject.
    subjects : sequence of Subject, optional
        Use these instead of drawing ``n_subjects`` from ``seed``.
    positions : sequence of str or comma-separated str, optional
        Carrying positions (:data:`~gaitml.simulate.positions.POSITIONS`): every
        subject and session is simulated once per position (a separate walk), the
        phone's placement drawn per subject, session and position
        (:meth:`Placement.random`). None (default): one hand-held recording per
        subject and session in ``pose``. The recording of the
        position equal to a subject's hand pose (``hand-flat`` for ``pose='flat'``)
        is the same as without ``positions``, apart from its id.

    Returns
    -------
    list of Recording
        ``meta``: ``subject`` (S01..), ``session`` and ``id`` (``S01-R1``; with
        ``positions`` ``S01-R1-front-pocket``), ``position``, the subject
        parameters (``pose``, ``pitch_rad``, ``roll_rad`` describe the hand-held
        phone only), the placement (``carry_*``) for carried positions, route,
        seed; ``reference``: ``steps``, ``steps_t_s``, ``n_steps_true``,
        ``trajectory``, ``attitude_wxyz`` (phone -> navigation quaternion per sample).
    """
    if pose not in (*POSES, "mixed"):
        raise InputError(f"pose must be one of {(*POSES, 'mixed')}, got {pose!r}.")
    if int(n_sessions) != n_sessions or n_sessions < 1:
        raise InputError(f"n_sessions must be a positive integer, got {n_sessions!r}.")
    pos_list = None if positions is None else check_positions(positions)
    if subjects is None:
        subjects = sample_subjects(n_subjects, seed, pose=None if pose == "mixed" else pose)
    recs = []
    for i, subj in enumerate(subjects):
        for j in range(int(n_sessions)):
            rid = f"{subj.subject}-R{j + 1}"
            # session 1 is the subject as drawn; later sessions vary a little (another day)
            s_j = subj if j == 0 else subj.session_variant(np.random.default_rng([int(seed), i, j, 2]))
            if pos_list is not None:
                for pos in pos_list:
                    recs.append(
                        _positioned(
                            s_j, pos, int(seed), i, j, f"{rid}-{pos}", route, duration_s, modes, sampling_rate_hz, pauses, segment_s
                        )
                    )
                continue
            recs.append(
                simulate_recording(
                    s_j,
                    route=route,
                    duration_s=duration_s,
                    modes=modes,
                    sampling_rate_hz=sampling_rate_hz,
                    seed=(int(seed), i, j, 1),
                    pauses=pauses,
                    segment_s=segment_s,
                    meta={"session": rid, "id": rid, "seed": int(seed)},
                )
            )
    return recs


def _positioned(subject, position, seed, i, j, rid, route, duration_s, modes, fs, pauses, segment_s) -> Recording:
    """One recording of ``subject`` carrying the phone at ``position`` (see :func:`simulate_dataset`).

    New randomness comes from seeds of its own (``[seed, i, j, 3, position]`` for the
    placement, ``(seed, i, j, 1, 10 + position)`` for the walk), so the hand-held
    recordings of the same seed are unchanged.
    """
    pi = POSITIONS.index(position)
    placement = None
    walk_seed: tuple = (seed, i, j, 1)
    if position in HAND_POSITIONS:
        held = subject.with_pose(HAND_POSITIONS[position], np.random.default_rng([seed, i, j, 3, pi]))
        if held is not subject:
            walk_seed = (seed, i, j, 1, 10 + pi)
        subject = held
    else:
        placement = Placement.random(position, np.random.default_rng([seed, i, j, 3, pi]))
        walk_seed = (seed, i, j, 1, 10 + pi)
    return simulate_recording(
        subject,
        route=route,
        duration_s=duration_s,
        modes=modes,
        sampling_rate_hz=fs,
        seed=walk_seed,
        pauses=pauses,
        segment_s=segment_s,
        meta={"session": rid, "id": rid, "seed": int(seed)},
        placement=placement,
    )


def simulate_route(
    route: str = "rectangle",
    *,
    subject: Subject | None = None,
    modes: Sequence[str] = MOTION_MODES,
    sampling_rate_hz: float = 50.0,
    seed: int = 0,
    pauses: bool = False,
    duration_s: float | None = None,
    segment_s: tuple[float, float] = SEGMENT_S,
    position: str | None = None,
) -> Recording:
    """Simulate one subject along a route with mixed modes (paper 003 sec. 4.3).

    ``rectangle`` (about 262 m) and ``arc`` (about 400 m) are walked from the
    start back to the start (``duration_s`` None) or cut at ``duration_s``;
    ``straight`` and ``random`` need ``duration_s`` (default 120 s).
    ``position`` (one of :data:`~gaitml.simulate.positions.POSITIONS`; None: the
    subject's hand pose) carries the phone there; the walk is the same for every
    position of the same seed, the placement is drawn from ``[seed, 977, 3, position]``.
    """
    if subject is None:
        subject = sample_subjects(1, seed)[0]
    if duration_s is None and route in ("straight", "random"):
        duration_s = 120.0
    rid = f"{subject.subject}-{route}"
    placement = None
    if position is not None:
        (position,) = check_positions([position])
        prng = np.random.default_rng([int(seed), 977, 3, POSITIONS.index(position)])
        if position in HAND_POSITIONS:
            subject = subject.with_pose(HAND_POSITIONS[position], prng)
        else:
            placement = Placement.random(position, prng)
        rid = f"{rid}-{position}"
    return simulate_recording(
        subject,
        route=route,
        duration_s=duration_s,
        modes=modes,
        sampling_rate_hz=sampling_rate_hz,
        seed=(int(seed), 977, ROUTES.index(route) if route in ROUTES else 0),
        pauses=pauses,
        segment_s=segment_s,
        meta={"session": rid, "id": rid, "seed": int(seed)},
        placement=placement,
    )


_MANIFEST_SKIP = {"source", "format", "id", "session", "subject"}


def write_simulation(recordings: Iterable[Recording], out_dir: str | os.PathLike) -> list[FsPath]:
    """Write simulated recordings in the DESIGN sec. 3 layout, each file atomically.

    ``<id>.csv`` (gaitml-csv with ``label``), ``<id>.steps.csv`` (``t_s, mode,
    step_length_m, heading_rad, foot`` + ``t_start_s, x_m, y_m``),
    ``<id>.trajectory.csv`` (``t, x_m, y_m, heading_rad``) and ``manifest.csv``
    (``file, subject, session`` + the subject's parameters), written last.
    Returns the recording file paths.
    """
    out = FsPath(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rows, paths = [], []
    recs = list(recordings)
    if not recs:
        raise InputError("no recordings to write; simulate at least one.")
    for rec in recs:
        rid = rec.name
        p = write_gaitml_csv(rec, out / f"{rid}.csv")
        paths.append(p)
        if "steps" in rec.reference:
            write_csv(out / f"{rid}.steps.csv", rec.reference["steps"])
        if "trajectory" in rec.reference:
            write_csv(out / f"{rid}.trajectory.csv", rec.reference["trajectory"])
        row = {"file": p.name, "subject": rec.meta.get("subject", rid), "session": rec.meta.get("session", rid)}
        row.update({k: v for k, v in rec.meta.items() if k not in _MANIFEST_SKIP and not isinstance(v, dict | list)})
        row["sampling_rate_hz"] = rec.sampling_rate_hz
        row["duration_s"] = round(rec.duration_s, 6)
        row["n_steps_true"] = int(rec.reference.get("n_steps_true", 0))
        rows.append(row)
    write_manifest(rows, out)
    return paths
