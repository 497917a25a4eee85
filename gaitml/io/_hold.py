"""Sample-and-hold streams: a sensor's last value repeated on rows written for other sensors.

Multi-sensor loggers that write one row per event of *any* sensor (Physics
Toolbox Sensor Suite's multi-record CSV, AndroSensor at a short interval) fill
each sensor's columns with its last value until it updates again. Read row by
row, such a stream looks sampled at the row rate (e.g. 52.7 Hz) while the
sensor changed only at its own rate (e.g. 14.7 Hz), and interpolation onto the
row times turns each sensor's samples into staircases: a silent wrong answer.

Rule (:func:`dehold`): a row whose three axes all equal the previous row's
exactly is a *repeat*. A real sensor sampled at its own rate repeats all three
axes only rarely (quantisation at rest); when at least :data:`HOLD_FRACTION` of
the rows are repeats, at least half of the repeats are in short holds (at most
:data:`SHORT_RUN_ROWS` rows), there are at least :data:`MIN_UPDATES` updates and they
span at least half the stream (a constant signal, or one still for a long stretch, is
not a hold pattern), the stream is a sample-and-hold stream
and is read at its update times: the first row of each run of equal values, timed by that row (the
moment the new value appeared). The row rate, the update rate and the number of
repeats go into ``meta['sample_and_hold']`` and a warning line; a too-low update
rate is then refused by the rate check with the rate named.
"""

from __future__ import annotations

import numpy as np

__all__ = ["HOLD_FRACTION", "dehold", "hold_pattern", "note_hold"]

#: Fraction of rows repeating the previous row exactly above which a stream is sample-and-hold.
HOLD_FRACTION = 0.3
#: Fewer updates than this is a constant signal, not a sample-and-hold stream.
MIN_UPDATES = 10
#: A hold of at most this many rows is a short hold (a sensor updating at >= 1/20 of the row rate).
SHORT_RUN_ROWS = 20


def dehold(t: np.ndarray, x: np.ndarray, what: str, *, hold_fraction: float = HOLD_FRACTION) -> tuple[np.ndarray, np.ndarray, dict | None]:
    """Keep only the update rows of a sample-and-hold stream (module doc); unchanged otherwise.

    Parameters
    ----------
    t : ndarray (n,)
        Row times (s), increasing.
    x : ndarray (n, k)
        The sensor's axes.
    what : str
        Names the sensor in the returned note.

    Returns
    -------
    t, x : the update rows (or the input unchanged).
    info : dict or None
        ``rows``, ``updates``, ``repeat_fraction``, ``row_rate_hz``, ``update_rate_hz``
        and a ``warning`` line when the stream was sample-and-hold, else None.
    """
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    n = len(t)
    if n < 10:
        return t, x, None
    same = np.r_[False, np.all(x[1:] == x[:-1], axis=1)]
    info = hold_pattern(t, same, what, hold_fraction=hold_fraction)
    if info is None:
        return t, x, None
    keep = ~same
    return t[keep], x[keep], info


def hold_pattern(t: np.ndarray, same: np.ndarray, what: str, *, hold_fraction: float = HOLD_FRACTION) -> dict | None:
    """The decision of :func:`dehold` from the row times and the repeat mask (``same[i]``: row ``i``
    equals row ``i - 1`` on every axis): its ``info`` for a sample-and-hold stream, else None.

    The chunked reader's first pass builds the mask block by block and asks the same question.
    """
    t = np.asarray(t, dtype=float)
    same = np.asarray(same, dtype=bool)
    n = len(t)
    if n < 10:
        return None
    frac = float(same.mean())
    if frac < hold_fraction:
        return None
    keep = ~same
    dur = float(t[-1] - t[0])
    up = np.flatnonzero(keep)
    runs = np.diff(np.r_[up, n])  # rows each update is held for
    # a hold pattern repeats nearly every update, all through the stream; a constant or mostly still
    # signal (one long run, or single repeats) is not one
    short = runs[runs <= SHORT_RUN_ROWS]
    spread = (short - 1).sum() / max(1, int(same.sum()))  # share of the repeats in short holds
    if len(up) < MIN_UPDATES or spread < 0.5 or (t[up[-1]] - t[up[0]]) < 0.5 * dur:
        return None
    row_rate = (n - 1) / dur if dur > 0 else float("nan")
    n_up = int(keep.sum())
    up_rate = (n_up - 1) / float(t[keep][-1] - t[keep][0]) if n_up > 1 and t[keep][-1] > t[keep][0] else float("nan")
    info = {
        "rows": n,
        "updates": n_up,
        "repeat_fraction": round(frac, 4),
        "row_rate_hz": round(row_rate, 3),
        "update_rate_hz": round(up_rate, 3),
    }
    info["warning"] = (
        f"the {what} repeats its last value on {100 * frac:.0f} % of the rows (sample-and-hold: a row is written whenever any sensor "
        f"updates); read at its own update rate {up_rate:.1f} Hz ({n_up} updates), not the {row_rate:.1f} Hz row rate"
    )
    return info


def note_hold(meta: dict, key: str, t: np.ndarray, x: np.ndarray, info: dict | None) -> tuple[np.ndarray, np.ndarray]:
    """Record :func:`dehold`'s ``info`` in ``meta['sample_and_hold'][key]`` and ``meta['warnings']``; return ``t, x``."""
    if info:
        meta.setdefault("sample_and_hold", {})[key] = info
        meta.setdefault("warnings", []).append(info["warning"])
    return t, x
