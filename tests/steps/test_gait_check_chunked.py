"""The gait-evidence test on long inputs read in chunks, and its account in every command that detects steps.

`gaitml steps` on a long input runs the test per chunk (as on a whole file) and sums the account over the
chunks' core steps; `gaitml pdr`, `label` and `segment` say, in one stderr note and a JSON field
``gait_check``, how many steps their default detector left out.

Bound on chunked vs whole-file counts: a bout of steps lying within a chunk margin of a chunk edge is tested
on the same steps as on the whole file, so the counts are equal when the margins are longer than the bouts
and than ``adaptive``'s cadence windows (its cadence is what other detectors are tested at). The gesture
bursts of the simulator last seconds and its walks here are cut into segments of 8-20 s; 10 s margins hold
them, and the counts below must be equal. (The opt-in short-bout rule, ``confirm_bout_steps``, is reachable from
Python's ``gait_check`` only: no chunked run applies it, so its 30 s context does not bound the margins here.)
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import gaitml.chunked_run as cr
import gaitml.io.chunked as ch
from gaitml.chunked_run import long_steps
from gaitml.cli import main
from gaitml.io import read_recording, write_gaitml_csv
from gaitml.simulate import simulate_dataset
from gaitml.simulate.nongait import simulate_nongait
from gaitml.steps import get_detector
from gaitml.steps._gait_evidence import gait_check_recording

CHUNK_S, MARGIN_S = 20.0, 10.0


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("gaitchunk")
    out = {}
    for name, rec in (
        ("gestures", simulate_nongait("gestures", seed=100)),
        ("walk", simulate_dataset(1, 120.0, sampling_rate_hz=50.0, seed=3)[0]),
    ):
        p = d / f"{name}.csv"
        write_gaitml_csv(rec, p)
        out[name] = p
    return out


def _whole(path, detector, gait):
    rec = read_recording(path)
    if detector == "adaptive":
        return get_detector("adaptive", gait_check=gait).detect(rec).steps_
    steps = get_detector(detector).detect(rec).steps_
    return gait_check_recording(steps, rec) if gait else steps


ACCOUNT_COUNTS = ("tested", "n_bouts", "n_bouts_rejected", "n_steps_rejected")


@pytest.mark.parametrize("name", ["gestures", "walk"])
@pytest.mark.parametrize(("detector", "gait"), [("adaptive", True), ("adaptive", False), ("single-peak", True)])
def test_chunked_gait_check_equals_whole_file(files, name, detector, gait):
    whole = _whole(files[name], detector, gait)
    chunked = long_steps(files[name], detector, chunk_s=CHUNK_S, margin_s=MARGIN_S, progress=False, gait_check=gait)
    np.testing.assert_array_equal(chunked["peak"].to_numpy(), whole["peak"].to_numpy())
    if not gait:
        assert "gait_check" not in chunked.attrs
        return
    a, b = whole.attrs["gait_check"], chunked.attrs["gait_check"]
    assert {k: b[k] for k in ACCOUNT_COUNTS} == {k: a[k] for k in ACCOUNT_COUNTS}
    np.testing.assert_allclose(b["rejected_t_s"], a["rejected_t_s"], atol=1e-9)
    if name == "gestures":  # the test has something to find here: most gesture "steps" go
        assert b["n_steps_rejected"] > len(chunked)


def test_chunked_steps_refuse_the_python_only_short_bout_rule(files):
    """The opt-in short-bout rule (gait_check's confirm_bout_steps) is not applied in chunks: naming it is refused
    with an error that says so and how to apply it, before anything is read."""
    from gaitml.errors import InputError

    for key, value in (("confirm_bout_steps", 10), ("context_s", 30.0)):
        with pytest.raises(InputError, match=f"{key}: .*not available in a chunked run.*gait_check"):
            long_steps(files["gestures"], "adaptive", chunk_s=CHUNK_S, margin_s=MARGIN_S, progress=False, detector_params={key: value})


def test_chunked_steps_default_follows_the_detector(files):
    """None: on for adaptive (its own default), off for the paper detectors (run as published)."""
    assert "gait_check" in long_steps(files["gestures"], "adaptive", chunk_s=CHUNK_S, margin_s=MARGIN_S, progress=False).attrs
    assert "gait_check" not in long_steps(files["gestures"], "single-peak", chunk_s=CHUNK_S, margin_s=MARGIN_S, progress=False).attrs


def _force_long(monkeypatch):
    monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", 1000)
    monkeypatch.setattr(cr, "DEFAULT_CHUNK_S", CHUNK_S)
    monkeypatch.setattr(cr, "DEFAULT_MARGIN_S", MARGIN_S)


@pytest.mark.parametrize("extra", [[], ["--no-gait-check"], ["--detector", "single-peak", "--gait-check"]])
def test_steps_cli_long_path_says_what_the_whole_file_path_says(files, monkeypatch, capsys, extra):
    path = str(files["gestures"])
    assert main(["steps", path, "--json", *extra]) == 0
    cap = capsys.readouterr()
    a, a_err = json.loads(cap.out), cap.err
    assert main(["steps", path, *extra]) == 0
    a_text = capsys.readouterr().out
    _force_long(monkeypatch)
    assert main(["steps", path, "--json", *extra]) == 0
    cap = capsys.readouterr()
    b, b_err = json.loads(cap.out), cap.err
    assert b["chunked"] and b["n_steps"] == a["n_steps"]
    assert ("gait_check" in b) == ("gait_check" in a) == ("--no-gait-check" not in extra)
    notes = [line for line in b_err.splitlines() if line.startswith("gaitml: note:") and "gait evidence" in line]
    assert notes == [line for line in a_err.splitlines() if line.startswith("gaitml: note:") and "gait evidence" in line]
    if "gait_check" in a:
        assert {k: b["gait_check"][k] for k in ACCOUNT_COUNTS} == {k: a["gait_check"][k] for k in ACCOUNT_COUNTS}
        assert len(notes) == 1 and f"{a['gait_check']['n_steps_rejected']} steps" in notes[0]
    # the confident / unsure verdict reads the global step table: the whole file's
    assert ("gait_confidence" in b) == ("gait_confidence" in a)
    if "gait_confidence" in a:
        assert (b["n_confident"], b["n_unsure"]) == (a["n_confident"], a["n_unsure"])
        assert [s["confident"] for s in b["steps"]] == [s["confident"] for s in a["steps"]]
        unsure = [line for line in a_err.splitlines() if "unsure" in line or "no confident gait" in line]
        assert unsure == [line for line in b_err.splitlines() if "unsure" in line or "no confident gait" in line]
    assert main(["steps", path, *extra]) == 0
    b_text = capsys.readouterr().out
    for key in ("gait check:", " confident, "):
        assert [line for line in a_text.splitlines() if key in line] == [line for line in b_text.splitlines() if key in line]


def _gait_notes(err: str) -> list[str]:
    return [line for line in err.splitlines() if line.startswith("gaitml: note:") and "without gait evidence" in line]


def _command(cmd, path, tmp_path):
    if cmd == "pdr":
        return ["pdr", str(path), "--modes", "forward"]
    if cmd == "segment":
        return ["segment", str(path), "--out", str(tmp_path / "seg.csv")]
    iv = tmp_path / "iv.csv"
    iv.write_text("start_s,end_s,label\n0,60,stand\n60,120,talk\n")
    return ["label", str(path), "--intervals", str(iv), "--out", str(tmp_path / "lab.csv")]


@pytest.mark.parametrize("cmd", ["pdr", "label", "segment"])
def test_commands_say_when_the_default_detector_left_steps_out(files, tmp_path, capsys, cmd):
    """The default detector (adaptive, gait check on) leaves the gesture bursts out: one stderr note, a JSON field."""
    whole = _whole(files["gestures"], "adaptive", True).attrs["gait_check"]
    assert whole["n_steps_rejected"] > 0
    assert main([*_command(cmd, files["gestures"], tmp_path), "--json"]) == 0
    cap = capsys.readouterr()
    obj = json.loads(cap.out)
    assert {k: obj["gait_check"][k] for k in ACCOUNT_COUNTS} == {k: whole[k] for k in ACCOUNT_COUNTS}
    np.testing.assert_allclose(obj["gait_check"]["rejected_t_s"], whole["rejected_t_s"])
    notes = _gait_notes(cap.err)
    assert len(notes) == 1 and f"{whole['n_steps_rejected']} steps in {whole['n_bouts_rejected']} of {whole['n_bouts']} bouts" in notes[0]
    assert main(_command(cmd, files["gestures"], tmp_path)) == 0  # the text output notes it too
    assert len(_gait_notes(capsys.readouterr().err)) == 1
    # a walk keeps every step: the JSON says so, and no note
    assert main([*_command(cmd, files["walk"], tmp_path), "--json"]) == 0
    cap = capsys.readouterr()
    assert json.loads(cap.out)["gait_check"]["n_steps_rejected"] == 0 and not _gait_notes(cap.err)


@pytest.mark.parametrize("cmd", ["pdr", "segment"])
def test_a_detector_without_the_test_reports_none(files, tmp_path, capsys, cmd):
    assert main([*_command(cmd, files["gestures"], tmp_path), "--detector", "single-peak", "--json"]) == 0
    cap = capsys.readouterr()
    assert "gait_check" not in json.loads(cap.out) and not _gait_notes(cap.err)


def test_pdr_long_path_sums_the_account_over_the_chunks(files, monkeypatch, capsys):
    argv = ["pdr", str(files["gestures"]), "--modes", "forward", "--json"]
    assert main(argv) == 0
    a = json.loads(capsys.readouterr().out)
    _force_long(monkeypatch)
    assert main(argv) == 0
    cap = capsys.readouterr()
    b = json.loads(cap.out)
    assert "read in chunks" in cap.err and b["n_steps"] == a["n_steps"]
    assert {k: b["gait_check"][k] for k in ACCOUNT_COUNTS} == {k: a["gait_check"][k] for k in ACCOUNT_COUNTS}
    np.testing.assert_allclose(b["gait_check"]["rejected_t_s"], a["gait_check"]["rejected_t_s"], atol=1e-9)
    assert len(_gait_notes(cap.err)) == 1


def test_the_long_path_verdict_is_the_whole_files_when_it_is_mixed(tmp_path, monkeypatch, capsys):
    """A walk, then gestures (gait check off, so their steps stay): the verdict is mixed and equal on both paths."""
    from gaitml.recording import Recording

    walk = simulate_dataset(1, 120.0, sampling_rate_hz=50.0, seed=3)[0]
    gest = simulate_nongait("gestures", duration_s=180.0, sampling_rate_hz=50.0, seed=106)
    rec = Recording.from_arrays(np.vstack([walk.acc, gest.acc]), 50.0, gyr=np.vstack([walk.gyr, gest.gyr]))
    path = tmp_path / "walk-then-gestures.csv"
    write_gaitml_csv(rec, path)
    assert main(["steps", str(path), "--json", "--no-gait-check"]) == 0
    a = json.loads(capsys.readouterr().out)
    _force_long(monkeypatch)
    assert main(["steps", str(path), "--json", "--no-gait-check"]) == 0
    b = json.loads(capsys.readouterr().out)
    assert b["chunked"]
    flags = [s["confident"] for s in a["steps"]]
    assert any(flags) and not all(flags)  # mixed: the test has something to compare
    assert [s["confident"] for s in b["steps"]] == flags
    assert (b["n_confident"], b["n_unsure"]) == (a["n_confident"], a["n_unsure"])


@pytest.mark.parametrize("cmd", ["label", "segment"])
def test_commands_say_when_the_gait_check_could_not_run(files, tmp_path, capsys, cmd):
    """No gyroscope: the account says tested false and one note says the check did not run."""
    from gaitml.recording import Recording

    rec = read_recording(files["walk"])
    path = tmp_path / "acc-only.csv"
    write_gaitml_csv(Recording.from_arrays(rec.acc, rec.sampling_rate_hz), path)
    assert main([*_command(cmd, path, tmp_path), "--json"]) == 0
    cap = capsys.readouterr()
    assert json.loads(cap.out)["gait_check"]["tested"] is False
    assert cap.err.count("gait check of adaptive did not run") == 1


def test_steps_notes_when_the_gait_check_could_not_run(files, tmp_path, capsys):
    from gaitml.recording import Recording

    rec = read_recording(files["walk"])
    path = tmp_path / "acc-only.csv"
    write_gaitml_csv(Recording.from_arrays(rec.acc, rec.sampling_rate_hz), path)
    assert main(["steps", str(path), "--json"]) == 0
    cap = capsys.readouterr()
    assert json.loads(cap.out)["gait_check"]["tested"] is False
    assert cap.err.count("gaitml: note: gait check not run") == 1


def test_a_bout_over_a_chunk_edge_left_out_in_one_chunk_counts_as_one_rejected_bout():
    """One bout of 9 steps (1 s apart) over the edge of two chunks, kept by the test in the first chunk and
    left out in the second (each chunk tests its own part of a bout longer than the margin): one bout, one
    rejected bout, its 5 steps in the second core rejected (the rejected bout used to be lost: it was
    counted only in the chunk holding its first step)."""
    from gaitml.io.chunked import Chunk
    from gaitml.recording import Recording
    from gaitml.steps._table import make_step_table

    fs = 10.0
    rec = Recording(acc=np.tile([0.0, 0.0, 9.81], (150, 1)), gyr=np.zeros((150, 3)), sampling_rate_hz=fs)
    peaks = np.arange(60, 150, 10)  # whole-file samples 60, 70, ..., 140

    def table(p):
        return make_step_table(p - 5, p, p + 5, fs, event="t_peak_s", period_s=np.full(len(p), 1.0))

    first = Chunk(rec, 0, 0, 100)  # core [0, 100): the steps at 60-90, kept
    second = Chunk(rec, 50, 100, 200)  # core [100, 200): the steps at 100-140, left out
    accounts = [
        cr._gait_account(table(peaks), table(peaks), rec, first),
        cr._gait_account(table(peaks - 50), table(peaks[:0]), rec, second),
    ]
    total = cr._sum_accounts(accounts)
    assert (total["n_bouts"], total["n_bouts_rejected"], total["n_steps_rejected"]) == (1, 1, 5)
    np.testing.assert_allclose(total["rejected_t_s"], [10.0, 11.0, 12.0, 13.0, 14.0])
    # a pause longer than any step interval between the two parts: two bouts, one of them rejected
    accounts[1] = cr._gait_account(table(peaks[4:] - 50 + 40), table(peaks[:0]), rec, Chunk(rec, 50, 100, 250))
    total = cr._sum_accounts(accounts)
    assert (total["n_bouts"], total["n_bouts_rejected"], total["n_steps_rejected"]) == (2, 1, 5)
