"""Physics of the simulated modes: cadence, swings, mirror symmetry, reversed patterns, gyro, gravity."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gaitml.consts import GRAVITY_MS2
from gaitml.simulate import Subject, sample_subjects, simulate_recording
from gaitml.simulate.modes import MODE_OFFSET_RAD, displacement_fraction, mode_gait, motion_acceleration, vertical_waveform

#: A subject holding the phone exactly level, without wander, so phone axes = body axes.
LEVEL = dataclasses.replace(Subject(), pitch_rad=0.0, roll_rad=0.0, wander_rad=1e-6, acc_noise_ms2=0.01)


def _single(mode, subject=LEVEL, duration_s=40.0, seed=0, **kw):
    return simulate_recording(subject, modes=(mode,), duration_s=duration_s, seed=seed, **kw)


def _profile(rec, channel, n_bins=20):
    """Mean of a channel over the step phase between consecutive true steps (steady steps only)."""
    t = rec.reference["steps_t_s"]
    x = rec.acc[:, channel] if channel < 3 else np.linalg.norm(rec.acc, axis=1)
    out = []
    for a, b in zip(t[2:-3], t[3:-2], strict=True):
        grid = np.linspace(a, b, n_bins, endpoint=False)
        out.append(np.interp(grid, rec.t_s, x))
    return np.mean(out, axis=0)


@pytest.fixture(scope="module")
def singles():
    return {m: _single(m) for m in ("walk", "run", "side_left", "side_right", "backward")}


def test_run_has_higher_cadence_and_larger_swings(singles):
    walk, run = singles["walk"], singles["run"]
    cad = lambda r: 1.0 / np.median(np.diff(r.reference["steps_t_s"]))  # noqa: E731
    assert 2.4 <= cad(run) <= 3.2
    assert cad(run) > cad(walk) + 0.5
    mag = lambda r: np.linalg.norm(r.acc, axis=1)  # noqa: E731
    assert mag(run).std() > 1.5 * mag(walk).std()
    assert np.percentile(mag(run), 99) - np.percentile(mag(run), 1) > 1.5 * (np.percentile(mag(walk), 99) - np.percentile(mag(walk), 1))
    # flight phase: the specific force drops far below g once per step
    assert np.percentile(mag(run), 5) < 0.7 * GRAVITY_MS2


def test_run_cadence_range_over_subjects():
    for s in sample_subjects(8, seed=1):
        assert 2.4 <= s.run_cadence_hz <= 3.2
        assert s.run_step_length_m > 1.25 * s.walk_step_length_m


def test_side_steps_are_lateral_and_mirror_each_other(singles):
    left, right, walk = singles["side_left"], singles["side_right"], singles["walk"]
    for rec in (left, right):
        # lateral (phone x) dominates forward (phone y) in side steps
        assert rec.acc[:, 0].std() > 2.0 * rec.acc[:, 1].std()
    assert walk.acc[:, 1].std() > walk.acc[:, 0].std() * 0.8
    pl, pr = _profile(left, 0), _profile(right, 0)
    assert np.corrcoef(pl, -pr)[0, 1] > 0.95  # mirror images
    assert np.corrcoef(pl, pr)[0, 1] < -0.9
    assert abs(np.abs(pl).max() - np.abs(pr).max()) < 0.3 * np.abs(pl).max()
    # the vertical pattern is the same for both
    assert np.corrcoef(_profile(left, 2), _profile(right, 2))[0, 1] > 0.95


def test_backward_reverses_the_forward_pattern(singles):
    walk, back = singles["walk"], singles["backward"]
    pw, pb = _profile(walk, 1), _profile(back, 1)
    assert np.corrcoef(pw, pb)[0, 1] < -0.8
    # walking brakes right after heel strike: forward acceleration below its mean in the first quarter step
    assert pw[1:5].mean() < pw.mean()
    assert pb[1:5].mean() > pb.mean()
    # backward: shorter, slower steps
    assert back.reference["steps"]["step_length_m"].mean() < walk.reference["steps"]["step_length_m"].mean()
    assert np.median(np.diff(back.reference["steps_t_s"])) > np.median(np.diff(walk.reference["steps_t_s"]))


def test_walk_sway_at_half_step_frequency(singles):
    walk = singles["walk"]
    x = walk.acc[:, 0] - walk.acc[:, 0].mean()
    f = np.fft.rfftfreq(len(x), 1 / walk.sampling_rate_hz)
    p = np.abs(np.fft.rfft(x)) ** 2
    cad = LEVEL.walk_cadence_hz
    band = lambda f0: p[(f > f0 - 0.1) & (f < f0 + 0.1)].sum()  # noqa: E731
    assert band(cad / 2) > 3 * band(cad)
    z = walk.acc[:, 2] - walk.acc[:, 2].mean()
    pz = np.abs(np.fft.rfft(z)) ** 2
    assert f[np.argmax(pz)] == pytest.approx(cad, abs=0.1)


@pytest.mark.parametrize("mode", ["walk", "run", "side_left", "side_right", "backward"])
def test_step_event_is_the_vertical_peak(mode):
    g = mode_gait(Subject(), mode)
    u = np.linspace(0, 1, 2001)[:-1]
    v = vertical_waveform(
        u,
        amplitude_ms2=g.vertical_ms2,
        harmonics=np.array(g.harmonics),
        skew=g.skew,
        mean=0.0,
        is_run=g.is_run,
        duty=g.duty,
        flight_unload=g.flight_unload,
    )
    assert np.argmax(v) == 0


def test_vertical_waveform_has_zero_mean_and_displacement_is_one_step():
    from gaitml.simulate.modes import gait_table

    tab = gait_table(Subject())
    u = (np.arange(4000) + 0.5) / 4000
    for i in range(len(tab["is_run"])):
        v = vertical_waveform(
            u,
            amplitude_ms2=tab["vertical_ms2"][i],
            harmonics=tab["harmonics"][i],
            skew=tab["skew"][i],
            mean=tab["vertical_mean"][i],
            shoulder=tab["shoulder"][i],
            is_run=tab["is_run"][i] > 0,
            duty=tab["duty"][i],
            flight_unload=tab["flight_unload"][i],
        )
        assert abs(v.mean()) < 1e-3
        c = [tab[k][i] for k in ("speed_c1", "speed_d1", "speed_c2", "speed_d2")]
        assert displacement_fraction(1.0, 0.0, *c) == pytest.approx(1.0)
        assert displacement_fraction(0.0, 0.0, *c) == pytest.approx(0.0)
        # the motion acceleration is the second derivative of the displacement (T = 0.5 s, L = 0.7 m)
        T, L = 0.5, 0.7
        x = L * displacement_fraction(u, 0.0, *c)
        acc_num = np.gradient(np.gradient(x, T / 4000), T / 4000)
        acc = motion_acceleration(u, 0.0, 1 / T, L, *c)
        assert np.allclose(acc_num[5:-5], acc[5:-5], atol=0.05)


def test_gravity_and_gyro_are_consistent_with_pose():
    tilted = dataclasses.replace(LEVEL, pose="tilted", pitch_rad=0.7)
    rec = _single("walk", subject=tilted, duration_s=30.0)
    g = rec.acc.mean(axis=0)
    assert g[1] == pytest.approx(GRAVITY_MS2 * np.sin(0.7), abs=0.25)
    assert g[2] == pytest.approx(GRAVITY_MS2 * np.cos(0.7), abs=0.25)
    flat = _single("walk", duration_s=30.0)
    assert flat.acc.mean(axis=0)[2] == pytest.approx(GRAVITY_MS2, abs=0.2)
    # the gyro is the derivative of the attitude: integrating it over a recording with turns
    # gives the heading change (right turn = negative z rate when flat)
    rec = simulate_recording(LEVEL, modes=("walk",), duration_s=90.0, seed=2)
    th = np.unwrap(rec.reference["trajectory"]["heading_rad"].to_numpy())
    gz = rec.gyr[:, 2] - LEVEL.gyr_bias_z_rads
    turned = -np.cumsum(gz) / rec.sampling_rate_hz
    assert np.ptp(th) > np.pi / 2  # the straight route has turns
    assert np.abs((th - th[0]) - turned).max() < 0.1


def test_turns_have_real_angular_rate():
    rec = simulate_recording(LEVEL, modes=("walk",), duration_s=90.0, seed=2)
    gz = np.abs(rec.gyr[:, 2])
    assert 0.8 < gz.max() < 6.0  # turning while walking: about 1-3 rad/s
    assert np.median(gz) < 0.15  # straight legs


def test_mode_offsets_follow_design():
    assert MODE_OFFSET_RAD["backward"] == pytest.approx(np.pi)
    assert MODE_OFFSET_RAD["side_left"] == pytest.approx(-np.pi / 2)
    assert MODE_OFFSET_RAD["side_right"] == pytest.approx(np.pi / 2)


def test_left_right_asymmetry():
    asym = dataclasses.replace(LEVEL, asymmetry_time=0.06, asymmetry_amp=0.12, impact_ms2=0.5, hand_jitter_ms2=0.05)
    rec = _single("walk", subject=asym, duration_s=60.0)
    steps = rec.reference["steps"]
    dur = (steps["t_s"] - steps["t_start_s"]).to_numpy()[1:]
    foot = steps["foot"].to_numpy()[1:]
    assert dur[foot == "left"].mean() > 1.08 * dur[foot == "right"].mean()
    idx = np.round(steps["t_s"].to_numpy() * rec.sampling_rate_hz).astype(int)[1:-1]
    peak = rec.acc[np.clip(idx, 0, rec.n_samples - 1), 2]
    f = steps["foot"].to_numpy()[1:-1]
    assert peak[f == "left"].mean() > peak[f == "right"].mean() + 0.5
    sym = _single("walk", subject=dataclasses.replace(asym, asymmetry_time=0.0, asymmetry_amp=0.0), duration_s=60.0)
    s2 = sym.reference["steps"]
    d2 = (s2["t_s"] - s2["t_start_s"]).to_numpy()[1:]
    f2 = s2["foot"].to_numpy()[1:]
    assert abs(d2[f2 == "left"].mean() / d2[f2 == "right"].mean() - 1) < 0.03


def test_orientation_wander_is_slow_and_sized():
    from gaitml.signal import moving_average

    for wander in (0.02, 0.06):
        subj = dataclasses.replace(Subject(), wander_rad=wander, wander_time_s=4.0)
        rec = _single("walk", subject=subj, duration_s=120.0, seed=3)
        g = np.column_stack([moving_average(rec.acc[:, j], 100) for j in range(3)])[100:-100]
        pitch = np.arctan2(g[:, 1], g[:, 2])
        assert 0.4 * wander < pitch.std() < 1.6 * wander + 0.01
        assert abs(pitch.mean() - subj.pitch_rad) < 3 * wander
