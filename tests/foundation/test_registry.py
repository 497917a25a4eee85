"""The step and ZUPT detector registries work the same way (gaitml._base.Registry), and so do detect_steps / detect_zupts."""

from __future__ import annotations

import pandas as pd
import pytest

from gaitml._base import Registry
from gaitml.errors import InputError
from gaitml.steps import DETECTORS as STEP_DETECTORS
from gaitml.steps import detect_steps
from gaitml.zupt import DETECTORS as ZUPT_DETECTORS
from gaitml.zupt import detect_zupts
from tests.pdr.synth import synth_walk


@pytest.mark.parametrize(("registry", "kind"), [(STEP_DETECTORS, "step detector"), (ZUPT_DETECTORS, "zero-velocity detector")])
def test_both_registries_name_build_and_refuse_alike(registry, kind):
    assert isinstance(registry, Registry) and registry.kind == kind
    name = registry.names()[0]
    assert type(registry.create(name)) is registry[name]
    with pytest.raises(InputError, match=f"unknown {kind} 'nope'; valid names: {name}, "):
        registry.create("nope")
    with pytest.raises(InputError, match=f"bad parameters for {kind} '{name}'.*see help"):
        registry.create(name, no_such_parameter=1)


def test_a_deprecated_zupt_name_still_works_with_a_warning():
    with pytest.warns(DeprecationWarning, match="'method1' is deprecated; use 'gyro-range'"):
        det = ZUPT_DETECTORS.create("method1")
    assert type(det) is ZUPT_DETECTORS["gyro-range"] and "method1" not in ZUPT_DETECTORS


def test_detect_steps_and_detect_zupts_return_the_same_kind_of_thing():
    rec = synth_walk([("walk", 20, 0.0)], noise=0.05)
    steps, zupts = detect_steps(rec), detect_zupts(rec, "magnitude")
    assert isinstance(steps, pd.DataFrame) and isinstance(zupts, pd.DataFrame)  # the result tables
    det_s, det_z = detect_steps(rec, return_detector=True), detect_zupts(rec, "magnitude", return_detector=True)
    pd.testing.assert_frame_equal(det_s.steps_, steps)
    pd.testing.assert_frame_equal(det_z.zupts_, zupts)
    assert len(steps) >= 15  # a 20-step walk: the table is the detector's, not an empty stand-in
