"""The one base class of every gaitml algorithm (step / ZUPT detectors, heading sources, ...).

Built on :class:`sklearn.base.BaseEstimator` (scikit-learn is already a core
dependency), which gives signature-based ``get_params(deep)``, ``set_params``,
``sklearn.base.clone`` and the repr with no new dependency. The contract
(gaitmap / scikit-learn style, STYLE.md):

- ``__init__`` only stores its keyword arguments under the same names: no
  computation, no validation, no ``**params``.
- The action method (``detect``, ``estimate``, ``fit``) validates the
  parameters, computes, stores its results in attributes ending in ``_`` and
  returns ``self``. Fitted values never overwrite a parameter, and the action
  never modifies its input.
- Parameter constraints are declared once per class in ``_parameter_constraints``
  (scikit-learn's style): parameter name -> list of accepted forms, an
  :class:`Interval`, :class:`Options`, ``"boolean"`` or ``None`` (None accepted).
  :meth:`BaseAlgorithm._validate_params` checks them before any work; every other
  numeric parameter must be a finite number. A violation raises
  :class:`gaitml.errors.InputError`, one line naming the parameter, the allowed
  values and the value given.
"""

from __future__ import annotations

import dataclasses
import numbers
import warnings
from typing import ClassVar

import numpy as np
from sklearn.base import BaseEstimator

from gaitml.errors import InputError

__all__ = [
    "BaseAlgorithm",
    "Interval",
    "NON_NEGATIVE",
    "NON_NEGATIVE_INTEGER",
    "Options",
    "POSITIVE",
    "POSITIVE_INTEGER",
    "Registry",
    "check_number",
]


def check_number(name: str, value, *, positive: bool = False, non_negative: bool = False, integer: bool = False) -> float:
    """Return ``value`` as a float after checking it; InputError naming ``name`` otherwise."""
    kind = "a positive " if positive else "a non-negative " if non_negative else "a finite "
    kind += "integer" if integer else "number"
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"`{name}` must be {kind}, got {value!r}; pass a number.")
    v = float(value)
    if not np.isfinite(v) or (positive and v <= 0) or (non_negative and v < 0) or (integer and v != int(v)):
        raise InputError(f"`{name}` must be {kind}, got {value!r}.")
    return v


def _is_number(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


@dataclasses.dataclass(frozen=True)
class Interval:
    """A numeric parameter's range: ``left`` / ``right`` (None: unbounded), ``closed`` ends, whole numbers only with ``integer``.

    ``closed`` is ``"both"``, ``"left"``, ``"right"`` or ``"neither"`` (scikit-learn's
    ``Interval``). The value must be a finite number in the range.
    """

    left: float | None = None
    right: float | None = None
    closed: str = "both"
    integer: bool = False

    def accepts(self, value) -> bool:
        """Whether ``value`` is a finite number (whole with ``integer``) in the range."""
        if not _is_number(value):
            return False
        v = float(value)
        if not np.isfinite(v) or (self.integer and v != int(v)):
            return False
        if self.left is not None and (v < self.left or (v == self.left and self.closed not in ("both", "left"))):
            return False
        return self.right is None or not (v > self.right or (v == self.right and self.closed not in ("both", "right")))

    def describe(self) -> str:
        """The range in words: ``a positive number``, ``a non-negative integer``, ``a number in (0, 1)``."""
        what = "integer" if self.integer else "number"
        if self.right is None and self.left == 0:
            return f"a {'positive' if self.closed in ('right', 'neither') else 'non-negative'} {what}"
        if self.right is None and self.left is None:
            return f"a finite {what}"
        lo = "-inf" if self.left is None else f"{self.left:g}"
        hi = "inf" if self.right is None else f"{self.right:g}"
        return f"a {what} in {'[' if self.closed in ('both', 'left') else '('}{lo}, {hi}{']' if self.closed in ('both', 'right') else ')'}"


@dataclasses.dataclass(frozen=True)
class Options:
    """A parameter that takes one of a few values (e.g. names)."""

    values: tuple

    def accepts(self, value) -> bool:
        """Whether ``value`` is one of :attr:`values`."""
        return any(type(value) is type(v) and value == v for v in self.values)

    def describe(self) -> str:
        """The values in words: ``one of 'a', 'b'``."""
        return "one of " + ", ".join(repr(v) for v in self.values)


def _accepts(constraint, value) -> bool:
    if constraint is None:
        return value is None
    if constraint == "boolean":
        return isinstance(value, bool | np.bool_)
    return constraint.accepts(value)


def _describe(constraint) -> str:
    if constraint is None:
        return "None"
    if constraint == "boolean":
        return "true or false"
    return constraint.describe()


#: The common numeric ranges.
POSITIVE = Interval(0, None, closed="neither")
NON_NEGATIVE = Interval(0, None, closed="left")
POSITIVE_INTEGER = Interval(0, None, closed="neither", integer=True)
NON_NEGATIVE_INTEGER = Interval(0, None, closed="left", integer=True)


class BaseAlgorithm(BaseEstimator):
    """Parameters in ``__init__``, results ending in ``_``, one action method returning ``self``.

    Subclasses name their action in ``_action_method`` and declare their parameters'
    allowed values in ``_parameter_constraints``; the action calls
    :meth:`_validate_params` first. ``_positive``, ``_non_negative`` and ``_integer``
    are derived from the constraints (the names whose every numeric form is > 0,
    >= 0, whole), for tests that probe them.
    """

    #: name of the action method (``detect``, ``estimate`` or ``fit``)
    _action_method: ClassVar[str] = ""
    #: parameter name -> accepted forms (:class:`Interval`, :class:`Options`, ``"boolean"``, ``None``)
    _parameter_constraints: ClassVar[dict[str, list]] = {}
    _positive: ClassVar[tuple[str, ...]] = ()
    _non_negative: ClassVar[tuple[str, ...]] = ()
    _integer: ClassVar[tuple[str, ...]] = ()

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        cons = cls._parameter_constraints
        intervals = {k: [c for c in v if isinstance(c, Interval)] for k, v in cons.items()}
        cls._positive = tuple(
            k
            for k, iv in intervals.items()
            if iv and all(c.left is not None and c.left >= 0 and (c.left > 0 or c.closed in ("right", "neither")) for c in iv)
        )
        cls._non_negative = tuple(
            k for k, iv in intervals.items() if iv and k not in cls._positive and all(c.left is not None and c.left >= 0 for c in iv)
        )
        cls._integer = tuple(k for k, iv in intervals.items() if iv and all(c.integer for c in iv))

    @classmethod
    def _get_param_names(cls) -> list[str]:
        """The ``__init__`` parameter names (scikit-learn's signature lookup), cached per class.

        ``inspect.signature`` costs tens of microseconds; the detectors validate their
        parameters on every call, so the names are read once per class.
        """
        names = cls.__dict__.get("_param_names")
        if names is None:
            names = tuple(super()._get_param_names())
            cls._param_names = names
        return list(names)

    def _validate_params(self) -> dict:
        """Check every parameter against its declared constraints (others: numbers finite); returns ``get_params(deep=False)``."""
        params = self.get_params(deep=False)
        constraints = self._parameter_constraints
        for name, value in params.items():
            cons = constraints.get(name)
            if cons is not None:
                if not any(_accepts(c, value) for c in cons):
                    allowed = " or ".join(_describe(c) for c in cons)
                    fix = "; pass a number." if len(cons) == 1 and isinstance(cons[0], Interval) and not _is_number(value) else "."
                    raise InputError(f"`{name}` must be {allowed}, got {value!r}{fix}")
            elif _is_number(value):
                check_number(name, value)
            elif isinstance(value, tuple) and value and all(_is_number(v) for v in value):
                for v in value:
                    check_number(name, v)
        return params


class Registry(dict):
    """Algorithm classes by their CLI name (``gaitml.steps.DETECTORS``, ``gaitml.zupt.DETECTORS``), one way for every family.

    A ``dict`` of name -> class that also builds instances: :meth:`create` raises
    :class:`~gaitml.errors.InputError` naming the valid names for an unknown name and
    the class's help for unknown parameters. ``deprecated`` maps old names to current
    ones: accepted by :meth:`create` with a DeprecationWarning, not listed.

    Parameters
    ----------
    kind : str
        What the entries are, for messages ("step detector").
    entries : dict
        Name -> class, in the order ``--help`` lists them.
    module : str
        The public module the classes are documented in (``gaitml.steps``).
    deprecated : dict, optional
        Old name -> registry name.
    """

    def __init__(self, kind: str, entries: dict, *, module: str, deprecated: dict | None = None):
        super().__init__(entries)
        self.kind = kind
        self.module = module
        self.deprecated = dict(deprecated or {})

    def names(self) -> tuple[str, ...]:
        """The registered names, in order."""
        return tuple(self)

    def create(self, name: str, **params):
        """An instance of the class registered as ``name`` with ``params``."""
        if name in self.deprecated:
            warnings.warn(f"the {self.kind} name {name!r} is deprecated; use {self.deprecated[name]!r}.", DeprecationWarning, stacklevel=3)
            name = self.deprecated[name]
        if name not in self:
            raise InputError(f"unknown {self.kind} {name!r}; valid names: {', '.join(self)}.")
        cls = self[name]
        try:
            return cls(**params)
        except TypeError as exc:
            raise InputError(f"bad parameters for {self.kind} {name!r}: {exc}; see help({self.module}.{cls.__name__}).") from None
