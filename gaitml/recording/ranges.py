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

__all__ = ["check_range", "check_ranges", "check_finite", "as_2d3", "RangeTally", "range_violations"]


def range_violations(arr: np.ndarray, limit: float) -> tuple[int, int, float, int] | None:
    """``(first sample, its column, its value, number of values)`` beyond ``limit`` in magnitude, or None."""
    if arr.size == 0:
        return None
    with np.errstate(invalid="ignore"):
        bad = np.abs(arr) > limit
    if not bad.any():
        return None
    i, j = (int(v) for v in np.argwhere(bad)[0])
    return i, j, float(arr[i, j]), int(bad.sum())


def range_message(
    name: str, first: tuple[int, int, float, int], limit: float, unit: str, alt: tuple[float, str] | None, xyz: bool = True
) -> str:
    """The one-line refusal of :func:`check_range` for a violation found by :func:`range_violations`."""
    i, j, v, count = first
    col = f"{name}_{'xyz'[j]}" if xyz else name
    hint = f" ({alt[1]})" if alt is not None and abs(v) * alt[0] <= limit else ""
    return (
        f"{col} = {v:.4g} at sample {i} ({count} value{'s' if count != 1 else ''} in all) is beyond any sensor's range "
        f"(|{name}| <= {limit:.4g} {unit}); remove or fix those rows{hint}."
    )


def check_range(name: str, arr: np.ndarray, limit: float, unit: str, alt: tuple[float, str] | None = None) -> None:
    """Raise InputError if any value of ``arr`` (columns x, y, z) is beyond ``limit`` in magnitude.

    Used with :data:`gaitml.consts.ACC_LIMIT_MS2` and :data:`gaitml.consts.GYR_LIMIT_RADS`:
    a value no sensor can output is a corrupt row or a wrong unit, and letting it
    through would overflow downstream sums (1e308). ``alt = (scale, fix)`` names a
    unit fix when the value times ``scale`` would be within the limit (e.g. deg/s).
    """
    first = range_violations(arr, limit)
    if first is not None:
        raise InputError(range_message(name, first, limit, unit, alt, xyz=arr.ndim == 2 and arr.shape[1] == 3))


def _range_specs(meta: Mapping[str, Any]) -> dict[str, tuple[float, str, tuple[float, str] | None]]:
    conv = meta.get("converted", [])
    return {
        "acc": (ACC_LIMIT_MS2, "m/s^2", None if "acc from g" in conv else (GRAVITY_MS2 / 1000, "if the column is in milli-g, convert it")),
        "gyr": (
            GYR_LIMIT_RADS,
            "rad/s",
            None if "gyr from deg/s" in conv else (DEG2RAD, "if the column is in deg/s, pass --gyr-unit deg/s"),
        ),
    }


class RangeTally:
    """Range checks of a recording seen in consecutive blocks: the first violation and the count over all of them.

    :meth:`raise_first` raises what :func:`check_ranges` raises on the whole
    recording (acc before gyr, the first sample, the number of values in all).
    """

    def __init__(self, meta: Mapping[str, Any]):
        self.specs = _range_specs(meta)
        self.first: dict[str, tuple[int, int, float, int] | None] = {"acc": None, "gyr": None}
        self.count = {"acc": 0, "gyr": 0}

    def add(self, acc: np.ndarray, gyr: np.ndarray | None, offset: int = 0) -> None:
        """Check one block whose first sample is sample ``offset`` of the recording."""
        for name, arr in (("acc", acc), ("gyr", gyr)):
            if arr is None:
                continue
            found = range_violations(arr, self.specs[name][0])
            if found is None:
                continue
            self.count[name] += found[3]
            if self.first[name] is None:
                self.first[name] = (found[0] + offset, found[1], found[2], 0)

    def raise_first(self) -> None:
        """Raise the InputError of the first channel with a violation (acc, then gyr), if any."""
        for name in ("acc", "gyr"):
            if self.first[name] is not None:
                i, j, v, _ = self.first[name]
                limit, unit, alt = self.specs[name]
                raise InputError(range_message(name, (i, j, v, self.count[name]), limit, unit, alt))


def check_ranges(acc: np.ndarray, gyr: np.ndarray | None, meta: Mapping[str, Any]) -> None:
    """Refuse values beyond any sensor's range (after unit conversion)."""
    tally = RangeTally(meta)
    tally.add(acc, gyr)
    tally.raise_first()


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
