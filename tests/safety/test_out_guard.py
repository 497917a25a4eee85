"""Issue 28 finding 1 and part of 9: an output never replaces an input (checked before anything is read)."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from gaitml.cli import main
from tests.conftest import ROOT


def _walk_csv(path, seconds=20.0, fs=100.0):
    t = np.arange(int(seconds * fs)) / fs
    acc = np.column_stack([0.5 * np.sin(2 * np.pi * 2 * t), 0.3 * np.cos(2 * np.pi * 2 * t), 9.81 + 2 * np.sin(2 * np.pi * 2 * t)])
    gyr = np.column_stack([0.2 * np.sin(2 * np.pi * t), 0.1 * np.cos(2 * np.pi * t), 0.05 * np.sin(2 * np.pi * 2 * t)])
    rows = "".join(
        f"{a:.4f},{b[0]:.5f},{b[1]:.5f},{b[2]:.5f},{c[0]:.5f},{c[1]:.5f},{c[2]:.5f}\n" for a, b, c in zip(t, acc, gyr, strict=True)
    )
    path.write_text("t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z\n" + rows)
    return path


@pytest.fixture
def model(tmp_path):
    dst = tmp_path / "model"
    shutil.copytree(ROOT / "models" / "demo", dst)
    return dst


COMMANDS = [
    ["steps", "{inp}", "--out", "{inp}"],
    ["zupt", "{inp}", "--out", "{inp}"],
    ["features", "{inp}", "--out", "{inp}"],
    ["predict", "{model}", "{inp}", "--out", "{inp}"],
    ["pdr", "{inp}", "--out", "{inp}"],
    ["pdr", "{inp}", "--out", "{tmp}/x.csv", "--plot", "{inp}"],
    ["segment", "{inp}", "--out", "{inp}"],
    ["label", "{inp}", "--intervals", "{iv}", "--out", "{iv}"],
    ["pdr", "{inp}", "--truth", "{iv}", "--out", "{iv}"],
    ["label", "{inp}", "--intervals", "{iv}", "--out", "{inp}"],
    ["predict", "{model}", "{inp}", "--out", "{model}/model.json"],
    ["predict", "{model}", "{inp}", "--out", "{model}/new.csv"],
    ["pdr", "{inp}", "--model", "{model}", "--out", "{model}/arrays.npz"],
    ["model", "card", "{model}", "--out", "{model}/MODEL.md"],
    ["model", "export", "{model}", "--format", "json", "--out", "{model}/model.json"],
    ["split", "{inp}", "--out", "{tmp}"],
    ["steps", "{link}", "--out", "{inp}"],
    ["steps", "{inp}", "--out", "{hard}"],
]


@pytest.mark.parametrize("argv", COMMANDS, ids=[" ".join(a[:1] + a[-2:]) for a in COMMANDS])
def test_out_over_an_input_is_refused_before_reading(tmp_path, capsys, model, argv):
    inp = _walk_csv(tmp_path / "walk.csv")
    iv = tmp_path / "iv.csv"
    iv.write_text("start_s,end_s,label\n0,10,walk\n")
    (tmp_path / "link.csv").symlink_to(inp)
    hard = tmp_path / "hard.csv"
    hard.hardlink_to(inp)
    before = {p: p.read_bytes() for p in [inp, iv, *model.iterdir()]}
    listing = sorted(p.name for p in tmp_path.rglob("*"))
    code = main([a.format(inp=inp, model=model, iv=iv, tmp=tmp_path, link=tmp_path / "link.csv", hard=hard) for a in argv])
    err = capsys.readouterr().err
    assert code == 2, err
    assert len(err.strip().splitlines()) == 1 and ("destroy" in err or "inside the model folder" in err or "holds" in err)
    assert {p: p.read_bytes() for p in before} == before
    assert sorted(p.name for p in tmp_path.rglob("*")) == listing


def test_out_beside_the_input_still_works(tmp_path, capsys):
    inp = _walk_csv(tmp_path / "walk.csv")
    assert main(["steps", str(inp), "--out", str(tmp_path / "steps.csv")]) == 0
    assert (tmp_path / "steps.csv").exists()


def test_out_with_a_trailing_slash_is_refused(tmp_path, capsys):
    """Finding 9: `--out newdir/` wrote a file named newdir."""
    inp = _walk_csv(tmp_path / "walk.csv")
    code = main(["steps", str(inp), "--out", f"{tmp_path / 'newdir'}/"])
    err = capsys.readouterr().err
    assert code == 2 and "ends with '/'" in err
    assert not (tmp_path / "newdir").exists()
    # the fix it names works
    assert main(["steps", str(inp), "--out", str(tmp_path / "newdir" / "out.csv")]) == 0
    assert (tmp_path / "newdir" / "out.csv").is_file()


def test_out_to_stdout_with_json_is_refused(tmp_path, capsys):
    """Finding 9: `--out /dev/stdout --json` mixed a CSV table and the JSON object on stdout."""
    inp = _walk_csv(tmp_path / "walk.csv")
    code = main(["steps", str(inp), "--out", "/dev/stdout", "--json"])
    captured = capsys.readouterr()
    assert code == 2 and "standard output" in captured.err and captured.out == ""
