"""The foot-placement rule in a stream: one window at a time, it flags the windows the whole-file path flags.

A synthetic foot-mounted signal (:func:`gaitml.simulate.foot.simulate_foot`) and a hand-held phone
are pushed one hop at a time through :class:`gaitml.features.StreamingFeatureExtractor`; every
completed window is classified and its own samples pass
:func:`gaitml.models.window_placement_reason`. The reasons must be those of
:func:`gaitml.models.predict_recording`'s ``out_of_domain_reason`` for the foot rule, window by
window (the rule reads a window's own samples only), and the foot must be flagged on most
windows, the phone on almost none (floors well below experiments/reports/foot-placement.md).
"""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.errors import InputError
from gaitml.features import StreamingFeatureExtractor
from gaitml.models import load_model, predict_recording, window_placement_reason
from gaitml.models._placement import FOOT_REASON
from gaitml.simulate import simulate_dataset
from gaitml.simulate.foot import simulate_foot
from tests.conftest import ROOT


def _stream(model, rec, with_gyr: bool) -> tuple[list[int], list[str | None], list[str]]:
    """Starts, foot-rule reasons and model modes of every window of ``rec`` streamed one hop at a time."""
    ext = StreamingFeatureExtractor(model.sampling_rate_hz, model.length_s, model.overlap, model.feature_set)
    hop, length = ext.hop_samples_, ext.length_samples_
    acc = np.asarray(rec.acc)
    gyr = np.asarray(rec.gyr) if with_gyr else None
    seen_acc, seen_gyr = [], []  # what the stream has received (a device keeps its last window's samples)
    starts, reasons, modes = [], [], []
    for i in range(0, len(acc), hop):
        a = acc[i : i + hop]
        seen_acc.append(a)
        if gyr is not None:
            seen_gyr.append(gyr[i : i + hop])
        rows = ext.push(a, gyr[i : i + hop]) if "gyro" in model.feature_set else ext.push(a)
        buf_a = np.vstack(seen_acc)
        buf_g = np.vstack(seen_gyr) if gyr is not None else None
        for r, s in zip(rows, ext.last_starts_, strict=True):
            starts.append(int(s))
            modes.append(str(model.estimator.predict(r[None, :])[0]))
            reasons.append(window_placement_reason(model, buf_a[s : s + length], None if buf_g is None else buf_g[s : s + length]))
    return starts, reasons, modes


@pytest.mark.parametrize("name, with_gyr", [("demo", True), ("demo-acc", False)])
def test_a_streamed_foot_is_flagged_like_the_whole_file(name, with_gyr):
    model = load_model(ROOT / "models" / name)
    rec = simulate_foot(modes=("walk",), duration_s=40.0, sampling_rate_hz=model.sampling_rate_hz, seed=611)
    if not with_gyr:
        rec = rec.__class__(acc=rec.acc, sampling_rate_hz=rec.sampling_rate_hz, meta=rec.meta, check_units=False)
    whole = predict_recording(model, rec, correction=False)
    starts, reasons, modes = _stream(model, rec, with_gyr)
    assert starts == whole["start"].tolist()
    assert modes == whole["mode_raw"].tolist()
    foot_whole = (whole["out_of_domain_reason"].to_numpy(dtype=object) == FOOT_REASON).tolist()
    foot_stream = [r == FOOT_REASON for r in reasons]
    assert foot_stream == foot_whole
    assert np.mean(foot_stream) >= 0.7  # the foot walks all along: most windows hold a stance between swings
    # a flagged window is out of domain on the whole-file path too
    assert not whole["in_domain"].to_numpy(dtype=object)[np.array(foot_stream)].any()


def test_a_streamed_phone_is_not_flagged():
    model = load_model(ROOT / "models" / "demo")
    rec = simulate_dataset(1, 40.0, sampling_rate_hz=model.sampling_rate_hz, seed=612, pose="mixed")[0]
    _, reasons, _ = _stream(model, rec, True)
    assert all(r in ("", FOOT_REASON) for r in reasons)
    assert np.mean([r == FOOT_REASON for r in reasons]) <= 0.05


def test_not_checked_without_a_domain_record_and_bad_shapes_refused():
    import dataclasses

    model = load_model(ROOT / "models" / "demo")
    acc = np.tile([0.0, 0.0, 9.81], (75, 1))
    assert window_placement_reason(model, acc, np.zeros((75, 3))) == ""
    assert window_placement_reason(dataclasses.replace(model, domain=None), acc) is None
    with pytest.raises(InputError, match="one window's samples"):
        window_placement_reason(model, acc[:, :2])
    with pytest.raises(InputError, match="one window's samples"):
        window_placement_reason(model, acc, np.zeros((74, 3)))


def test_empty_short_and_non_finite_windows_and_another_rate_are_refused():
    model = load_model(ROOT / "models" / "demo")
    acc = np.tile([0.0, 0.0, 9.81], (75, 1))
    for a, g in ((np.zeros((0, 3)), np.zeros((0, 3))), (np.zeros((0, 3)), None), (acc[:3], None)):
        with pytest.raises(InputError, match="too short for the foot-placement rule"):
            window_placement_reason(model, a, g)
    bad = acc.copy()
    bad[5] = np.nan
    with pytest.raises(InputError, match="acc samples hold NaN"):
        window_placement_reason(model, bad, np.zeros((75, 3)))
    g = np.zeros((75, 3))
    g[7, 1] = np.inf
    with pytest.raises(InputError, match="gyr samples hold NaN"):
        window_placement_reason(model, acc, g)
    assert window_placement_reason(model, acc, None, sampling_rate_hz=model.sampling_rate_hz) == ""
    with pytest.raises(InputError, match="resample the stream"):
        window_placement_reason(model, acc, None, sampling_rate_hz=100.0)
