"""Exceptions raised by gaitml.

Every error a user can cause derives from :class:`GaitmlError`. The command line
maps them to exit status 2 with a one-line message (see :mod:`gaitml.cli`); any
other exception is an internal error (exit status 1).

Messages follow one pattern: name the problem, the offending value, and the fix,
on one line, e.g. ``"acc looks like it is in g (median |acc| = 1.00); pass
acc_unit='g' or convert to m/s^2."``
"""

from __future__ import annotations

__all__ = ["GaitmlError", "InputError", "ConfigError", "ModelError", "NotAvailableError"]


class GaitmlError(Exception):
    """Base class of every error gaitml raises on purpose."""


class InputError(GaitmlError, ValueError):
    """Bad data or files: shape, NaN/inf, timestamps, format, units, too short."""


class ConfigError(GaitmlError, ValueError):
    """A bad experiment config: names the key, the bad value and the allowed ones."""


class ModelError(GaitmlError):
    """A model artifact that is missing, corrupt, tampered with or incompatible."""


class NotAvailableError(GaitmlError):
    """A registered capability that is not built yet (exit status 2, not a fake result)."""
