"""HDE's structure guard (gaitml.pdr.hde, module Notes step 6; issue 27).

A walk without dominant directions (a loop round a room: the heading turns all the time) lies
outside HDE's premise: its whole-recording rate fit lines the headings up by chance and removes a
made-up rate. The guard holds HDE off there (the gyro heading is kept, and the outputs say so),
lets it correct a corridor route's drift exactly as without the guard, and holds it off below the
minimum step count. ``--hde-guard off`` gives HDE without the guard, computed here from its parts.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from gaitml.cli import main
from gaitml.io import write_gaitml_csv
from gaitml.pdr import run_pdr
from gaitml.pdr.attitude import wrap_angle
from gaitml.pdr.hde import (
    STRUCTURE_ALPHA,
    STRUCTURE_MIN_STEPS,
    HeuristicDriftElimination,
    direction_structure,
    estimate_drift_rate,
    hde_correct,
    hde_heading,
)
from gaitml.pdr.update import forward_update
from tests.pdr.synth import synth_walk

#: z gyro bias of the synthetic walks (rad/s): 34 deg/min of heading drift, an uncalibrated phone gyro
BIAS_RADS = 0.01
#: warning line of a held-off HDE (gaitml.commands.pdr._warn_heading_check)
WARNING = "gaitml: warning: HDE not applied"


def _loop_recording(seed: int, n: int = 160):
    """A walker turning 0.2-0.5 rad after every step (a loop round a room every ~4 m), with a gyro bias."""
    turns = np.random.default_rng(seed).uniform(0.2, 0.5, n)
    legs = [("walk", 1, float(x)) for x in turns]
    return synth_walk(legs, gyro_bias_rads=(0.0, 0.0, BIAS_RADS), noise=0.05, turn_s=0.1)


def _corridor_recording():
    """Four 30-step legs round a rectangle (turns of 90 deg), with the same gyro bias."""
    legs = [("walk", 30, np.pi / 2)] * 4
    return synth_walk(legs, gyro_bias_rads=(0.0, 0.0, BIAS_RADS), noise=0.05)


def _heading_drift_deg_min(res, rec) -> float:
    """Slope of the step heading's error against the true heading (deg/min)."""
    st, ref = res.steps, rec.reference["steps"]
    t = st[st.attrs.get("event", "t_peak_s")].to_numpy(float)
    truth = np.interp(t, ref["t_s"].to_numpy(float), np.unwrap(ref["heading_rad"].to_numpy(float)))
    err = np.unwrap(wrap_angle(st["heading_rad"].to_numpy(float) - truth))
    return float(np.polyfit(t, err, 1)[0] * 180 / np.pi * 60)


def _pdr(rec, **kw):
    return run_pdr(rec, modes="forward", gyro_bias="off", **kw)


def _unguarded():
    return HeuristicDriftElimination(structure_alpha=None)


# ---- the library: hde_heading / HeuristicDriftElimination


@pytest.mark.parametrize("seed", [1, 2])
def test_loop_walk_with_drift_guarded_heading_drifts_no_more_than_the_gyro(seed):
    rec = _loop_recording(seed)
    gyro = _pdr(rec, heading="gyro")
    guarded = _pdr(rec)
    unguarded = _pdr(rec, hde=_unguarded())
    assert gyro.n_steps == guarded.n_steps >= 150
    d_gyro, d_guarded, d_off = (abs(_heading_drift_deg_min(r, rec)) for r in (gyro, guarded, unguarded))
    # without the guard HDE removes a rate it made up: the heading drifts more than the gyro's own
    assert d_off > d_gyro + 5.0
    check = guarded.info["heading_check"]
    assert check["guard"] == "on" and not check["hde_applied"] and check["reason"] == "no dominant directions"
    assert check["statistic"] <= check["threshold"]
    assert d_guarded <= d_gyro + 0.1
    np.testing.assert_array_equal(guarded.steps["heading_rad"].to_numpy(), wrap_angle(gyro.steps["heading_rad"].to_numpy()))


def test_corridor_route_with_drift_is_still_corrected_as_without_the_guard():
    rec = _corridor_recording()
    gyro = _pdr(rec, heading="gyro")
    guarded = _pdr(rec)
    unguarded = _pdr(rec, hde=_unguarded())
    check = guarded.info["heading_check"]
    assert check["hde_applied"] and check["structured"] and check["statistic"] > 2 * check["threshold"]
    np.testing.assert_array_equal(guarded.trajectory[["x_m", "y_m"]].to_numpy(), unguarded.trajectory[["x_m", "y_m"]].to_numpy())
    assert abs(_heading_drift_deg_min(guarded, rec)) < 0.25 * abs(_heading_drift_deg_min(gyro, rec))


def test_a_recording_below_the_minimum_step_count_is_not_corrected_and_says_so():
    n = STRUCTURE_MIN_STEPS - 3
    raw = np.deg2rad(np.linspace(0.0, 20.0, n))  # a straight stretch drifting by 2 deg a step: a rate fit would take it
    t = np.arange(n) * 0.5
    h, corr, straight, rate, check = hde_heading(raw, np.full(n, 0.5), t)
    assert not check["hde_applied"] and check["reason"] == "too few steps" and check["n_steps"] == n
    np.testing.assert_array_equal(h, wrap_angle(raw))
    assert rate == 0.0 and not corr.any() and not straight.any()
    # the same headings with the guard off are corrected (the rate fit takes the 2 deg a step out)
    h_off, _, _, rate_off, check_off = hde_heading(raw, np.full(n, 0.5), t, structure_alpha=None)
    assert check_off["guard"] == "off" and check_off["hde_applied"] and rate_off != 0.0
    assert not np.array_equal(h_off, wrap_angle(raw))


def test_guard_off_is_hde_from_its_parts():
    rec = _loop_recording(2)
    gyro_h = _pdr(rec, heading="gyro").steps
    psi, t = gyro_h["heading_rad"].to_numpy(float), gyro_h["t_peak_s"].to_numpy(float)
    dur = (gyro_h["end"].to_numpy() - gyro_h["start"].to_numpy()) / rec.sampling_rate_hz
    rate = estimate_drift_rate(psi, t)
    expected = hde_correct(psi - rate * (t - t[0]), dur)[0]
    np.testing.assert_array_equal(hde_heading(psi, dur, t, structure_alpha=None)[0], expected)
    np.testing.assert_array_equal(hde_heading(psi, dur, t, structure_alpha=0)[0], expected)


def test_bad_guard_settings_are_refused():
    from gaitml.errors import InputError

    with pytest.raises(InputError, match="structure_alpha"):
        hde_heading(np.zeros(20), structure_alpha=1.5)
    with pytest.raises(InputError, match="structure_min_steps"):
        hde_heading(np.zeros(20), structure_min_steps=-1)
    with pytest.raises(InputError, match="structure_alpha"):
        _pdr(_corridor_recording(), hde=HeuristicDriftElimination(structure_alpha=-0.1))


def test_headings_without_structure_pass_at_most_about_alpha():
    rng = np.random.default_rng(0)
    t = np.arange(150) * 0.5
    hits = 0
    for _ in range(300):
        u = rng.uniform(-np.pi, np.pi, len(t))
        hits += direction_structure(u, t, estimate_drift_rate(u, t))["structured"]
    # the union bound is conservative: at most alpha in expectation; 300 draws leave room for 3 sd
    assert hits / 300 <= STRUCTURE_ALPHA + 3 * np.sqrt(STRUCTURE_ALPHA / 300)


def test_the_threshold_grows_with_the_scanned_rates_and_shrinks_with_steps():
    a = direction_structure(np.zeros(100), np.arange(100) * 0.5)
    b = direction_structure(np.zeros(400), np.arange(400) * 0.5)
    assert a["structured"] and a["statistic"] == 1.0
    assert b["n_rates"] > a["n_rates"] and b["threshold"] < a["threshold"]
    assert not direction_structure([], [])["structured"]
    # the same perfect alignment on fewer steps than the minimum is not enough
    assert not direction_structure(np.zeros(STRUCTURE_MIN_STEPS - 1), np.arange(STRUCTURE_MIN_STEPS - 1) * 0.5)["structured"]


# ---- the command line: gaitml pdr


@pytest.fixture(scope="module")
def loop_file(tmp_path_factory):
    p = tmp_path_factory.mktemp("hdeguard") / "loop.csv"
    write_gaitml_csv(_loop_recording(2), p)
    return p


def _run(capsys, *argv):
    assert main(["pdr", *map(str, argv)]) == 0
    return capsys.readouterr()


def test_cli_json_key_and_one_warning_line_when_hde_is_held_off(loop_file, capsys):
    out = _run(capsys, loop_file, "--modes", "forward", "--gyro-bias", "off", "--json")
    check = json.loads(out.out)["heading_check"]
    assert check["guard"] == "on" and check["hde_applied"] is False and check["structured"] is False
    assert check["statistic"] <= check["threshold"] and check["n_steps"] >= 150
    lines = [ln for ln in out.err.splitlines() if "HDE not applied" in ln]
    assert len(lines) == 1 and lines[0].startswith(WARNING)
    assert "--heading gyro" in lines[0] and "--hde-guard off" in lines[0]
    text = _run(capsys, loop_file, "--modes", "forward", "--gyro-bias", "off")
    assert "heading check: HDE not applied, gyro heading kept (no dominant directions" in text.out
    assert sum("HDE not applied" in ln for ln in text.err.splitlines()) == 1


def test_cli_hde_guard_off_restores_hde_without_the_guard(loop_file, capsys):
    from gaitml.io import read_recording

    out = _run(capsys, loop_file, "--modes", "forward", "--gyro-bias", "off", "--hde-guard", "off", "--json")
    obj = json.loads(out.out)
    assert "HDE not applied" not in out.err
    assert obj["heading_check"]["guard"] == "off" and obj["heading_check"]["hde_applied"] is True
    # HDE before the guard, from its parts: the rate fit and the buffered feedback on the gyro step headings
    rec = read_recording(loop_file)
    ref = rec.reference.get("trajectory")
    h0 = 0.0 if ref is None else float(ref["heading_rad"].iloc[0])  # the CLI's start heading
    st = _pdr(rec, heading="gyro", initial_heading_rad=h0).steps
    psi, t = st["heading_rad"].to_numpy(float), st["t_peak_s"].to_numpy(float)
    dur = np.maximum(st["end"].to_numpy() - st["start"].to_numpy(), 1) / rec.sampling_rate_hz
    rate = estimate_drift_rate(psi, t, reference_rad=h0)
    theta = hde_correct(psi - rate * (t - t[0]), dur, reference_rad=h0)[0]
    xy = forward_update(st["step_length_m"].to_numpy(float), theta)
    got = np.array([[r["x_m"], r["y_m"]] for r in obj["trajectory"]])
    np.testing.assert_array_equal(got, xy)
    guarded = json.loads(_run(capsys, loop_file, "--modes", "forward", "--gyro-bias", "off", "--json").out)
    assert guarded["trajectory"] != obj["trajectory"]


def test_cli_short_recording_is_not_corrected_and_says_why(tmp_path, capsys):
    p = tmp_path / "short.csv"
    write_gaitml_csv(synth_walk([("walk", STRUCTURE_MIN_STEPS - 4, 0.0)], gyro_bias_rads=(0.0, 0.0, BIAS_RADS)), p)
    out = _run(capsys, p, "--modes", "forward", "--gyro-bias", "off")
    assert f"fewer than {STRUCTURE_MIN_STEPS} steps" in out.out
    lines = [ln for ln in out.err.splitlines() if "HDE not applied" in ln]
    assert len(lines) == 1 and f"fewer than the {STRUCTURE_MIN_STEPS} it needs" in lines[0]


def test_cli_gyro_heading_has_no_heading_check(loop_file, capsys):
    out = _run(capsys, loop_file, "--modes", "forward", "--heading", "gyro", "--json")
    assert "heading_check" not in json.loads(out.out)
    assert "HDE not applied" not in out.err


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: direction_structure([0.0, np.nan] + [0.0] * 20, np.arange(22.0)), "NaN"),
        (lambda: direction_structure(np.zeros(30), np.arange(30.0)[::-1]), "must not decrease"),
        (lambda: direction_structure(np.zeros(30), np.arange(30.0), alpha=None), "alpha"),
        (lambda: direction_structure(np.zeros(30), np.arange(30.0), min_steps=2.5), "min_steps"),
        (lambda: hde_heading(np.zeros(30), np.full(30, 0.5), np.arange(30.0)[::-1]), "must not decrease"),
        (lambda: hde_heading(np.zeros(20), structure_min_steps=None), "structure_min_steps"),
        (lambda: hde_heading(np.zeros(20), structure_min_steps=np.nan), "structure_min_steps"),
        (lambda: hde_heading(np.zeros(20), structure_alpha="a"), "structure_alpha"),
    ],
)
def test_bad_guard_input_is_one_line_error_not_a_silent_verdict(call, match):
    """NaN headings or step times out of order would give a NaN statistic or threshold (held off, no error);
    settings that are not numbers would raise a bare TypeError/ValueError."""
    from gaitml.errors import InputError

    with pytest.raises(InputError, match=match):
        call()


@pytest.mark.parametrize("heading", ["gyro", "dwpca"])
def test_cli_hde_guard_off_without_hde_says_it_changes_nothing(loop_file, capsys, heading):
    base = _run(capsys, loop_file, "--modes", "forward", "--heading", heading, "--json")
    out = _run(capsys, loop_file, "--modes", "forward", "--heading", heading, "--hde-guard", "off", "--json")
    assert json.loads(out.out)["trajectory"] == json.loads(base.out)["trajectory"]
    lines = [ln for ln in out.err.splitlines() if "--hde-guard off has no effect" in ln]
    assert len(lines) == 1 and f"--heading {heading}" in lines[0]
    assert "--hde-guard" not in base.err


def test_cli_long_file_read_in_chunks_makes_the_whole_files_decision(loop_file, capsys, monkeypatch):
    """The guard reads all steps of a long file at once (chunked_run.long_pdr), so it holds HDE off as a
    whole-file run does, with the same statistic (the chunked heading moves a step by < 1e-4 rad), one warning."""
    import gaitml.chunked_run as cr
    import gaitml.io.chunked as ch

    argv = (loop_file, "--modes", "forward", "--gyro-bias", "off", "--detector", "single-peak", "--json")
    whole = _run(capsys, *argv)
    monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", 1000)
    monkeypatch.setattr(cr, "DEFAULT_CHUNK_S", 30.0)
    monkeypatch.setattr(cr, "DEFAULT_MARGIN_S", 5.0)
    long = _run(capsys, *argv)
    a, b = json.loads(whole.out)["heading_check"], json.loads(long.out)["heading_check"]
    assert "is long: read in chunks" in long.err and "is long" not in whole.err
    assert set(a) == set(b) and a["hde_applied"] is b["hde_applied"] is False and a["n_steps"] == b["n_steps"]
    assert b["statistic"] == pytest.approx(a["statistic"], abs=1e-4) and b["threshold"] == a["threshold"]
    assert (
        sum("HDE not applied" in ln for ln in long.err.splitlines()) == sum("HDE not applied" in ln for ln in whole.err.splitlines()) == 1
    )


def test_cli_one_step_recording_is_not_corrected_and_says_one_step(tmp_path, capsys):
    p = tmp_path / "one.csv"
    write_gaitml_csv(synth_walk([("walk", 1, 0.0)]), p)
    out = _run(capsys, p, "--modes", "forward", "--detector", "single-peak")
    guard_lines = [ln for ln in (out.out + out.err).splitlines() if "heading check" in ln or "HDE not applied" in ln]
    assert len(guard_lines) == 2 and not any("1 steps" in ln for ln in guard_lines)
    assert f"(fewer than {STRUCTURE_MIN_STEPS} steps: 1 step)" in out.out
    assert "only 1 step, fewer than" in out.err
