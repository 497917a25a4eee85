"""A foot-mounted IMU (on the instep) walking and running, with its true zero-velocity intervals.

The phone positions of :mod:`.positions` follow the trunk, a thigh or an arm; a
foot-mounted IMU (the sensor of zero-velocity-aided pedestrian navigation, papers
001 and 004) sees a different signal: the foot stands still on the ground for part
of every stance and rotates fast in the swing. This module turns the simulator's
step plan (:func:`~gaitml.simulate.plan_steps`: heel strikes of one foot, step
lengths, walk/run segments, pauses) into that foot's motion, stride by stride.

Phases of a stride of one foot, from its heel strike (HS) to the next:

- loading: the foot rolls about the heel from its landing pitch to flat;
- foot flat: the foot lies still on the ground (the true zero-velocity interval);
- push-off: the heel rises and the foot rolls about the toe to the toe-off (TO) pitch;
- swing: the foot keeps rotating toe-down into early swing, then swings forward
  toe-up, peaks just before landing and drops a little to the landing pitch
  (the rotation reversal of terminal swing), while it moves one stride forward
  with a minimum-jerk profile and lifts by its clearance.

Timing from the literature:

- walking: stance 60-62 % of the stride, foot flat from ~10 % to ~35 % of the
  stride (loading response and mid-stance; Perry & Burnfield, *Gait Analysis:
  Normal and Pathological Function*, 2nd ed. 2010, ch. 2-3);
- running: ground contact time ``t_c = L_c / v`` with the contact length ``L_c``
  nearly independent of speed (Weyand et al., "Faster top running speeds are
  achieved with greater ground forces not more rapid leg movements", J. Appl.
  Physiol. 89, 2000), drawn so that ``t_c`` is 0.2-0.3 s at 2.5-4 m/s, as
  reported for distance running (Novacheck, "The biomechanics of running", Gait
  & Posture 7, 1998); a rearfoot strike with the foot flat from 12-22 % to 40-60 %
  of contact (so the zero-velocity interval lasts 0.04-0.12 s: shorter than the
  0.1 s window of :class:`gaitml.zupt.PseudoStdZuptDetector`).
  Forefoot strikers (no foot flat) are not modelled.

The pitch (toe up +) follows knots at these events through a shape-preserving
cubic (``scipy.interpolate.PchipInterpolator``: flat between equal knots, so the
foot is exactly still in foot flat, and the gyroscope is its exact derivative).
The sensor rides 5 cm above the sole, 8 cm ahead of the heel and 12 cm behind
the toe joint; its position in loading and push-off is that of the rolling
pivot. A heel-strike impact (a 25 Hz oscillation decaying in ~10 ms, 1.5-3 g
walking, 4-8 g running, with a gyroscope transient) ends before foot flat.
Sensor noise and bias as a foot IMU (0.02 m/s^2, 0.3 deg/s white).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.interpolate import PchipInterpolator

from gaitml.consts import GRAVITY_MS2
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.simulate.dataset import _check_rate, _check_seed
from gaitml.simulate.plan import mode_schedule, plan_steps
from gaitml.simulate.route import make_path
from gaitml.simulate.sensor import band_noise, body_rates, nav_to_phone
from gaitml.simulate.subject import Subject

__all__ = [
    "FOOT_MODES",
    "RUN_CONTACT_LENGTH_RANGE_M",
    "RUN_CONTACT_TIME_RANGE_S",
    "WALK_DUTY_RANGE",
    "simulate_foot",
]

#: Modes a foot-mounted recording can hold.
FOOT_MODES = ("walk", "run")
#: Walking stance (ground contact) as a fraction of the stride (Perry & Burnfield 2010: ~60-62 %).
WALK_DUTY_RANGE = (0.58, 0.64)
#: Walking: foot flat starts this fraction of the contact after heel strike (~10 % of the stride)
WALK_FLAT_START_RANGE = (0.13, 0.20)
#: Walking: heel-off comes this fraction of the contact before toe-off (heel rise at ~30-40 % of the stride)
WALK_PUSH_RANGE = (0.38, 0.48)
#: Running contact length L_c (m): t_c = L_c / v (Weyand et al. 2000); 0.2-0.3 s at 2.5-4 m/s (Novacheck 1998)
RUN_CONTACT_LENGTH_RANGE_M = (0.7, 0.85)
#: Running contact time kept within (s)
RUN_CONTACT_TIME_RANGE_S = (0.16, 0.34)
#: Running (rearfoot strike): foot flat starts this fraction of the contact after heel strike
RUN_FLAT_START_RANGE = (0.08, 0.16)
#: Running: heel-off this fraction of the contact before toe-off (foot flat ends at 40-60 % of contact)
RUN_PUSH_RANGE = (0.20, 0.40)
#: Running: the step event of the plan (mid-stance) lies this fraction of the contact after heel strike
RUN_EVENT_IN_CONTACT = 0.45
#: Foot pitch (deg) at heel strike, toe-off, the early-swing minimum, and the overshoot before landing.
PITCH_DEG = {
    "walk": {"hs": (15.0, 25.0), "to": (-65.0, -50.0), "swing_min_extra": (0.0, 10.0), "overshoot": (3.0, 8.0)},
    "run": {"hs": (8.0, 20.0), "to": (-60.0, -45.0), "swing_min_extra": (15.0, 35.0), "overshoot": (5.0, 12.0)},
}
#: Peak sensor clearance in the swing (m).
CLEARANCE_M = {"walk": (0.10, 0.15), "run": (0.20, 0.35)}
#: Heel-strike impact amplitude along the foot's up axis (m/s^2) and its gyroscope transient (deg/s).
IMPACT_MS2 = {"walk": (15.0, 30.0), "run": (40.0, 80.0)}
IMPACT_GYR_DEGS = {"walk": (40.0, 90.0), "run": (100.0, 250.0)}
#: Sensor offsets (m, foot frame: y forward, z up) from the heel (loading pivot) and the toe joint (push-off pivot).
SENSOR_FROM_HEEL_M = (0.08, 0.05)
SENSOR_FROM_TOE_M = (-0.12, 0.05)
#: White noise of the foot IMU (m/s^2, rad/s) and the shoe vibration in the swing (m/s^2 per m/s of speed).
ACC_NOISE_MS2 = 0.02
GYR_NOISE_RADS = np.radians(0.3)
SWING_VIBRATION_MS2_PER_MS = 0.3
#: The first stride starts from standing: push-off and swing durations (s).
FIRST_PUSH_S = 0.2
FIRST_SWING_S = 0.5
#: Where in the swing (fraction) the foot is most toe-down and most toe-up (terminal swing).
SWING_MIN_AT = 0.12
SWING_MAX_AT = 0.88


def _pivot_offset(theta: float, r: tuple[float, float]) -> tuple[float, float]:
    """Sensor displacement (forward, up) from its foot-flat place when the foot pitches by ``theta`` about a pivot."""
    y, z = r
    c, s = np.cos(theta), np.sin(theta)
    return c * y - s * z - y, s * y + c * z - z


def _contact_timing(mode: str, stride_s: float, speed_ms: float, rng: np.random.Generator) -> tuple[float, float, float]:
    """Contact time (s) and the flat-start / push fractions of the contact for one stance."""
    if mode == "walk":
        tc = rng.uniform(*WALK_DUTY_RANGE) * stride_s
        return tc, rng.uniform(*WALK_FLAT_START_RANGE), rng.uniform(*WALK_PUSH_RANGE)
    tc = float(np.clip(rng.uniform(*RUN_CONTACT_LENGTH_RANGE_M) / max(speed_ms, 0.5), *RUN_CONTACT_TIME_RANGE_S))
    return tc, rng.uniform(*RUN_FLAT_START_RANGE), rng.uniform(*RUN_PUSH_RANGE)


def _foot_strides(steps: pd.DataFrame, side: str, rng: np.random.Generator, gaits: dict) -> pd.DataFrame:
    """One row per stance of ``side``: heel strike, flat start, heel-off, toe-off (s), mode, landing x (m) and draws."""
    own = steps[steps["foot"] == side].reset_index(drop=True)
    rows = []
    x_cum = np.cumsum(steps["step_length_m"].to_numpy(float))
    idx = steps.index[steps["foot"] == side].to_numpy()
    for i, r in own.iterrows():
        mode = r["mode"]
        if mode not in FOOT_MODES:
            raise InputError(f"a foot-mounted recording models {', '.join(FOOT_MODES)} only, got mode {mode!r}; choose modes from those.")
        g = gaits[mode]
        stride_nom = 2.0 / g.cadence_hz
        speed = g.step_length_m * g.cadence_hz
        tc, a, b = _contact_timing(mode, stride_nom, speed, rng)
        t_event = float(r["t_s"])
        hs = t_event - (RUN_EVENT_IN_CONTACT * tc if mode == "run" else 0.0)
        swing = stride_nom - tc
        p = PITCH_DEG[mode]
        rows.append(
            {
                "mode": mode,
                "t_heel_strike_s": hs,
                "contact_s": tc,
                "flat_start_frac": a,
                "push_frac": b,
                "swing_s": swing,
                "x_m": float(x_cum[idx[i]]),
                "speed_ms": speed,
                "pitch_hs": np.radians(rng.uniform(*p["hs"])),
                "pitch_to": np.radians(rng.uniform(*p["to"])),
                "swing_min_extra": np.radians(rng.uniform(*p["swing_min_extra"])),
                "overshoot": np.radians(rng.uniform(*p["overshoot"])),
                "clearance_m": rng.uniform(*CLEARANCE_M[mode]),
                "impact_ms2": rng.uniform(*IMPACT_MS2[mode]),
                "impact_gyr_rads": np.radians(rng.uniform(*IMPACT_GYR_DEGS[mode])),
                "roll_to": np.radians(rng.uniform(2.0, 6.0)),
            }
        )
    st = pd.DataFrame(rows)
    if st.empty:
        raise InputError("the recording holds no stance of the instrumented foot; use a longer duration.")
    # a stride up to 1.5 nominal strides long scales contact and swing together; a longer one is
    # a pause: the stance lasts until the next swing must start (the swing keeps its length)
    hs = st["t_heel_strike_s"].to_numpy()
    nxt = np.append(hs[1:], np.inf)
    stride = nxt - hs
    nominal = (st["contact_s"] + st["swing_s"]).to_numpy()
    swing_next = np.append(st["swing_s"].to_numpy()[1:], 0.0)
    normal = stride <= 1.5 * nominal
    scale = np.where(normal, stride / nominal, 1.0)
    st["contact_s"] = st["contact_s"] * scale
    to = np.where(normal, hs + st["contact_s"], nxt - swing_next)
    st["t_toe_off_s"] = np.where(np.isfinite(nxt), to, np.inf)
    st["swing_s"] = np.where(np.isfinite(nxt), nxt - st["t_toe_off_s"], np.nan)
    st["t_flat_start_s"] = st["t_heel_strike_s"] + st["flat_start_frac"] * st["contact_s"]
    st["t_heel_off_s"] = st["t_toe_off_s"] - st["push_frac"] * st["contact_s"]
    return st


def _knots(st: pd.DataFrame, t_end: float) -> dict[str, tuple[list, list]]:
    """Knots (time, value) of pitch, roll, forward and up position of the sensor over all strides.

    The swing's position knots are left out: :func:`_swing_acceleration` writes its acceleration.
    """
    k = {name: ([], []) for name in ("pitch", "roll", "y", "z")}

    def add(name, t, v):
        k[name][0].append(float(t))
        k[name][1].append(float(v))

    first = st.iloc[0]
    # before the first heel strike: the foot stood flat, then pushed off and swung in over FIRST_SWING_S
    y_prev = first["x_m"] - 2.0 * first["speed_ms"] * first["swing_s"] if np.isfinite(first["swing_s"]) else first["x_m"] - 1.0
    t_ho0 = first["t_heel_strike_s"] - FIRST_SWING_S - FIRST_PUSH_S
    for tt in (t_ho0 - 10.0, t_ho0):
        add("pitch", tt, 0.0)
        add("roll", tt, 0.0)
        add("y", tt, y_prev)
        add("z", tt, 0.0)
    for i, r in st.iterrows():
        hs, fs_, ho, to = r["t_heel_strike_s"], r["t_flat_start_s"], r["t_heel_off_s"], r["t_toe_off_s"]
        x = r["x_m"]
        dy_hs, dz_hs = _pivot_offset(r["pitch_hs"], SENSOR_FROM_HEEL_M)
        mid_l = 0.5 * (hs + fs_)
        dy_ml, dz_ml = _pivot_offset(0.5 * r["pitch_hs"], SENSOR_FROM_HEEL_M)
        if i == 0:  # push off and swing into the first landing
            to0 = hs - FIRST_SWING_S
            dy, dz = _pivot_offset(r["pitch_to"], SENSOR_FROM_TOE_M)
            add("pitch", to0, r["pitch_to"])
            add("y", to0, y_prev + dy)
            add("z", to0, dz)
            add("roll", to0, 0.0)
            tt = hs - 0.15 * FIRST_SWING_S
            add("pitch", tt, r["pitch_hs"] + r["overshoot"])
            add("y", tt, y_prev + dy + 0.97 * (x + dy_hs - y_prev - dy))
            add("z", tt, 0.35 * r["clearance_m"])
        add("pitch", hs, r["pitch_hs"])
        add("pitch", mid_l, 0.5 * r["pitch_hs"])
        add("pitch", fs_, 0.0)
        add("y", hs, x + dy_hs)
        add("y", mid_l, x + dy_ml)
        add("y", fs_, x)
        add("z", hs, dz_hs)
        add("z", mid_l, dz_ml)
        add("z", fs_, 0.0)
        add("roll", hs, -0.5 * r["roll_to"])
        add("roll", fs_, 0.0)
        if not np.isfinite(to) or ho >= t_end + 1.0:
            for name in k:
                add(name, t_end + 1.0, k[name][1][-1])
            break
        add("pitch", ho, 0.0)
        add("y", ho, x)
        add("z", ho, 0.0)
        add("roll", ho, 0.0)
        mid_p = 0.5 * (ho + to)
        for tt, th in ((mid_p, 0.5 * r["pitch_to"]), (to, r["pitch_to"])):
            dy, dz = _pivot_offset(th, SENSOR_FROM_TOE_M)
            add("pitch", tt, th)
            add("y", tt, x + dy)
            add("z", tt, dz)
        add("roll", to, r["roll_to"])
        # swing: toe-down minimum, toe-up overshoot before landing; minimum-jerk forward motion
        nxt = st.iloc[i + 1]
        sw = nxt["t_heel_strike_s"] - to
        add("pitch", to + SWING_MIN_AT * sw, r["pitch_to"] - r["swing_min_extra"])
        add("pitch", to + SWING_MAX_AT * sw, nxt["pitch_hs"] + nxt["overshoot"])
        for frac, v in ((0.2, 0.5), (0.5, -0.5), (0.85, -0.4)):
            add("roll", to + frac * sw, v * r["roll_to"])
    return k


def _swing_acceleration(st: pd.DataFrame, t: np.ndarray, acc_nav: np.ndarray) -> None:
    """Write the swing's forward and vertical acceleration into ``acc_nav`` (in place).

    Forward: a minimum-jerk move from the toe-off place to the landing place (Flash & Hogan,
    J. Neurosci. 5, 1985), ``a = D / T^2 (60 s - 180 s^2 + 120 s^3)``; vertical: from the
    toe-off height to the landing height (minimum jerk) plus a clearance bump ``16 h s^2 (1 - s)^2``.
    """
    to = st["t_toe_off_s"].to_numpy()
    hs_next = np.append(st["t_heel_strike_s"].to_numpy()[1:], np.inf)
    ok = np.isfinite(to) & np.isfinite(hs_next)
    x_next = np.append(st["x_m"].to_numpy()[1:], np.nan)
    pitch_next = np.append(st["pitch_hs"].to_numpy()[1:], 0.0)
    for i in np.flatnonzero(ok):
        a, b = np.searchsorted(t, [to[i], hs_next[i]])
        if b <= a:
            continue
        T = hs_next[i] - to[i]
        u = (t[a:b] - to[i]) / T
        y0, z0 = _pivot_offset(st["pitch_to"].iat[i], SENSOR_FROM_TOE_M)
        y1, z1 = _pivot_offset(pitch_next[i], SENSOR_FROM_HEEL_M)
        d = x_next[i] + y1 - (st["x_m"].iat[i] + y0)
        mj = 60 * u - 180 * u**2 + 120 * u**3
        acc_nav[a:b, 1] = d / T**2 * mj
        acc_nav[a:b, 2] = ((z1 - z0) * mj + 16 * st["clearance_m"].iat[i] * (2 - 12 * u + 12 * u**2)) / T**2


def _pchip(knots: tuple[list, list]) -> PchipInterpolator:
    t, v = np.asarray(knots[0]), np.asarray(knots[1])
    order = np.argsort(t, kind="stable")
    t, v = t[order], v[order]
    keep = np.concatenate(([True], np.diff(t) > 1e-6))
    return PchipInterpolator(t[keep], v[keep], extrapolate=True)


def simulate_foot(
    subject: Subject | None = None,
    *,
    modes=("run",),
    duration_s: float = 60.0,
    sampling_rate_hz: float = 100.0,
    seed: int = 0,
    side: str = "left",
    pauses: bool = False,
    segment_s: tuple[float, float] = (20.0, 40.0),
) -> Recording:
    """Simulate a foot-mounted IMU on ``side`` walking and/or running, with its true stances.

    Parameters
    ----------
    subject : Subject, optional
        Default: ``Subject.random`` from the seed (cadence, step length, running speed).
    modes : sequence of {'walk', 'run'}
        Modes of the schedule (shuffled segments of ``segment_s``, as the phone simulator).
    duration_s, sampling_rate_hz, seed :
        Length (2 s - 1 h), rate (the simulator's range) and seed.
    side : {'left', 'right'}
        The instrumented foot.
    pauses : bool
        Standing pauses between segments (the foot stays flat).

    Returns
    -------
    Recording
        ``acc`` (specific force, m/s^2) and ``gyr`` (rad/s) in the foot frame (x right,
        y forward along the foot, z up from the sole), per-sample mode ``labels``
        (``stand`` before the first and after the last stride), and ``reference``:
        ``stances`` (one row per heel strike: ``mode, t_heel_strike_s,
        t_flat_start_s, t_heel_off_s, t_toe_off_s, contact_s``), ``zupt_mask``
        (True in foot flat), ``zupt_intervals`` (``start``, ``end`` samples, end
        exclusive, of every foot flat with a heel strike in the recording) and the
        plan's ``steps`` (both feet).
    """
    fs = _check_rate(sampling_rate_hz)
    _check_seed(seed)
    if side not in ("left", "right"):
        raise InputError(f"`side` must be 'left' or 'right', got {side!r}.")
    bad = [m for m in modes if m not in FOOT_MODES]
    if bad or not len(modes):
        raise InputError(f"a foot-mounted recording models {', '.join(FOOT_MODES)} only, got {list(modes)!r}; choose from those.")
    if not (np.isfinite(duration_s) and 2.0 <= duration_s <= 3600.0):
        raise InputError(f"`duration_s` must be within 2-3600 s, got {duration_s!r}.")
    ss = np.random.SeedSequence([int(seed), 7919])
    r_subj, r_path, r_sched, r_plan, r_foot, r_noise = (np.random.default_rng(s) for s in ss.spawn(6))
    if subject is None:
        subject = Subject.random(r_subj, subject=f"F{int(seed):03d}")
    from gaitml.simulate.modes import mode_gait

    gaits = {m: mode_gait(subject, m) for m in FOOT_MODES}
    path = make_path("straight", r_path, min_length_m=duration_s * 6.0 + 50.0)
    schedule = mode_schedule(r_sched, list(modes), duration_s, segment_s=segment_s, pauses=pauses)
    plan = plan_steps(subject, path, schedule, r_plan, duration_s=duration_s)
    st = _foot_strides(plan.steps, side, r_foot, gaits)
    n = int(round(duration_s * fs))
    t = np.arange(n) / fs
    k = _knots(st, n / fs)
    pitch_f, roll_f, y_f, z_f = (_pchip(k[name]) for name in ("pitch", "roll", "y", "z"))
    pitch, roll = pitch_f(t), roll_f(t)
    dpitch, droll = pitch_f.derivative()(t), roll_f.derivative()(t)
    acc_nav = np.column_stack([np.zeros(n), y_f.derivative(2)(t), z_f.derivative(2)(t)])
    _swing_acceleration(st, t, acc_nav)
    acc_nav[:, 2] += GRAVITY_MS2
    acc = nav_to_phone(acc_nav, np.zeros(n), pitch, roll)
    gyr = body_rates(np.zeros(n), pitch, dpitch, roll, droll)
    # heel-strike impact (foot frame): a 25 Hz oscillation decaying with tau 8 ms, over before foot flat
    hs = st["t_heel_strike_s"].to_numpy()
    fl = st["t_flat_start_s"].to_numpy()
    j = np.clip(np.searchsorted(hs, t, side="right") - 1, 0, len(hs) - 1)
    dt_hs = t - hs[j]
    inside = (dt_hs >= 0) & (t < fl[j])
    osc = np.where(inside, np.exp(-dt_hs / 0.008) * np.sin(2 * np.pi * 25.0 * dt_hs + 0.5 * np.pi), 0.0)
    acc[:, 2] += st["impact_ms2"].to_numpy()[j] * osc
    acc[:, 1] -= 0.4 * st["impact_ms2"].to_numpy()[j] * osc
    gyr[:, 0] += st["impact_gyr_rads"].to_numpy()[j] * osc
    # truth: foot flat (zero velocity); the shoe vibrates in the swing only
    flat = np.zeros(n, dtype=bool)
    ho = st["t_heel_off_s"].to_numpy()
    starts = np.clip(np.ceil(fl * fs - 1e-9).astype(np.int64), 0, n)
    ends = np.clip(np.floor(np.where(np.isfinite(ho), ho, n / fs) * fs + 1e-9).astype(np.int64) + 1, 0, n)
    for a, b in zip(starts, ends, strict=True):
        flat[a:b] = True
    flat[: int(np.clip(np.floor((hs[0] - FIRST_SWING_S - FIRST_PUSH_S) * fs), 0, n))] = True
    speed = st["speed_ms"].to_numpy()[j]
    vib = band_noise(r_noise, n, fs, 8.0, 40.0, 3) * (SWING_VIBRATION_MS2_PER_MS * speed * ~flat)[:, None]
    acc = acc + vib + ACC_NOISE_MS2 * r_noise.standard_normal((n, 3)) + r_noise.normal(0, 0.05, 3)
    gyr = gyr + 0.1 * vib + GYR_NOISE_RADS * r_noise.standard_normal((n, 3)) + r_noise.normal(0, np.radians(0.5), 3)
    labels = np.where(t < hs[0] - 0.5, "stand", st["mode"].to_numpy()[j])
    last_to = st["t_toe_off_s"].to_numpy()
    labels = np.where(~np.isfinite(last_to[j]) & (t > hs[-1] + 0.5), "stand", labels)
    in_rec = (st["t_heel_strike_s"] >= 0) & (st["t_heel_strike_s"] < n / fs)
    stances = st.loc[in_rec, ["mode", "t_heel_strike_s", "t_flat_start_s", "t_heel_off_s", "t_toe_off_s", "contact_s"]].reset_index(
        drop=True
    )
    iv = pd.DataFrame({"start": starts[in_rec.to_numpy()], "end": ends[in_rec.to_numpy()]})
    iv = iv[iv["end"] > iv["start"]].reset_index(drop=True)
    meta = {
        "source": "gaitml.simulate.foot",
        "format": "simulated",
        "device": "simulated foot IMU",
        "position": f"foot-{side}",
        "subject": subject.subject,
        "modes": ",".join(modes),
        "seed": int(seed),
    }
    return Recording(
        acc=acc,
        gyr=gyr,
        labels=labels,
        sampling_rate_hz=fs,
        meta=meta,
        reference={"stances": stances, "zupt_mask": flat, "zupt_intervals": iv, "steps": plan.steps},
        check_units=False,
    )
