"""Attitude/heading (paper 003 sec. 4.2), HDE and DW-PCA (paper 002 sec. 3)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gaitml.errors import InputError
from gaitml.pdr.attitude import AttitudeEstimator, initial_attitude, integrate_gyro, integrate_gyro_gravity, step_headings, wrap_angle
from gaitml.pdr.dwpca import dwpca_check_and_average, pca_step_directions
from gaitml.pdr.hde import hde_correct
from gaitml.recording import Recording
from tests.pdr.synth import synth_walk


def test_flat_phone_turning_counter_clockwise_decreases_the_compass_heading():
    fs, n = 50.0, 1001
    acc = np.tile([0.0, 0.0, 9.80665], (n, 1))
    gyr = np.zeros((n, 3))
    gyr[:, 2] = 0.1  # counter-clockwise about up = turning left
    # an even turn with a noiseless gyroscope looks like rest to the still detector: bias removal off here
    for gain in (0.0, 0.5):
        h = (
            AttitudeEstimator(gravity_gain_hz=gain, initial_heading_rad=0.5, gyro_bias="off")
            .estimate(Recording.from_arrays(acc, fs, gyr=gyr))
            .heading_rad_
        )
        assert h[0] == pytest.approx(0.5)
        assert h[-1] == pytest.approx(wrap_angle(0.5 - 0.1 * (n - 1) / fs), abs=1e-9)


@pytest.mark.parametrize("pitch_deg", [-30.0, 25.0, 60.0])
def test_tilted_phone_heading_follows_the_turns(pitch_deg):
    rec = synth_walk([("walk", 6, np.pi / 2), ("walk", 6, np.pi / 2), ("walk", 6, 0.0)], pitch_deg=pitch_deg)
    att = AttitudeEstimator(gravity_gain_hz=0.0).estimate(rec)
    ref = rec.reference["steps"]
    idx = np.round(ref["t_s"].to_numpy() * rec.sampling_rate_hz).astype(int)
    assert np.allclose(wrap_angle(att.heading_rad_[idx] - ref["heading_rad"].to_numpy()), 0.0, atol=1e-6)


def test_initial_attitude_levels_the_phone():
    up = np.array([0.1, 0.5, 0.8])
    up /= np.linalg.norm(up)
    r = initial_attitude(up, heading_rad=1.0)
    assert np.allclose(r.apply(up), [0, 0, 1], atol=1e-12)
    f = r.apply([0.0, 1.0, 0.0])
    assert np.arctan2(f[0], f[1]) == pytest.approx(1.0)


def test_prefix_scan_equals_sequential_integration():
    rng = np.random.default_rng(0)
    gyr = rng.normal(0, 0.7, (777, 3))
    r0 = Rotation.from_euler("xyz", [0.2, -0.1, 1.0])
    q1 = integrate_gyro(gyr, 50.0, r0).as_quat()
    q2 = integrate_gyro_gravity(gyr, np.tile([0.0, 0.0, 1.0], (777, 1)), 50.0, r0, 0.0).as_quat()
    assert np.allclose(np.abs(np.sum(q1 * q2, axis=1)), 1.0, atol=1e-9)


def test_gravity_feedback_limits_tilt_drift_from_gyro_bias():
    rec = synth_walk([("walk", 80, 0.0)], pitch_deg=10, gyro_bias_rads=(0.02, -0.02, 0.0))
    g0 = AttitudeEstimator(gravity_gain_hz=0.0, gyro_bias="off").estimate(rec)
    g1 = AttitudeEstimator(gravity_gain_hz=0.5, gyro_bias="off").estimate(rec)
    true_up_body = Rotation.from_euler("x", 10, degrees=True).inv().apply([0, 0, 1.0])
    tilt0 = np.degrees(np.arccos(np.clip(g0.rotation_[-1].inv().apply([0, 0, 1.0]) @ true_up_body, -1, 1)))
    tilt1 = np.degrees(np.arccos(np.clip(g1.rotation_[-1].inv().apply([0, 0, 1.0]) @ true_up_body, -1, 1)))
    assert tilt0 > 20.0  # 0.028 rad/s of tilt bias over ~42 s
    assert tilt1 < 4.0  # steady state: |bias| / gain = 0.028 / 0.5 rad = 3.2 deg


def test_step_headings_average_over_the_window_across_the_wrap():
    h = wrap_angle(np.linspace(np.pi - 0.2, np.pi + 0.2, 41))
    assert abs(wrap_angle(step_headings(h, [0], [41])[0] - np.pi)) < 1e-9


def test_hde_removes_a_constant_offset_on_straight_legs():
    n = 60
    truth = np.repeat([0.0, np.pi / 2, np.pi, -np.pi / 2], n)
    raw = truth + np.deg2rad(6.0) + np.random.default_rng(0).normal(0, np.deg2rad(1.0), 4 * n)
    # a 6 deg offset is beyond the default error gate (5 deg): the literal rule (gate off) removes it
    corr, delta, straight = hde_correct(raw, np.full(4 * n, 0.5), max_error_rad=np.pi)
    err_raw = np.abs(wrap_angle(raw - truth))[-n // 2 :].mean()
    err = np.abs(wrap_angle(corr - truth))[-n // 2 :].mean()
    assert np.degrees(err_raw) > 5.5
    assert np.degrees(err) < 1.5  # the 1 deg step noise alone gives ~0.8 deg
    assert straight.mean() > 0.8


def test_hde_error_gate_corrects_small_offsets_and_leaves_off_direction_legs():
    n = 60
    truth = np.repeat([0.0, np.pi / 2, np.pi, -np.pi / 2], n)
    noise = np.random.default_rng(0).normal(0, np.deg2rad(1.0), 4 * n)
    raw = truth + np.deg2rad(3.0) + noise
    corr, _, _ = hde_correct(raw, np.full(4 * n, 0.5))
    assert np.degrees(np.abs(wrap_angle(corr - truth))[-n // 2 :].mean()) < 1.5
    # a straight leg 10 deg off every dominant direction: the gate keeps the feedback off
    leg = np.deg2rad(10.0) + noise
    corr, delta, straight = hde_correct(leg, np.full(4 * n, 0.5))
    assert straight.mean() > 0.8
    assert np.all(delta == 0.0)
    corr, delta, _ = hde_correct(leg, np.full(4 * n, 0.5), max_error_rad=np.pi)
    assert np.degrees(np.abs(wrap_angle(corr))[-n:].mean()) < 2.0  # literal rule pulls it to 0 deg


def test_hde_stays_off_on_a_gentle_curve():
    raw = np.deg2rad(np.arange(200) * 1.2)  # 1.2 deg per step: an arc
    corr, delta, straight = hde_correct(raw, np.full(200, 0.5))
    assert not straight.any()
    assert np.allclose(corr, wrap_angle(raw))


def test_hde_bad_input():
    with pytest.raises(InputError, match="feedback_per"):
        hde_correct([0.0, 0.1], feedback_per="minute")
    with pytest.raises(InputError, match="max_error_rad"):
        hde_correct([0.0, 0.1], max_error_rad=0.0)


@pytest.mark.parametrize("direction_deg", [0.0, 37.0, 135.0, -100.0])
def test_pca_direction_with_180_disambiguation(direction_deg):
    d = np.deg2rad(direction_deg)
    n = 25
    tau = np.arange(n) / n
    am = 2.0 * np.cos(2 * np.pi * tau)  # decreases then increases along the motion
    rng = np.random.default_rng(0)
    a = np.column_stack([am * np.sin(d), am * np.cos(d)]) + rng.normal(0, 0.05, (n, 2))
    a = np.vstack([a, a])
    direction, axis, expl = pca_step_directions(a, [0, n], [n, 2 * n])
    assert np.allclose(wrap_angle(direction - d), 0.0, atol=np.deg2rad(3))
    assert (expl > 0.95).all()
    # the reversed pattern (concave) flips the answer
    direction2, *_ = pca_step_directions(-a, [0], [n])
    assert abs(wrap_angle(direction2[0] - d - np.pi)) < np.deg2rad(3)


def test_gyro_check_fixes_a_flip_and_confirms_a_turn():
    pca = np.deg2rad([0.0, 2.0, 180.0, 1.0, 91.0, 89.0])
    gyro = np.deg2rad([0.0, 0.0, 0.0, 0.0, 90.0, 90.0])
    h, fixed = dwpca_check_and_average(pca, gyro, average=False)
    assert abs(np.degrees(wrap_angle(h[2]))) < 3.0  # flip undone
    assert np.degrees(h[4]) == pytest.approx(91.0)  # real turn: previous + gyro turn
    assert fixed.tolist() == [False, False, True, False, True, False]
    avg, _ = dwpca_check_and_average(np.deg2rad([10.0, -10.0, 10.0]), np.zeros(3))
    assert np.allclose(np.degrees(avg), [10.0, 0.0, 0.0], atol=1e-9)


def test_drift_rate_fit_recovers_a_constant_gyro_drift_and_hde_then_removes_it():
    from gaitml.pdr.hde import estimate_drift_rate, hde_heading

    n = 400
    t = np.arange(n) * 0.5
    truth = np.repeat(np.deg2rad([0.0, 90.0, 180.0, 270.0]), n // 4)
    drift = 0.02  # rad/s, 1.1 deg/s: an uncalibrated phone gyro
    raw = wrap_angle(truth + drift * t)
    assert estimate_drift_rate(raw, t) == pytest.approx(drift, abs=5e-4)
    h, _, _, rate, _ = hde_heading(raw, np.full(n, 0.5), t)
    assert rate == pytest.approx(drift, abs=5e-4)
    assert np.degrees(np.abs(wrap_angle(h - truth))).max() < 1.0
    # the paper's buffered HDE alone cannot follow that drift
    h0, _, _, _, _ = hde_heading(raw, np.full(n, 0.5), t, drift_rate="none")
    assert np.degrees(np.abs(wrap_angle(h0 - truth))).max() > 10.0


def test_dwpca_reanchors_after_consistent_disagreement():
    # the chain picked up a wrong value (60 deg) while the PCA keeps saying 0 and the gyro no turn
    pca = np.deg2rad([0.0, 0.0, 60.0, 0.0, 1.0, -1.0, 0.0, 0.0])
    gyro = np.zeros(8)
    gyro[2:] = np.deg2rad(60.0)  # a gyro error makes the jump look like a real turn
    h_paper, _ = dwpca_check_and_average(pca, gyro, average=False, reanchor_steps=0)
    h, _ = dwpca_check_and_average(pca, gyro, average=False, reanchor_steps=3)
    assert abs(np.degrees(h_paper[-1])) > 50.0  # Algorithm 3 alone stays wrong
    assert abs(np.degrees(h[-1])) < 2.0


def test_fit_polarity_learns_a_reversed_rule():
    from gaitml.pdr.dwpca import DwPcaHeading

    n = 25
    tau = np.arange(n) / n
    d = np.deg2rad(40.0)
    walk = 2.0 * np.cos(2 * np.pi * tau)  # convex: the paper's rule holds
    run = -walk  # concave: the rule flips it
    a = np.vstack([np.column_stack([x * np.sin(d), x * np.cos(d)]) for x in [walk] * 6 + [run] * 6])
    start = np.arange(12) * n
    modes = ["walk"] * 6 + ["run"] * 6
    dw = DwPcaHeading().fit_polarity(a, start, start + n, np.full(12, d), modes)
    assert dw.polarity_ == {"walk": 1.0, "run": -1.0}
    dw.directions(a, start, start + n, np.full(12, d), None, modes)
    assert np.allclose(wrap_angle(dw.motion_rad_ - d), 0.0, atol=1e-6)
