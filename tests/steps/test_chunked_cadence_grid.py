"""Chunked ``adaptive`` cadence on the whole-file window grid, at a rate whose cadence hop is not a whole
number of samples per second.

``adaptive``'s cadence windows hop by ``round(hop_s * fs / q) * q`` samples (``q`` the decimation to about
``CADENCE_RATE_HZ``): 90 samples at 90.09 Hz, not the 90.09 of one second. :func:`gaitml.chunked_run.long_steps`
with ``keep_cadence`` must give the whole-file run's windows, each once, at the whole-file times.
"""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.chunked_run import long_steps
from gaitml.io import read_recording, write_gaitml_csv
from gaitml.simulate import simulate_dataset
from gaitml.steps import get_detector


@pytest.fixture(scope="module", params=[90.09, 198.59])
def odd_rate_file(request, tmp_path_factory):
    rec = simulate_dataset(1, 75.0, sampling_rate_hz=request.param, seed=11)[0]
    p = tmp_path_factory.mktemp("cadgrid") / "rec.csv"
    write_gaitml_csv(rec, p)
    return p


@pytest.mark.parametrize(("chunk_s", "margin_s"), [(20.0, 10.0), (20.0, 30.0)])
def test_chunked_cadence_windows_are_the_whole_file_windows(odd_rate_file, chunk_s, margin_s):
    rec = read_recording(odd_rate_file)
    whole = get_detector("adaptive").detect(rec).cadence_
    chunked = long_steps(odd_rate_file, "adaptive", chunk_s=chunk_s, margin_s=margin_s, progress=False, keep_cadence=True)
    cad = chunked.attrs["cadence"]
    t = np.asarray(cad["t_s"])
    assert len(t) == len(whole), f"{len(t)} chunked windows vs {len(whole)} whole-file windows"
    assert np.all(np.diff(t) > 0), "a window is given twice or out of order"
    np.testing.assert_allclose(t, whole["t_s"].to_numpy(), rtol=0, atol=1e-9)
    np.testing.assert_array_equal(np.asarray(cad["stride"]), whole["stride"].to_numpy())
    # same windows, so the same values up to the band-pass filter's edge transient at the chunk ends
    np.testing.assert_allclose(np.asarray(cad["cadence_hz"]), whole["cadence_hz"].to_numpy(), rtol=0, atol=1e-6)


def test_chunked_steps_do_not_depend_on_keep_cadence(odd_rate_file):
    """The chunks are cut on the cadence grid with or without keep_cadence: `steps --json` and the text output
    give the same steps."""
    kw = {"chunk_s": 20.0, "margin_s": 10.0, "progress": False}
    a = long_steps(odd_rate_file, "adaptive", keep_cadence=True, **kw)
    b = long_steps(odd_rate_file, "adaptive", **kw)
    assert len(a) > 50  # a walk: there are steps to compare
    np.testing.assert_array_equal(a["peak"].to_numpy(), b["peak"].to_numpy())
    assert "cadence" not in b.attrs


def test_chunked_pdr_finds_the_steps_of_chunked_steps(odd_rate_file):
    """`gaitml pdr` on a long input cuts its chunks on adaptive's cadence grid as `gaitml steps` does, so both
    commands place the same steps (they did not when only long_steps was aligned)."""
    from gaitml.chunked_run import long_pdr

    kw = {"chunk_s": 20.0, "margin_s": 10.0, "progress": False}
    steps = long_steps(odd_rate_file, "adaptive", **kw)
    pdr = long_pdr(odd_rate_file, detector="adaptive", modes="forward", **kw)
    assert len(steps) > 50
    np.testing.assert_array_equal(pdr.steps["peak"].to_numpy(), steps["peak"].to_numpy())


def test_the_adaptive_cross_check_count_of_another_detector_is_adaptive_s_own_chunked_count(odd_rate_file):
    """`count_also="adaptive"` beside another main detector counts on chunks on adaptive's grid too, so the
    cross-check count equals what `gaitml steps --detector adaptive` counts on the same long input."""
    kw = {"chunk_s": 20.0, "margin_s": 10.0, "progress": False}
    own = long_steps(odd_rate_file, "adaptive", **kw)
    other = long_steps(odd_rate_file, "single-peak", count_also="adaptive", **kw)
    assert other.attrs["count_also"]["n_steps"] == len(own)
