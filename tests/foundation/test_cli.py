"""The CLI contract: exit codes, one-line errors, `gaitml info` on every shared file."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from gaitml.cli import build_parser, main
from tests.conftest import shared


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_every_design_subcommand_is_registered():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    assert set(sub.choices) >= {"info", "simulate", "steps", "zupt", "features", "train", "evaluate", "predict", "pdr", "demo", "bench"}


def _write(tmp_path, text, name="x.csv"):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


GOOD = "t,acc_x,acc_y,acc_z\n" + "".join(f"{i / 50},0.1,0.2,9.8\n" for i in range(100))


@pytest.mark.parametrize(
    "content, match",
    [
        (None, "no such file"),
        ("", "empty"),
        ("foo,bar\n1,2\n", "unknown format"),
        ("t,acc_x,acc_y,acc_z\n0,1,1,nan\n0.02,1,1,9.8\n", "NaN/inf"),
        ("t,acc_x,acc_y,acc_z\n0,1,1,inf\n0.02,1,1,9.8\n", "NaN/inf"),
        ("t,acc_x,acc_y,acc_z\n0,1,1,9.8\n0,1,1,9.8\n", "duplicate timestamp"),
        ("t,acc_x,acc_y,acc_z\n0,1,1,9.8\n0.04,1,1,9.8\n0.02,1,1,9.8\n", "timestamps decrease"),
        ("t,acc_x,acc_y,acc_z\n" + "".join(f"{i / 50},0.01,0.02,1.0\n" for i in range(50)), "in g"),
    ],
)
def test_bad_input_exit_2_one_line(tmp_path, capsys, content, match):
    path = str(tmp_path / "missing.csv") if content is None else _write(tmp_path, content)
    code, out, err = run(capsys, "info", path)
    assert code == 2
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("gaitml: error:")
    assert match in lines[0]


def test_manifest_naming_missing_file_exit_2(tmp_path, capsys):
    _write(tmp_path, GOOD, "a.csv")
    (tmp_path / "manifest.csv").write_text("file,subject,session\na.csv,s1,1\nb.csv,s2,1\n")
    code, _, err = run(capsys, "info", str(tmp_path))
    assert code == 2 and "names a missing file: b.csv" in err


def test_bad_arguments_exit_2_one_line(capsys):
    code, _, err = run(capsys, "steps", "x.csv", "--detector", "nope")
    assert code == 2 and len(err.strip().splitlines()) == 1 and "invalid choice" in err
    code, _, err = run(capsys, "frobnicate")
    assert code == 2


def test_info_text_and_json(tmp_path, capsys):
    p = _write(tmp_path, GOOD)
    code, out, _ = run(capsys, "info", p)
    assert code == 0 and "samples   100" in out and "50 Hz" in out
    code, out, _ = run(capsys, "info", p, "--json")
    d = json.loads(out)
    assert d["n_samples"] == 100 and d["sampling_rate_hz"] == 50.0 and d["channels"] == ["acc_x", "acc_y", "acc_z"]


def test_acc_unit_option_converts(tmp_path, capsys):
    p = _write(tmp_path, "t,acc_x,acc_y,acc_z\n" + "".join(f"{i / 50},0.01,0.02,1.0\n" for i in range(50)))
    code, out, _ = run(capsys, "info", p, "--acc-unit", "g", "--json")
    assert code == 0 and json.loads(out)["converted"] == ["acc from g"]


def test_console_script_no_traceback(tmp_path):
    p = _write(tmp_path, "t,acc_x,acc_y,acc_z\n0,1,1,nan\n0.02,1,1,9.8\n")
    res = subprocess.run([sys.executable, "-m", "gaitml.cli", "info", p], capture_output=True, text=True)
    assert res.returncode == 2
    assert "Traceback" not in res.stderr and res.stdout == ""


# ----------------------------------------------------------------- real data
@pytest.mark.realdata
@pytest.mark.parametrize("name, n", [("acceleration_flat_holding_1.xlsx", 7197), ("acceleration_flat_holding_2.xlsx", 8379)])
def test_info_ifsm(capsys, name, n):
    code, out, _ = run(capsys, "info", str(shared("ifsm-flat-phone", name)), "--json")
    d = json.loads(out)
    assert code == 0 and d["n_samples"] == n and d["sampling_rate_hz"] == 50.0


@pytest.mark.realdata
def test_info_oxford_set_matches_stats(capsys):
    root = shared("oxford-step-counter")
    code, out, _ = run(capsys, "info", str(root), "--json")
    d = json.loads(out)
    stats = pd.read_csv(root / "optimisation" / "stats.csv", skipinitialspace=True)
    stats.columns = [c.strip().lstrip("#") for c in stats.columns]
    assert code == 0 and d["n_recordings"] == 48
    assert d["n_steps_true"] == int(stats["steps"].sum()) == 13740
    per = {r["id"]: r["reference"]["n_steps_true"] for r in d["recordings"]}
    for row in stats.itertuples():
        assert per[row.dir.strip()] == row.steps
    assert all(r["sampling_rate_hz"] == 100.0 and r["resampled"] for r in d["recordings"])


@pytest.mark.realdata
def test_info_gaitmap_sample(capsys):
    code, out, _ = run(capsys, "info", str(shared("gaitmap-example", "imu_sample.csv.gz")), "--json", "--sensor", "right")
    d = json.loads(out)
    assert code == 0 and d["n_samples"] == 7928 and d["sampling_rate_hz"] == 204.8 and d["sensor"] == "right"
    assert d["reference"]["strides"] == 30


@pytest.mark.realdata
def test_info_reads_every_shared_file_and_folder(capsys):
    root = shared()
    targets = [root / "ifsm-flat-phone", root / "oxford-step-counter", root / "gaitmap-example"]
    for folder in ("ifsm-flat-phone", "gaitmap-example"):
        targets += sorted(p for p in (root / folder).iterdir() if p.suffix in (".xlsx", ".gz"))
    targets += sorted((root / "oxford-step-counter" / "optimisation" / "data").iterdir())
    for t in targets:
        code, out, err = run(capsys, "info", str(t), "--json")
        assert code == 0, (t, err)
        d = json.loads(out)
        assert d["kind"] in ("recording", "dataset", "table")
        if d["kind"] == "recording":
            assert d["n_samples"] > 0 and np.isfinite(d["sampling_rate_hz"])


def test_no_command_is_one_line(capsys):
    code, out, err = run(capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "no command" in err


def test_truncated_gzip_csv_exit_2(tmp_path, capsys):
    import gzip

    from tests.conftest import ROOT

    data = gzip.compress((ROOT / "data" / "samples" / "S02-mixed.csv").read_bytes())
    p = tmp_path / "t.csv.gz"
    p.write_bytes(data[: len(data) // 3])
    code, _, err = run(capsys, "info", str(p))
    assert code == 2 and "truncated" in err


def test_broken_stdout_pipe_is_quiet():
    from tests.conftest import ROOT

    res = subprocess.run(
        f"{sys.executable} -m gaitml.cli steps {ROOT / 'data' / 'samples' / 'S02-mixed.csv'} --json | head -c 10",
        shell=True,
        capture_output=True,
        text=True,
    )
    assert "internal error" not in res.stderr and "Traceback" not in res.stderr
