"""A long input of a format read whole (here a columns-csv) prints the reader's warnings once, as a whole-file run does.

The chunked road is forced with ``gaitml.io.chunked.LARGE_INPUT_SAMPLES`` below every input. The file's
rate changes mid-file (100 Hz, then 50 Hz), which the reader warns about (one stderr line).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import gaitml.io.chunked as ch
from gaitml.cli import main
from gaitml.simulate import simulate_dataset

COLUMNS = ["--columns", "t=time_ms,acc_x=ax,acc_y=ay,acc_z=az,gyr_x=gx,gyr_y=gy,gyr_z=gz", "--time-unit", "ms"]


@pytest.fixture(scope="module")
def rate_change_file(tmp_path_factory):
    rec = simulate_dataset(1, 60.0, sampling_rate_hz=100.0, seed=5)[0]
    keep = np.r_[np.arange(3000), np.arange(3000, rec.n_samples, 2)]  # 30 s at 100 Hz, then 50 Hz
    df = pd.DataFrame({"time_ms": 1000.0 * rec.t_s[keep]})
    for i, ax in enumerate("xyz"):
        df[f"a{ax}"] = rec.acc[keep, i]
    for i, ax in enumerate("xyz"):
        df[f"g{ax}"] = rec.gyr[keep, i]
    p = tmp_path_factory.mktemp("ratechange") / "logger.csv"
    df.to_csv(p, index=False)
    return p


def _warnings(argv, monkeypatch, capsys, chunked: bool) -> list[str]:
    monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", -1 if chunked else 10**12)
    assert main([*argv, *COLUMNS, "--json"]) == 0
    return [line for line in capsys.readouterr().err.splitlines() if line.startswith("gaitml: warning:")]


@pytest.mark.parametrize(
    "argv",
    [["zupt", "{f}"], ["steps", "{f}"], ["predict", "models/demo", "{f}"], ["pdr", "{f}"]],
    ids=["zupt", "steps", "predict", "pdr"],
)
def test_chunked_run_prints_reader_warnings_once(argv, rate_change_file, monkeypatch, capsys):
    argv = [a.format(f=rate_change_file) for a in argv]
    whole = _warnings(argv, monkeypatch, capsys, chunked=False)
    chunked = _warnings(argv, monkeypatch, capsys, chunked=True)
    rate = [w for w in whole if "sampling rate changes mid-file" in w]
    assert len(rate) == 1, whole  # the reader warns, once
    assert chunked.count(rate[0]) == 1, chunked
    assert sorted(set(whole)) == sorted(set(chunked))
