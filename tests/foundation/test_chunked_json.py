"""A long input (read in chunks) answers with the same JSON keys as the same file read whole.

The chunked road is forced with ``gaitml.io.chunked.LARGE_INPUT_SAMPLES`` below every input, as
tests/foundation/test_chunked_rates.py does. Every key (nested keys too, and those of a list's
first object) of a whole-file run's JSON must be in the chunked run's; the chunked run may add its
own (``chunked``: the chunk and margin lengths).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import gaitml.chunked_run as cr
import gaitml.io.chunked as ch
from gaitml.cli import main
from gaitml.io import write_gaitml_csv
from gaitml.simulate import simulate_dataset

#: Keys a whole-file run has and a chunked run does not give yet (none at present; a command's entry
#: is a set of top-level keys).
KNOWN_WHOLE_ONLY: dict[str, set[str]] = {}


@pytest.fixture(scope="module")
def rec_file(tmp_path_factory):
    rec = simulate_dataset(1, 60.0, sampling_rate_hz=100.0, seed=5, pose="mixed")[0]
    p = tmp_path_factory.mktemp("longjson") / "rec.csv"
    write_gaitml_csv(rec, p)
    return p


def _keys(obj, prefix: str = "") -> set[str]:
    out: set[str] = set()
    if isinstance(obj, dict):
        for k, v in obj.items():
            out.add(prefix + k)
            out |= _keys(v, f"{prefix}{k}.")
    elif isinstance(obj, list) and obj and isinstance(obj[0], dict):
        out |= _keys(obj[0], f"{prefix}[].")
    return out


def _json(argv, monkeypatch, capsys, chunked: bool) -> dict:
    monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", -1 if chunked else 10**12)
    assert main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize(
    "argv",
    [
        ["zupt", "{f}"],
        ["zupt", "{f}", "--detector", "magnitude", "--interval-rules", "fixed"],
        ["steps", "{f}"],
        ["predict", "models/demo", "{f}"],
        ["pdr", "{f}"],
    ],
    ids=["zupt", "zupt-magnitude-fixed", "steps", "predict", "pdr"],
)
def test_chunked_json_has_whole_file_keys(argv, rec_file, monkeypatch, capsys):
    argv = [a.format(f=rec_file) for a in argv]
    whole = _json(argv, monkeypatch, capsys, chunked=False)
    chunked = _json(argv, monkeypatch, capsys, chunked=True)
    known = KNOWN_WHOLE_ONLY.get(argv[0], set())
    missing = {k for k in _keys(whole) - _keys(chunked) if k.split(".")[0] not in known}
    assert not missing, f"{argv[0]} --json read in chunks lacks {sorted(missing)}"


def test_chunked_zupt_reports_interval_rules(rec_file, monkeypatch, capsys):
    """The chunked zupt JSON names the interval rules, with the whole-file run's value."""
    for rules in ("stride", "none"):
        argv = ["zupt", str(rec_file), "--interval-rules", rules]
        whole = _json(argv, monkeypatch, capsys, chunked=False)
        chunked = _json(argv, monkeypatch, capsys, chunked=True)
        assert whole["interval_rules"] == rules
        assert chunked["interval_rules"] == whole["interval_rules"]


def test_chunked_steps_cadence_matches_whole_file(rec_file, monkeypatch, capsys):
    """``steps --json`` read in chunks lists the per-window cadence of the whole-file run: the same window
    times (each window once, in the chunk whose core holds its centre) and the same values up to the
    band-pass filter's edge transient at the chunk ends (10 s margins here; measured below 1e-9)."""
    argv = ["steps", str(rec_file)]
    whole = _json(argv, monkeypatch, capsys, chunked=False)["cadence"]
    # 20 s cores with 10 s margins: the 60 s file is read in three chunks, so windows are cut at two edges
    monkeypatch.setattr(cr, "DEFAULT_CHUNK_S", 20.0)
    monkeypatch.setattr(cr, "DEFAULT_MARGIN_S", 10.0)
    obj = _json(argv, monkeypatch, capsys, chunked=True)
    assert obj["chunked"] == {"chunk_s": 20.0, "margin_s": 10.0}
    chunked = obj["cadence"]
    assert [w["t_s"] for w in chunked] == pytest.approx([w["t_s"] for w in whole], abs=1e-9)
    assert [w["stride"] for w in chunked] == [w["stride"] for w in whole]
    for key in ("cadence_hz", "periodicity"):
        assert np.allclose([w[key] for w in chunked], [w[key] for w in whole], rtol=0, atol=1e-6), key
