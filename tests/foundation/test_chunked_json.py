"""A long input (read in chunks) answers with the same JSON keys as the same file read whole.

The chunked road is forced with ``gaitml.io.chunked.LARGE_INPUT_SAMPLES`` below every input, as
tests/foundation/test_chunked_rates.py does. Every key (nested keys too, and those of a list's
first object) of a whole-file run's JSON must be in the chunked run's; the chunked run may add its
own (``chunked``: the chunk and margin lengths).
"""

from __future__ import annotations

import json

import pytest

import gaitml.io.chunked as ch
from gaitml.cli import main
from gaitml.io import write_gaitml_csv
from gaitml.simulate import simulate_dataset

#: Keys a whole-file run has and a chunked run does not give yet: ``gaitml steps`` with a detector that
#: estimates a local cadence (``adaptive``) lists it per window (``cadence``) on a whole file only.
KNOWN_WHOLE_ONLY = {"steps": {"cadence"}}


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
