"""Range and shape checks of a recording's arrays: values no sensor can produce are refused.

Each check raises :class:`gaitml.errors.InputError` naming the column, the first
offending sample and the limit (:data:`gaitml.consts.ACC_LIMIT_MS2`,
:data:`gaitml.consts.GYR_LIMIT_RADS`); a value that would be in range in another
unit names that unit's fix.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from gaitml.consts import ACC_LIMIT_MS2, DEG2RAD, GRAVITY_MS2, GYR_LIMIT_RADS
from gaitml.errors import InputError

__all__ = ["check_range", "check_ranges", "check_finite", "as_2d3"]


def check_range(name: str, arr: np.ndarray, limit: float, unit: str, alt: tuple[float, str] | None = None) -> None:
    """Raise InputError if any value of ``arr`` (columns x, y, z) is beyond ``limit`` in magnitude.

    Used with :data:`gaitml.consts.ACC_LIMIT_MS2` and :data:`gaitml.consts.GYR_LIMIT_RADS`:
    a value no sensor can output is a corrupt row or a wrong unit, and letting it
    through would overflow downstream sums (1e308). ``alt = (scale, fix)`` names a
    unit fix when the value times ``scale`` would be within the limit (e.g. deg/s).
    """
    if arr.size == 0:
        return
    with np.errstate(invalid="ignore"):
        bad = np.abs(arr) > limit
    if bad.any():
        i, j = (int(v) for v in np.argwhere(bad)[0])
        col = f"{name}_{'xyz'[j]}" if arr.ndim == 2 and arr.shape[1] == 3 else name
        v = float(arr[i, j])
        hint = f" ({alt[1]})" if alt is not None and abs(v) * alt[0] <= limit else ""
        raise InputError(
            f"{col} = {v:.4g} at sample {i} ({int(bad.sum())} value{'s' if int(bad.sum()) != 1 else ''} in all) is beyond any sensor's range "
            f"(|{name}| <= {limit:.4g} {unit}); remove or fix those rows{hint}."
        )


def check_ranges(acc: np.ndarray, gyr: np.ndarray | None, meta: Mapping[str, Any]) -> None:
    """Refuse values beyond any sensor's range (after unit conversion)."""
    conv = meta.get("converted", [])
    check_range(
        "acc",
        acc,
        ACC_LIMIT_MS2,
        "m/s^2",
        None if "acc from g" in conv else (GRAVITY_MS2 / 1000, "if the column is in milli-g, convert it"),
    )
    if gyr is not None:
        check_range(
            "gyr",
            gyr,
            GYR_LIMIT_RADS,
            "rad/s",
            None if "gyr from deg/s" in conv else (DEG2RAD, "if the column is in deg/s, pass --gyr-unit deg/s"),
        )


def as_2d3(name: str, x: Any) -> np.ndarray:
    arr = np.asarray(x, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise InputError(f"`{name}` must have shape (n, 3), got {arr.shape}; pass x, y, z columns.")
    return arr


def check_finite(name: str, arr: np.ndarray) -> None:
    bad = ~np.isfinite(arr)
    if bad.any():
        rows = np.flatnonzero(bad.any(axis=-1) if arr.ndim > 1 else bad)
        raise InputError(
            f"`{name}` has {int(bad.sum())} NaN/inf values (first at sample {int(rows[0])}); remove or interpolate them before loading."
        )
