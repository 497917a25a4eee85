"""Adjacent-window correction of motion-mode labels (paper 003 sec. 3.4).

The paper assumes a pedestrian switches mode at most once within a 1.5 s
window. With four consecutive window labels W1, W2, W3, W4 (W4 the current
window), the previous window W3 is corrected:

1. if W2 != W3 and W2 != W4 and W3 != W4 and W1 == W2, then W3 = W2;
2. otherwise, if W2 == W4 and W2 != W3 (hence W3 != W4), then W3 = W2;
3. otherwise W3 is kept.

Reading of the text (documented choices)
-----------------------------------------
- **Feedback**: the paper writes the rule as an assignment ("令 W3 = W2") on the
  label sequence as it is processed online, so W1 and W2 are the labels
  *already output* (corrected), while W3 and W4 are raw classifier outputs
  (W3 is being decided, W4 is current). This is what a streaming device holding
  its output history computes, and offline processing is the same left-to-right
  pass, so streaming == offline exactly.
- **Edges**: the first window has no W1, W2 and is never changed; the second
  window (W2 = first window, no W1) can only be changed by rule 2, which does
  not involve W1; the last window has no W4 and is kept.
- **Delay**: causal with a one-window delay: the label of window k is final
  once window k + 1 has been classified.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitml._base import BaseAlgorithm

__all__ = ["adjacent_window_correction", "AdjacentWindowCorrector"]

_MISSING = object()


def _correct(w1: Any, w2: Any, w3: Any, w4: Any) -> Any:
    """Corrected W3 given W1..W4 (paper 003 sec. 3.4); a missing W1/W2 is ``_MISSING``."""
    if w2 is _MISSING:
        return w3
    if w1 is not _MISSING and w2 != w3 and w2 != w4 and w3 != w4 and w1 == w2:
        return w2  # rule 1: an isolated label between two different neighbours, history stable
    if w2 == w4 and w2 != w3:
        return w2  # rule 2: a single-window blip inside a run
    return w3  # rule 3


def adjacent_window_correction(labels) -> np.ndarray:
    """Correct a whole sequence of window labels (paper 003 sec. 3.4).

    Parameters
    ----------
    labels : sequence, shape (n,)
        Predicted labels of consecutive windows, in time order.

    Returns
    -------
    ndarray, shape (n,)
        Corrected labels, same dtype as ``np.asarray(labels)``. Identical to
        feeding :class:`AdjacentWindowCorrector` one label at a time and flushing.

    Notes
    -----
    A left-to-right pass where W1, W2 are the already corrected labels (see the
    module docstring). The loop is over windows (about one per 0.75 s of
    data), with plain Python comparisons on a list.
    """
    arr = np.asarray(labels)
    if arr.ndim != 1:
        from gaitml.errors import InputError

        raise InputError(f"`labels` must be 1-D (one label per window), got shape {arr.shape}.")
    seq = arr.tolist()
    out = list(seq)
    for k in range(1, len(seq) - 1):
        w2 = out[k - 1]
        w1 = out[k - 2] if k >= 2 else _MISSING
        out[k] = _correct(w1, w2, seq[k], seq[k + 1])
    return np.asarray(out, dtype=arr.dtype) if len(out) else arr.copy()


class AdjacentWindowCorrector(BaseAlgorithm):
    """Adjacent-window correction as an algorithm object: offline ``correct`` and streaming ``push``.

    ``correct(labels)`` corrects a whole sequence (sets ``labels_``, returns ``self``;
    the input is not modified). For streaming, ``push(label_k)`` takes the classifier
    output of window k and returns the final (corrected) label of window k - 1, or
    ``None`` on the first push; ``flush()`` returns the final label of the last pushed
    window (kept as is: it has no successor) or ``None`` if nothing is pending.
    Pushing a whole sequence and flushing gives :func:`adjacent_window_correction`.

    Parameters
    ----------
    None: the rule of paper 003 sec. 3.4 has no parameters.

    Attributes
    ----------
    labels_ : ndarray
        The corrected labels of the last ``correct`` call.
    history_ : list
        The last (up to two) corrected labels output: W1, W2 of the next decision.
    """

    _action_method = "correct"

    def __init__(self) -> None:
        pass

    def correct(self, labels) -> AdjacentWindowCorrector:
        """Correct a whole sequence of window labels; sets ``labels_`` and returns ``self``."""
        self.labels_ = adjacent_window_correction(labels)
        return self

    def reset(self) -> AdjacentWindowCorrector:
        """Start a new sequence."""
        self.history_: list = []
        self._pending: Any = _MISSING
        return self

    def push(self, label: Any) -> Any:
        """Add the current window's label; return the corrected previous label or None."""
        if not hasattr(self, "history_"):
            self.reset()
        if self._pending is _MISSING:
            self._pending = label
            return None
        h = self.history_
        w2 = h[-1] if h else _MISSING
        w1 = h[-2] if len(h) >= 2 else _MISSING
        out = _correct(w1, w2, self._pending, label)
        h.append(out)
        if len(h) > 2:
            del h[0]
        self._pending = label
        return out

    def flush(self) -> Any:
        """Return the last pending label unchanged (no successor) and clear it."""
        if getattr(self, "_pending", _MISSING) is _MISSING:
            return None
        out = self._pending
        self.history_ = [*self.history_, out][-2:]
        self._pending = _MISSING
        return out
