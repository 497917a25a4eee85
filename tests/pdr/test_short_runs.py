"""The short-run rule: side or backward runs too short to be a bout move forward (gaitml.pdr.step_modes.forward_short_runs)."""

from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from gaitml.errors import InputError
from gaitml.pdr.step_modes import SHORT_RUN_WINDOWS, forward_short_runs

from .synth import synth_walk

WINDOW_S = 1.5


def modes_of(spec):
    """``[("walk", 5), ("backward", 2), ...]`` -> per-step modes."""
    return np.concatenate([[m] * n for m, n in spec])


def test_a_run_shorter_than_one_window_between_forward_steps_moves_forward():
    # 2 steps/s: one 1.5 s window holds 3 steps; a 2-step backward run between walks is two switches within a window
    modes = modes_of([("walk", 6), ("backward", 2), ("walk", 6)])
    t = np.arange(len(modes)) * 0.5
    out, moved = forward_short_runs(modes, t, WINDOW_S, 1.0)
    assert moved == 2 and set(out) == {"walk"}
    # one window's steps or more is a bout: kept
    for n in (3, 10):
        modes = modes_of([("walk", 6), ("side_left", n), ("walk", 6)])
        out, moved = forward_short_runs(modes, np.arange(len(modes)) * 0.5, WINDOW_S, 1.0)
        assert moved == 0 and (out == modes).all()


def test_the_walkers_interval_not_the_runs_span_decides():
    """Two shuffling steps at a stop span the standing between them; they are still two steps, fewer than a window's."""
    modes = modes_of([("walk", 8), ("backward", 2), ("walk", 8)])
    t = np.arange(len(modes)) * 0.5
    t[8:] += 1.5  # a stop before the run
    t[9:] += 1.5  # and between its two steps
    out, moved = forward_short_runs(modes, t, WINDOW_S, 1.0)
    assert moved == 2 and set(out) == {"walk"}


def test_only_runs_between_forward_steps_move_and_they_take_the_mode_before():
    # walk | backward x2 | run: the left neighbour's mode
    modes = modes_of([("walk", 5), ("backward", 2), ("run", 5)])
    out, _ = forward_short_runs(modes, np.arange(len(modes)) * 0.5, WINDOW_S, 1.0)
    assert out.tolist() == ["walk"] * 7 + ["run"] * 5
    # at the start or the end (one switch), or beside another side/backward run: left alone
    for spec in (
        [("backward", 2), ("walk", 8)],
        [("walk", 8), ("side_right", 2)],
        [("walk", 5), ("backward", 2), ("side_left", 6), ("walk", 5)],
    ):
        modes = modes_of(spec)
        out, moved = forward_short_runs(modes, np.arange(len(modes)) * 0.5, WINDOW_S, 1.0)
        assert moved == 0 and (out == modes).all()


def test_zero_windows_is_off_and_bad_input_is_refused():
    modes = modes_of([("walk", 6), ("backward", 1), ("walk", 6)])
    t = np.arange(len(modes)) * 0.5
    out, moved = forward_short_runs(modes, t, WINDOW_S, 0.0)
    assert moved == 0 and (out == modes).all()
    assert forward_short_runs(modes, t, WINDOW_S)[1] == (1 if SHORT_RUN_WINDOWS > 0.5 else 0)
    with pytest.raises(InputError, match="one mode per step"):
        forward_short_runs(modes, t[:-1], WINDOW_S, 1.0)
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(InputError, match="min_windows"):
            forward_short_runs(modes, t, WINDOW_S, bad)


def _fake_windows(t_end: float, backward: tuple[float, float]) -> pd.DataFrame:
    """1.5 s windows every 0.75 s, read ``walk`` except ``backward`` where their centre falls in the given span."""
    start = np.arange(0.0, t_end - 1.5, 0.75)
    centre = start + 0.75
    mode = np.where((centre >= backward[0]) & (centre <= backward[1]), "backward", "walk")
    return pd.DataFrame({"t_start_s": start, "t_end_s": start + 1.5, "mode_raw": mode, "mode": mode})


def test_run_pdr_moves_a_short_backward_run_forward_counts_it_and_says_so(monkeypatch):
    import gaitml.models
    from gaitml.pdr import run_pdr

    rec = synth_walk([("walk", 40, 0.0)], period_s=0.5)
    model = SimpleNamespace(length_s=1.5, window_by="time", domain=None, labels=["walk", "backward"])
    windows = _fake_windows(rec.duration_s, (9.6, 10.2))  # covers the steps nearest one window: 1-2 steps
    monkeypatch.setattr(gaitml.models, "predict_recording", lambda *a, **k: windows)
    kw = {"model": model, "modes": "model", "detector": "single-peak", "mode_boundaries": "nearest", "gyro_bias": "off"}
    off = run_pdr(rec, short_run_windows=0, **kw)
    n_back = int((off.steps["mode"] == "backward").sum())
    assert 1 <= n_back < 3 and off.info["short_run_steps"] == 0
    on = run_pdr(rec, short_run_windows=1, **kw)
    assert not (on.steps["mode"] == "backward").any()
    assert on.info["short_run_steps"] == n_back and on.to_json_dict()["short_run_steps"] == n_back
    assert any("moved forward" in note for note in on.info["notes"])
    # moved forward, the path is the forward-only one's length along the heading: it ends further from the start
    assert np.hypot(*on.end_xy_m) > np.hypot(*off.end_xy_m)
    with pytest.raises(InputError, match="short_run_windows"):
        run_pdr(rec, short_run_windows=-1, **kw)
    # without model modes there is nothing to move: no count
    assert run_pdr(rec, modes="forward", detector="single-peak").info["short_run_steps"] is None


def test_cli_refuses_a_bad_short_runs_value(capsys):
    from gaitml.cli import main

    assert main(["pdr", "nowhere.csv", "--short-runs", "-1"]) == 2
    err = capsys.readouterr().err
    assert "--short-runs" in err and err.count("\n") == 1


def test_a_short_run_setting_that_cannot_act_says_so(monkeypatch, tmp_path):
    """``short_run_windows`` > 0 where there are no window modes to read (modes 'forward' or 'true', a step-window
    model) changes nothing, and a note says so rather than leaving the setting silently unused."""
    import gaitml.pdr.pipeline as pp
    from gaitml.chunked_run import long_pdr
    from gaitml.io import write_gaitml_csv
    from gaitml.pdr import run_pdr

    rec = synth_walk([("walk", 20, 0.0)], period_s=0.5)
    kw = {"detector": "single-peak", "gyro_bias": "off"}
    for modes in ("forward", "true"):
        off = run_pdr(rec, modes=modes, **kw)
        on = run_pdr(rec, modes=modes, short_run_windows=1, **kw)
        assert on.info["short_run_steps"] is None and (on.steps["mode"] == off.steps["mode"]).all()
        assert not any("short_run_windows" in n for n in off.info["notes"])
        assert sum("short_run_windows" in n and "no effect" in n for n in on.info["notes"]) == 1
    # a step-window model gives each step its own mode: nothing for the rule to read
    model = SimpleNamespace(length_s=1.5, window_by="steps", domain=None, labels=["walk", "backward"])

    def per_step(model, recording, steps, **k):
        n = len(steps)
        return np.array(["walk"] * n, dtype=object), "per-step modes", [None] * n, [""] * n

    monkeypatch.setattr(pp, "modes_from_step_model", per_step)
    on = run_pdr(rec, model=model, modes="model", short_run_windows=1, **kw)
    assert on.info["short_run_steps"] is None
    assert sum("short_run_windows" in n and "no effect" in n for n in on.info["notes"]) == 1
    # the chunked road says the same
    p = tmp_path / "walk.csv"
    write_gaitml_csv(rec, p)
    chunked = long_pdr(p, modes="forward", short_run_windows=1, chunk_s=30.0, margin_s=5.0, progress=False, **kw)
    assert sum("short_run_windows" in n and "no effect" in n for n in chunked.info["notes"]) == 1
