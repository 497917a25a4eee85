"""The algorithm API contract, checked on every registered algorithm (gaitml._base).

Parametrised over the registries (``gaitml.steps.DETECTORS``, ``gaitml.zupt.DETECTORS``,
``gaitml.pdr.HEADING_SOURCES``) plus the step length model, the attitude estimator and the
adjacent-window corrector, so a newly registered algorithm is covered automatically:
``sklearn.base.clone`` round trip, ``set_params`` (unknown names raise), every ``__init__``
parameter documented in the numpydoc "Parameters" section, the action returns ``self``,
the input is not modified, results end in ``_``, and a bad numeric parameter (NaN; a
negative value where it must be positive) raises InputError naming the parameter.
"""

from __future__ import annotations

import copy
import inspect
import numbers
import re

import numpy as np
import pandas as pd
import pytest
from sklearn.base import clone

from gaitml._base import BaseAlgorithm
from gaitml.errors import InputError
from gaitml.labels import IntervalLabeller
from gaitml.pdr import HEADING_SOURCES, AttitudeEstimator, StepLengthModel, step_length_features
from gaitml.postprocess import AdjacentWindowCorrector
from gaitml.steps import DETECTORS as STEP_DETECTORS
from gaitml.steps import SinglePeakStepDetector
from gaitml.zupt import DETECTORS as ZUPT_DETECTORS
from tests.pdr.synth import synth_walk

ALGORITHMS = (
    [pytest.param(c, id=f"steps:{n}") for n, c in STEP_DETECTORS.items()]
    + [pytest.param(c, id=f"zupt:{n}") for n, c in ZUPT_DETECTORS.items()]
    + [pytest.param(c, id=f"heading:{n}") for n, c in HEADING_SOURCES.items()]
    + [pytest.param(c, id=c.__name__) for c in (StepLengthModel, AttitudeEstimator, AdjacentWindowCorrector, IntervalLabeller)]
)


@pytest.fixture(scope="module")
def inputs():
    rec = synth_walk([("walk", 20, np.pi / 2), ("backward", 12, 0.0)], noise=0.05)
    steps = SinglePeakStepDetector().detect(rec).steps_
    steps = steps.assign(mode=np.where(np.arange(len(steps)) < len(steps) // 2, "walk", "backward"))
    steps.attrs = {"event": "t_peak_s", "sampling_rate_hz": rec.sampling_rate_hz}
    feats = step_length_features(rec.acc, steps, rec.sampling_rate_hz)
    lengths = np.full(len(steps), 0.7)
    labels = np.array(["walk", "walk", "run", "walk", "side_left", "side_left", "walk"])
    return {"rec": rec, "steps": steps, "feats": feats, "lengths": lengths, "modes": steps["mode"].to_numpy(), "labels": labels}


def _args(cls, inputs) -> tuple:
    """Positional arguments of the class's action method."""
    if cls in STEP_DETECTORS.values() or cls in ZUPT_DETECTORS.values() or cls is AttitudeEstimator:
        return (inputs["rec"],)
    if cls in HEADING_SOURCES.values():
        return (inputs["rec"], inputs["steps"])
    if cls is StepLengthModel:
        return (inputs["feats"], inputs["lengths"], inputs["modes"])
    if cls is AdjacentWindowCorrector:
        return (inputs["labels"],)
    if cls is IntervalLabeller:
        d = inputs["rec"].duration_s
        return (inputs["rec"], pd.DataFrame({"start_s": [0.0, d / 2], "end_s": [d / 2, d], "label": ["walk", "backward"]}))
    raise AssertionError(f"no test input for {cls.__name__}; add one to _args")


def _act(obj, inputs):
    return getattr(obj, obj._action_method)(*_args(type(obj), inputs))


def _snapshot(args) -> list:
    out = []
    for a in args:
        if hasattr(a, "acc"):  # Recording
            out.append(("rec", a.acc.copy(), None if a.gyr is None else a.gyr.copy(), copy.deepcopy(a.reference), a.sampling_rate_hz))
        else:
            out.append(copy.deepcopy(a))
    return out


def _equal(a, b) -> bool:
    if type(a) is not type(b):
        return False
    if isinstance(a, (tuple, list)):
        return len(a) == len(b) and all(_equal(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, pd.Series):
        return a.equals(b)
    if isinstance(a, pd.DataFrame):
        return a.equals(b) and a.attrs == b.attrs and list(a.columns) == list(b.columns)
    if isinstance(a, np.ndarray):
        return a.shape == b.shape and np.array_equal(a, b, equal_nan=a.dtype.kind == "f")
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_equal(a[k], b[k]) for k in a)
    return a == b


def _numeric_params(obj) -> list[str]:
    return [
        k
        for k, v in obj.get_params(deep=False).items()
        if (isinstance(v, numbers.Real) and not isinstance(v, bool)) or k in obj._positive or k in obj._non_negative
    ]


def _documented(cls) -> set[str]:
    doc = inspect.getdoc(cls) or ""
    m = re.search(r"^Parameters\n-+\n(.*?)(?:\n\n[A-Z][A-Za-z ]+\n-+\n|\Z)", doc, flags=re.S | re.M)
    if not m:
        return set()
    names: set[str] = set()
    for line in m.group(1).splitlines():
        if line and not line.startswith(" "):
            head = line.split(" : ")[0]
            names.update(n.strip() for n in head.split(","))
    return names


def test_every_registered_algorithm_is_a_base_algorithm():
    for p in ALGORITHMS:
        cls = p.values[0]
        assert issubclass(cls, BaseAlgorithm), cls
        assert cls._action_method, cls


@pytest.mark.parametrize("cls", ALGORITHMS)
def test_clone_round_trip(cls):
    obj = cls()
    twin = clone(obj)
    assert twin is not obj and type(twin) is cls
    assert repr(twin) == repr(obj)
    for name in _numeric_params(obj)[:1]:
        obj.set_params(**{name: obj.get_params()[name] * 0.5 + 1})
        assert clone(obj).get_params(deep=False)[name] == obj.get_params(deep=False)[name]


@pytest.mark.parametrize("cls", ALGORITHMS)
def test_init_only_stores_its_parameters(cls):
    sig = inspect.signature(cls.__init__)
    names = [p for p in sig.parameters if p != "self"]
    assert all(sig.parameters[p].kind is not inspect.Parameter.VAR_KEYWORD for p in names), "no **params"
    obj = cls()
    assert set(vars(obj)) == set(names), f"__init__ must store exactly its parameters: {sorted(vars(obj))} vs {names}"


@pytest.mark.parametrize("cls", ALGORITHMS)
def test_set_params_and_unknown_params(cls):
    obj = cls()
    params = obj.get_params(deep=False)
    for name, value in params.items():
        assert obj.set_params(**{name: value}) is obj
    with pytest.raises(ValueError, match="no_such_parameter"):
        obj.set_params(no_such_parameter=1)


@pytest.mark.parametrize("cls", ALGORITHMS)
def test_every_parameter_is_documented(cls):
    params = set(cls().get_params(deep=False))
    missing = params - _documented(cls)
    assert not missing, f"{cls.__name__}: parameters missing from the numpydoc 'Parameters' section: {sorted(missing)}"


@pytest.mark.parametrize("cls", ALGORITHMS)
def test_action_returns_self_keeps_input_and_results_end_in_underscore(cls, inputs):
    obj = cls()
    params_before = copy.deepcopy(obj.get_params(deep=False))
    args = _args(cls, inputs)
    before = _snapshot(args)
    assert _act(obj, inputs) is obj
    assert _equal(_snapshot(args), before), "the action modified its input"
    assert repr(obj.get_params(deep=False)) == repr(params_before), "the action changed a parameter"
    new = [k for k in vars(obj) if k not in params_before and not k.startswith("_")]
    assert new, "the action stored no result"
    assert all(k.endswith("_") for k in new), f"results must end in '_': {[k for k in new if not k.endswith('_')]}"


def _bad_cases():
    for p in ALGORITHMS:
        cls = p.values[0]
        obj = cls()
        for name in _numeric_params(obj):
            yield pytest.param(cls, name, float("nan"), id=f"{p.id}-{name}-nan")
            if name in obj._positive or name in obj._non_negative:
                yield pytest.param(cls, name, -1.0, id=f"{p.id}-{name}-negative")


@pytest.mark.parametrize(("cls", "name", "value"), list(_bad_cases()))
def test_bad_parameter_raises_input_error_naming_it(cls, name, value, inputs):
    obj = cls().set_params(**{name: value})
    with pytest.raises(InputError, match=f"`{name}`"):
        _act(obj, inputs)


@pytest.mark.parametrize("cls", [p for p in ALGORITHMS if p.values[0] in HEADING_SOURCES.values()])
def test_heading_sources_nest_the_attitude_estimator(cls, inputs):
    obj = cls(attitude=AttitudeEstimator(initial_heading_rad=0.3))
    deep = obj.get_params(deep=True)
    assert deep["attitude__initial_heading_rad"] == 0.3
    twin = clone(obj)
    assert twin.attitude is not obj.attitude and twin.attitude.initial_heading_rad == 0.3
    obj.set_params(attitude__initial_heading_rad=0.5)
    assert obj.attitude.initial_heading_rad == 0.5
    h = obj.estimate(inputs["rec"], inputs["steps"]).heading_rad_
    assert h.shape == (len(inputs["steps"]),) and np.isfinite(h).all()
    assert not hasattr(obj.attitude, "rotation_"), "the nested estimator given as a parameter is not fitted in place"
