"""Chunked reading gives the same samples as reading the whole file."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from gaitml import InputError
from gaitml.io import chunked as ch
from gaitml.io import read_recording


def _write(tmp_path, n, fs=100.0, irregular=False, seed=0, labels=True, gyr=True):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    if irregular:
        t = np.cumsum(rng.uniform(0.7, 1.3, n)) / fs
    df = pd.DataFrame({"t": t, "acc_x": rng.normal(0, 1, n), "acc_y": rng.normal(0, 1, n), "acc_z": 9.8 + rng.normal(0, 1, n)})
    if gyr:
        for c in ("gyr_x", "gyr_y", "gyr_z"):
            df[c] = rng.normal(0, 0.5, n)
    if labels:
        df["label"] = np.repeat(["walk", "run", "walk", "side_left"], -(-n // 4))[:n]
    p = tmp_path / "long.csv"
    df.to_csv(p, index=False)
    return p


def _reassemble(chunks):
    parts_acc, parts_lab = [], []
    for c in chunks:
        lo = c.core_start - c.offset
        hi = c.core_end - c.offset
        parts_acc.append(c.recording.acc[lo:hi])
        if c.recording.labels is not None:
            parts_lab.append(c.recording.labels[lo:hi])
    return np.vstack(parts_acc), (np.concatenate(parts_lab) if parts_lab else None)


@pytest.mark.parametrize("irregular", [False, True])
def test_chunks_reassemble_to_whole_file(tmp_path, monkeypatch, irregular):
    monkeypatch.setattr(ch, "_ROWS_PER_READ", 777)  # many read blocks
    p = _write(tmp_path, 5000, irregular=irregular)
    whole = read_recording(p, sampling_rate_hz=100.0 if irregular else None)
    chunks = list(ch.iter_chunks(p, chunk_s=7.0, margin_s=1.5, align_samples=25, sampling_rate_hz=100.0 if irregular else None))
    assert len(chunks) > 5
    acc, lab = _reassemble(chunks)
    np.testing.assert_allclose(acc, whole.acc, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(lab, whole.labels)
    for c in chunks[:-1]:
        assert c.core_start % 25 == 0 and c.core_end % 25 == 0
        assert c.offset <= c.core_start and c.offset + c.recording.n_samples >= c.core_end
    assert chunks[1].core_start - chunks[1].offset == 150  # a full left margin


def test_chunks_of_small_formats(tmp_path):
    p = _write(tmp_path, 1200)
    whole = read_recording(p)
    from gaitml.io.chunked import recording_chunks

    acc, _ = _reassemble(recording_chunks(whole, chunk_s=3.0, margin_s=1.0, align_samples=1))
    np.testing.assert_array_equal(acc, whole.acc)


def test_chunked_bad_rows_are_errors(tmp_path, monkeypatch):
    monkeypatch.setattr(ch, "_ROWS_PER_READ", 100)
    p = _write(tmp_path, 1000, labels=False, gyr=False)
    lines = p.read_text().splitlines()
    lines[500] = lines[500].replace(lines[500].split(",")[1], "nan", 1)
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match="line 501"):
        list(ch.iter_chunks(p, chunk_s=2.0, margin_s=0.5))
    lines = _write(tmp_path, 1000, labels=False, gyr=False).read_text().splitlines()
    lines[300], lines[301] = lines[301], lines[300]
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match="timestamps decrease at sample 300"):
        list(ch.iter_chunks(p, chunk_s=2.0, margin_s=0.5))
    _same_refusal(p)


def _same_refusal(p):
    """Issue 28: the chunked path refuses with the message of the whole-file reader (one reading path)."""
    with pytest.raises(InputError) as whole:
        read_recording(p)
    with pytest.raises(InputError) as chunked:
        list(ch.iter_chunks(p, chunk_s=2.0, margin_s=0.5))
    assert str(chunked.value) == str(whole.value)


@pytest.mark.parametrize("irregular", [False, True])
def test_chunked_long_gap_and_impossible_values_are_refused(tmp_path, monkeypatch, irregular):
    """Issue 17: the chunked path refuses what the whole-file reader refuses, before allocating or interpolating."""
    monkeypatch.setattr(ch, "_ROWS_PER_READ", 100)
    p = _write(tmp_path, 1000, irregular=irregular, labels=False)
    df = pd.read_csv(p)
    df.loc[650:, "t"] += 1e7  # in the seventh block
    df.to_csv(p, index=False)
    with pytest.raises(InputError, match=r"1e\+07 s gap in the timestamps after sample 649"):
        list(ch.iter_chunks(p, chunk_s=2.0, margin_s=0.5))
    _same_refusal(p)
    df = pd.read_csv(_write(tmp_path, 1000, irregular=irregular, labels=False))
    df.loc[420, "gyr_y"] = 1e308
    df.to_csv(p, index=False)
    with pytest.raises(InputError, match=r"gyr_y = 1e\+308 at sample 420 .*beyond any sensor's range"):
        list(ch.iter_chunks(p, chunk_s=2.0, margin_s=0.5))
    _same_refusal(p)


def _held_csv(path, n=6000, fs=100.0, every=3):
    """An accelerometer that updates every ``every`` rows and is held between (a multi-sensor logger's rows)."""
    t = np.arange(n) / fs
    k = (np.arange(n) // every) * every
    acc = np.c_[np.sin(2 * np.pi * 1.8 * t[k]), 0.5 * np.cos(2 * np.pi * 1.8 * t[k]), 9.81 + 3 * np.sin(2 * np.pi * 1.8 * t[k])]
    gyr = np.c_[0.1 * np.sin(t), 0.1 * np.cos(t), 0.05 * t]
    cols = {"t": t, "acc_x": acc[:, 0], "acc_y": acc[:, 1], "acc_z": acc[:, 2], "gyr_x": gyr[:, 0], "gyr_y": gyr[:, 1], "gyr_z": gyr[:, 2]}
    pd.DataFrame(cols).to_csv(path, index=False)
    return path


def test_a_held_stream_is_refused_on_the_chunked_road_with_its_rates(tmp_path, monkeypatch, capsys):
    """A file read whole is re-timed at the held sensor's updates; the chunked road, which keeps the row times,
    refuses it in one line naming the update and row rates and the fix (never reads it at the row rate)."""
    from gaitml.cli import main

    p = _held_csv(tmp_path / "held.csv")
    whole = read_recording(p)
    assert whole.meta["sample_and_hold"]["acc"]["update_rate_hz"] == pytest.approx(33.3, abs=0.2)
    monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", 100)
    monkeypatch.setattr(ch, "_ROWS_PER_READ", 700)  # holds across read blocks
    assert main(["steps", str(p)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "sample-and-hold" in err[0] and "33.3 Hz" in err[0] and "fewer than 100 rows" in err[0]
    # a stream that does not hold is read on the chunked road as before
    assert main(["steps", str(_write(tmp_path, 6000))]) == 0
