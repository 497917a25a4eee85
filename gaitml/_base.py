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
- Every numeric parameter must be a finite number (checked by
  :meth:`BaseAlgorithm._validate_params` before any work); parameters named in
  ``_positive`` must be > 0 and those in ``_non_negative`` >= 0. A violation
  raises :class:`gaitml.errors.InputError` naming the parameter.
"""

from __future__ import annotations

import numbers
import warnings
from typing import ClassVar

import numpy as np
from sklearn.base import BaseEstimator

from gaitml.errors import InputError

__all__ = ["BaseAlgorithm", "Registry", "check_number"]


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


class BaseAlgorithm(BaseEstimator):
    """Parameters in ``__init__``, results ending in ``_``, one action method returning ``self``.

    Subclasses name their action in ``_action_method`` and list bounded numeric
    parameters in ``_positive`` / ``_non_negative`` / ``_integer``; the action calls
    :meth:`_validate_params` first.
    """

    #: name of the action method (``detect``, ``estimate`` or ``fit``)
    _action_method: ClassVar[str] = ""
    #: numeric parameters that must be > 0, >= 0, or whole numbers
    _positive: ClassVar[tuple[str, ...]] = ()
    _non_negative: ClassVar[tuple[str, ...]] = ()
    _integer: ClassVar[tuple[str, ...]] = ()

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
        """Check every numeric parameter (finite; the declared bounds); returns ``get_params(deep=False)``."""
        params = self.get_params(deep=False)
        for name, value in params.items():
            bounded = name in self._positive or name in self._non_negative or name in self._integer
            if bounded or (isinstance(value, numbers.Real) and not isinstance(value, bool)):
                check_number(
                    name,
                    value,
                    positive=name in self._positive,
                    non_negative=name in self._non_negative,
                    integer=name in self._integer,
                )
            elif isinstance(value, tuple) and value and all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in value):
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
