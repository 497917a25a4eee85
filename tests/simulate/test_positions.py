"""Carrying positions (gaitml.simulate.positions): every position x mode, segment physics, attitude truth, manifest, CLI, config."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import scipy.signal
from scipy.spatial.transform import Rotation

from gaitml.cli import main
from gaitml.consts import GRAVITY_MS2, MOTION_MODES
from gaitml.errors import ConfigError, InputError
from gaitml.simulate import (
    CARRIED_POSITIONS,
    POSITIONS,
    Placement,
    check_positions,
    sample_subjects,
    simulate_dataset,
    simulate_recording,
    simulate_route,
    write_simulation,
)

FS = 50.0


@pytest.fixture(scope="module")
def every_position_and_mode():
    return {m: simulate_dataset(1, 10.0, (m,), seed=5, positions=POSITIONS) for m in MOTION_MODES}


def _walk(position: str, mode: str = "walk", seed: int = 1, duration_s: float = 40.0, side: float | None = None):
    """One straight-line walk of a default-ish subject with the phone at ``position``."""
    subj = sample_subjects(1, seed)[0]
    p = Placement.random(position, np.random.default_rng(seed))
    if side is not None:
        p = Placement(**{**p.__dict__, "side": side})
    return simulate_recording(subj, route="straight", duration_s=duration_s, modes=(mode,), seed=seed, placement=p), p


def _gyr_unbiased(rec) -> np.ndarray:
    return rec.gyr - np.array([rec.meta["gyr_bias_x_rads"], rec.meta["gyr_bias_y_rads"], rec.meta["gyr_bias_z_rads"]])


def _walking_part(rec):
    st = rec.reference["steps_t_s"]
    return slice(int(st[2] * FS), int(st[-2] * FS))


def _dominant_hz(x: np.ndarray) -> float:
    f, p = scipy.signal.welch(x - x.mean(), fs=FS, nperseg=min(len(x), 512))
    band = (f > 0.3) & (f < 6)
    return float(f[band][np.argmax(p[band])])


# ------------------------------------------------------------------ names
def test_position_names_and_errors():
    assert POSITIONS[:2] == ("hand-flat", "hand-tilted")
    assert set(CARRIED_POSITIONS) == {"front-pocket", "back-pocket", "belt", "swinging-hand", "bag"}
    assert check_positions("front_pocket, belt,front-pocket") == ("front-pocket", "belt")
    with pytest.raises(InputError, match="unknown carrying position 'pocket'; choose from hand-flat, .*bag") as exc:
        check_positions(["pocket"])
    assert "\n" not in str(exc.value)
    with pytest.raises(InputError, match="no carrying position"):
        check_positions(" , ")
    with pytest.raises(InputError):
        simulate_dataset(1, 10.0, positions=("belt", "neck"))


@pytest.mark.parametrize("position", CARRIED_POSITIONS)
def test_placements_are_rotations_and_reproducible(position):
    for s in range(20):
        p = Placement.random(position, np.random.default_rng(s))
        m = p.mount()
        assert np.allclose(m.T @ m, np.eye(3), atol=1e-12) and np.isclose(np.linalg.det(m), 1.0)
        assert p == Placement.random(position, np.random.default_rng(s))
        assert all(k.startswith("carry_") for k in p.to_dict())


# ------------------------------------------------------------------ every position x mode
@pytest.mark.parametrize("mode", MOTION_MODES)
def test_every_position_simulates_every_mode(every_position_and_mode, mode):
    recs = every_position_and_mode[mode]
    assert [r.meta["position"] for r in recs] == list(POSITIONS)
    for rec in recs:
        n = rec.n_samples
        assert rec.acc.shape == rec.gyr.shape == (n, 3) and n == 10 * FS
        assert np.isfinite(rec.acc).all() and np.isfinite(rec.gyr).all()
        assert set(np.unique(rec.labels)) == {mode}
        steps = rec.reference["steps"]
        assert len(steps) >= 7 and (steps["mode"] == mode).all() and rec.reference["n_steps_true"] == len(steps)
        assert rec.meta["id"] == f"S01-R1-{rec.meta['position']}"
        q = rec.reference["attitude_wxyz"]
        assert q.shape == (n, 4) and np.allclose(np.linalg.norm(q, axis=1), 1.0)
        mag = np.linalg.norm(rec.acc, axis=1)
        assert 8.5 < mag.mean() < 13.5 and mag.std() > 0.5, (rec.meta["position"], mode)
        if rec.meta["position"] not in ("hand-flat", "hand-tilted"):
            assert rec.meta["carry_side"] in (-1.0, 1.0)


def test_seeds_are_reproducible_and_the_hand_held_path_is_unchanged():
    a = simulate_dataset(2, 12.0, seed=4, positions=("hand-flat", "front-pocket", "bag"))
    b = simulate_dataset(2, 12.0, seed=4, positions=("bag", "front-pocket", "hand-flat"))
    by_id = {r.name: r for r in b}
    for r in a:
        assert np.array_equal(r.acc, by_id[r.name].acc) and np.array_equal(r.gyr, by_id[r.name].gyr)
    legacy = simulate_dataset(2, 12.0, seed=4)
    for old, new in zip(legacy, [r for r in a if r.meta["position"] == "hand-flat"], strict=True):
        assert np.array_equal(old.acc, new.acc) and np.array_equal(old.gyr, new.gyr)
        assert old.reference["steps"].equals(new.reference["steps"])
    # positions are different walks with different phones
    assert not np.array_equal(a[0].acc, a[1].acc)


# ------------------------------------------------------------------ segment physics
def test_pocket_gyro_is_the_thigh_pitch_at_the_stride_frequency():
    rec, p = _walk("front-pocket")
    part = _walking_part(rec)
    gyr = _gyr_unbiased(rec)[part]
    pitch_axis = p.mount().T @ np.array([1.0, 0.0, 0.0])  # the thigh's flexion axis in the phone frame
    rate = gyr @ pitch_axis
    assert rate.var() > 0.7 * gyr.var(axis=0).sum()
    cadence = rec.meta["walk_cadence_hz"]
    assert _dominant_hz(rate) == pytest.approx(cadence / 2, abs=0.15)
    assert np.abs(rate).max() > 1.5  # rad/s: the thigh swings through 30-45 deg at about 1 Hz


def _regularity(rec):
    mag = np.linalg.norm(rec.acc[_walking_part(rec)], axis=1)
    mag = mag - mag.mean()
    lag = int(round(FS / rec.meta["walk_cadence_hz"]))

    def r(k):
        return float(np.dot(mag[:-k], mag[k:]) / np.dot(mag, mag))

    return r(lag), r(2 * lag)


@pytest.mark.parametrize("position", ["front-pocket", "back-pocket"])
def test_one_leg_repeats_per_stride_not_per_step(position):
    """The magnitude of a pocket phone repeats per stride (its own leg), not per step (both legs),
    as in the real Oxford pocket walks (autocorrelation at a stride 0.4-0.7, at a step 0.04-0.3)."""
    r_step, r_stride = _regularity(_walk(position)[0])
    assert r_stride > r_step + 0.2, (r_step, r_stride)
    r_step_hand, r_stride_hand = _regularity(simulate_recording(sample_subjects(1, 1)[0], duration_s=40.0, modes=("walk",), seed=1))
    assert abs(r_stride_hand - r_step_hand) < 0.1


def _stance_pitch_rate(rec, p) -> float:
    """Mean thigh flexion rate (rad/s) over the first 40 % of each stride of the pocket leg."""
    rate = _gyr_unbiased(rec) @ (p.mount().T @ np.array([1.0, 0.0, 0.0]))
    steps = rec.reference["steps"]
    own = steps[steps["foot"] == ("right" if p.side > 0 else "left")]["t_s"].to_numpy()
    vals = []
    for a, b in zip(own[1:-2], own[2:-1], strict=True):
        i, j = int(a * FS), int((a + 0.4 * (b - a)) * FS)
        vals.append(rate[i:j].mean())
    return float(np.mean(vals))


@pytest.mark.parametrize("side", [-1.0, 1.0])
def test_walking_backward_reverses_the_thigh_pattern(side):
    walk, p = _walk("front-pocket", "walk", side=side)
    back, q = _walk("front-pocket", "backward", side=side)
    # forward: the thigh lands flexed and extends in stance; backward: lands extended and flexes
    assert _stance_pitch_rate(walk, p) < -0.3
    assert _stance_pitch_rate(back, q) > 0.3


def test_swinging_hand_swings_at_the_stride_frequency():
    rec, p = _walk("swinging-hand")
    gyr = _gyr_unbiased(rec)[_walking_part(rec)]
    rate = gyr @ (p.mount().T @ np.array([1.0, 0.0, 0.0]))
    assert rate.var() > 0.6 * gyr.var(axis=0).sum()
    assert _dominant_hz(rate) == pytest.approx(rec.meta["walk_cadence_hz"] / 2, abs=0.15)
    assert np.abs(rate).max() > 1.0  # rad/s: a pendulum of 10-25 deg at about 1 Hz


def test_belt_follows_the_pelvis_at_the_step_frequency():
    rec, _ = _walk("belt")
    mag = np.linalg.norm(rec.acc[_walking_part(rec)], axis=1)
    assert _dominant_hz(mag) == pytest.approx(rec.meta["walk_cadence_hz"], abs=0.15)
    gyr = _gyr_unbiased(rec)[_walking_part(rec)]
    assert np.abs(gyr).max() < 2.0  # small pelvis rotations only (and turns)


@pytest.mark.parametrize("position", POSITIONS)
def test_standing_still_the_accelerometer_reads_gravity_in_the_attitude_truth(position):
    """Acc and attitude agree: while the person stands (after 1 s of settling) acc = R^T g."""
    recs = simulate_dataset(1, 40.0, ("walk", "run"), seed=6, positions=(position,), pauses=True, segment_s=(6.0, 8.0))
    rec = recs[0]
    stand = rec.labels == "stand"
    settled = stand & np.concatenate([np.zeros(int(FS), bool), stand[: -int(FS)]])
    assert settled.sum() > FS
    q = rec.reference["attitude_wxyz"][settled]
    g_phone = Rotation.from_quat(q[:, [1, 2, 3, 0]]).inv().apply([0.0, 0.0, GRAVITY_MS2])
    err = np.linalg.norm(rec.acc[settled] - g_phone, axis=1)
    assert np.median(err) < 0.4, np.median(err)
    # and the check can fail: the attitude read the wrong way round (R instead of R^T) does not fit
    g_wrong = Rotation.from_quat(q[:, [1, 2, 3, 0]]).apply([0.0, 0.0, GRAVITY_MS2])
    assert np.median(np.linalg.norm(rec.acc[settled] - g_wrong, axis=1)) > 1.0


def _integration_error(rec, gyr, seconds: float = 1.0) -> float:
    """Largest angle (rad) between the attitude truth and the integrated gyro over windows of ``seconds``."""
    q = rec.reference["attitude_wxyz"]
    truth = Rotation.from_quat(q[:, [1, 2, 3, 0]])
    m = int(seconds * FS)
    worst = 0.0
    for start in range(int(3 * FS), rec.n_samples - m, int(2.3 * FS)):
        r = truth[start]
        for k in range(start, start + m):
            r = r * Rotation.from_rotvec(0.5 * (gyr[k] + gyr[k + 1]) / FS)
        worst = max(worst, float((truth[start + m].inv() * r).magnitude()))
    return worst


@pytest.mark.parametrize("position", POSITIONS)
def test_integrating_the_gyro_reproduces_the_attitude(position):
    if position.startswith("hand"):
        subj = sample_subjects(1, 2, pose=position.split("-")[1])[0]
        rec = simulate_recording(subj, duration_s=20.0, seed=2, modes=("walk", "side_left"), segment_s=(8, 9))
    else:
        subj = sample_subjects(1, 2)[0]
        p = Placement.random(position, np.random.default_rng(2))
        rec = simulate_recording(subj, duration_s=20.0, seed=2, modes=("walk", "side_left"), segment_s=(8, 9), placement=p)
    gyr = _gyr_unbiased(rec)
    assert _integration_error(rec, gyr) < 0.06
    # and the check can fail: a gyro in the wrong frame does not reproduce the attitude
    assert _integration_error(rec, -gyr) > 0.1


# ------------------------------------------------------------------ outputs, CLI, config
def test_manifest_and_meta_carry_the_position(tmp_path):
    from gaitml.io import read_dataset

    recs = simulate_dataset(1, 10.0, ("walk", "run"), seed=0, positions="front_pocket,hand-flat")
    write_simulation(recs, tmp_path)
    man = pd.read_csv(tmp_path / "manifest.csv")
    assert man["position"].tolist() == ["front-pocket", "hand-flat"]
    assert man["file"].tolist() == ["S01-R1-front-pocket.csv", "S01-R1-hand-flat.csv"]
    assert man.loc[0, "carry_side"] in (-1, 1) and np.isnan(man.loc[1, "carry_side"])
    back = {r.meta["position"] for r in read_dataset(tmp_path)}
    assert back == {"front-pocket", "hand-flat"}


def test_route_in_a_position():
    a = simulate_route("rectangle", seed=3, modes=("walk",), position="back-pocket")
    b = simulate_route("rectangle", seed=3, modes=("walk",))
    assert a.meta["position"] == "back-pocket" and b.meta["position"] == "hand-flat"
    assert a.reference["steps"].equals(b.reference["steps"])  # the same walk, another phone
    assert not np.allclose(a.acc, b.acc)


def test_cli_simulate_positions(tmp_path, capsys):
    out = tmp_path / "sim"
    assert main(["simulate", str(out), "--subjects", "1", "--duration-s", "8", "--modes", "walk", "--positions", "front_pocket,belt"]) == 0
    capsys.readouterr()
    man = pd.read_csv(out / "manifest.csv")
    assert man["position"].tolist() == ["front-pocket", "belt"]
    bad = tmp_path / "bad"
    assert main(["simulate", str(bad), "--positions", "front-pocket,pocket"]) == 2
    lines = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert len(lines) == 1 and "'pocket'" in lines[0] and "front-pocket, back-pocket, belt, swinging-hand, bag" in lines[0]
    assert not bad.exists()


def test_config_key_is_validated(tmp_path):
    from gaitml.pipeline import parse_config, prepare_data

    raw = {
        "name": "pos",
        "data": {"simulated": {"subjects": 2, "duration_s": 16.0, "modes": ["walk", "run"], "positions": ["hand-flat", "belt"]}},
    }
    cfg = parse_config(raw, base_dir=tmp_path)
    assert cfg["data"]["simulated"]["positions"] == ["hand-flat", "belt"]
    data = prepare_data(cfg, use_cache=False)
    assert sorted(r.meta["position"] for r in data.recordings) == ["belt", "belt", "hand-flat", "hand-flat"]
    assert parse_config({"name": "x"}, base_dir=tmp_path)["data"]["simulated"]["positions"] == []
    raw["data"]["simulated"]["positions"] = ["belt", "pocket"]
    with pytest.raises(ConfigError, match=r"data.simulated.positions.*'pocket'") as exc:
        parse_config(raw, base_dir=tmp_path)
    assert "\n" not in str(exc.value) and "front-pocket" in str(exc.value)
