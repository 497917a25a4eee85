"""Parameter constraints declared once per class (gaitml._base: Interval, Options, "boolean", None), checked by the base."""

from __future__ import annotations

from typing import ClassVar

import numpy as np
import pytest

from gaitml._base import NON_NEGATIVE, POSITIVE, POSITIVE_INTEGER, BaseAlgorithm, Interval, Options
from gaitml.errors import InputError


class _Toy(BaseAlgorithm):
    """A toy algorithm.

    Parameters
    ----------
    rate_hz, count, ratio, mode, flag, window_s, free : the declared parameters.
    """

    _action_method = "run"
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "rate_hz": [POSITIVE],
        "count": [POSITIVE_INTEGER],
        "ratio": [Interval(0, 1, closed="left")],
        "mode": [Options(("a", "b"))],
        "flag": ["boolean"],
        "window_s": [None, NON_NEGATIVE],
    }

    def __init__(self, *, rate_hz=1.0, count=3, ratio=0.5, mode="a", flag=True, window_s=None, free=2.0):
        self.rate_hz = rate_hz
        self.count = count
        self.ratio = ratio
        self.mode = mode
        self.flag = flag
        self.window_s = window_s
        self.free = free

    def run(self):
        self._validate_params()
        self.done_ = True
        return self


def test_valid_parameters_pass_and_the_derived_tuples_follow_the_constraints():
    assert _Toy(window_s=0.0, flag=np.bool_(False), ratio=0.0, count=np.int64(2)).run().done_
    assert _Toy._positive == ("rate_hz", "count") and _Toy._non_negative == ("ratio", "window_s") and _Toy._integer == ("count",)


@pytest.mark.parametrize(
    ("params", "message"),
    [
        ({"rate_hz": 0.0}, "`rate_hz` must be a positive number, got 0.0."),
        ({"rate_hz": "x"}, "`rate_hz` must be a positive number, got 'x'; pass a number."),
        ({"count": 2.5}, "`count` must be a positive integer, got 2.5."),
        ({"ratio": 1.0}, "`ratio` must be a number in [0, 1), got 1.0."),
        ({"mode": "c"}, "`mode` must be one of 'a', 'b', got 'c'."),
        ({"flag": 1}, "`flag` must be true or false, got 1."),
        ({"window_s": -1.0}, "`window_s` must be None or a non-negative number, got -1.0."),
        ({"free": float("nan")}, "`free` must be a finite number, got nan."),
    ],
)
def test_a_violation_is_one_line_naming_the_parameter_and_the_allowed_values(params, message):
    with pytest.raises(InputError) as err:
        _Toy(**params).run()
    assert str(err.value) == message and "\n" not in str(err.value)
