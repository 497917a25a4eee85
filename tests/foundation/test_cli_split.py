"""`gaitml split`: the fix that the long-gap refusal names, as a user runs it."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from gaitml.cli import main
from gaitml.consts import GRAVITY_MS2
from gaitml.io import read_recording


def _gappy_csv(path, *, gap_after=400, gap_s=3600.0, n=1000, fs=50.0):
    rng = np.random.default_rng(3)
    acc = rng.normal(0, 1, (n, 3)) + [0, 0, GRAVITY_MS2]
    t = np.arange(n) / fs
    t[gap_after:] += gap_s
    labels = np.where(np.arange(n) < 700, "walk", "run")
    pd.DataFrame({"t": t, "acc_x": acc[:, 0], "acc_y": acc[:, 1], "acc_z": acc[:, 2], "label": labels}).to_csv(path, index=False)
    return acc, labels


def test_gap_refusal_names_split_and_split_fixes_it(tmp_path, capsys):
    src = tmp_path / "walk.csv"
    acc, labels = _gappy_csv(src)
    assert main(["steps", str(src)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "3600.02 s gap" in err[0] and "gaitml split FILE --out DIR" in err[0]

    out = tmp_path / "segments"
    assert main(["split", str(src), "--out", str(out), "--json"]) == 0
    js = json.loads(capsys.readouterr().out)
    assert js["n_segments"] == 2 and js["segments_dropped"] == 0
    assert [s["n_samples"] for s in js["segments"]] == [400, 600]
    assert js["segments"][1]["t_start_s"] == pytest.approx(3608.0)
    man = pd.read_csv(out / "manifest.csv")
    assert list(man["file"]) == ["walk-seg001.csv", "walk-seg002.csv"]
    assert list(man["first_sample"]) == [0, 400] and list(man["last_sample"]) == [399, 999]
    # no sample lost: both files together hold every sample and label of the input, in order
    parts = [read_recording(out / f) for f in man["file"]]
    np.testing.assert_allclose(np.vstack([p.acc for p in parts]), acc, rtol=0, atol=1e-12)
    assert list(np.concatenate([p.labels for p in parts])) == list(labels)
    # the folder is a data set the other commands read
    assert main(["info", str(out), "--json"]) == 0
    assert main(["steps", str(out / "walk-seg002.csv"), "--json"]) == 0


def test_split_without_gaps_writes_one_segment(tmp_path, capsys):
    src = tmp_path / "plain.csv"
    _gappy_csv(src, gap_s=0.0)
    assert main(["split", str(src), "--out", str(tmp_path / "o")]) == 0
    assert "wrote 1 segments (1000 samples)" in capsys.readouterr().err
    assert len(pd.read_csv(tmp_path / "o" / "manifest.csv")) == 1


def test_split_never_replaces_a_folder_of_other_files(tmp_path, capsys):
    src = tmp_path / "walk.csv"
    _gappy_csv(src)
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    assert main(["split", str(src), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("gaitml: error:")
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]


def test_split_of_bad_input_leaves_nothing(tmp_path, capsys):
    src = tmp_path / "empty.csv"
    src.write_text("")
    assert main(["split", str(src), "--out", str(tmp_path / "o")]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["empty.csv"]
