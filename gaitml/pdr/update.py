"""Position update of pedestrian dead reckoning: traditional (forward-only) and multi-state.

Convention (DESIGN sec. 2): x = east, y = north, heading ``theta`` is the compass
heading of the direction the person *faces*, clockwise from north, so a forward
step of length L moves by ``L (sin theta, cos theta)`` (paper 003 eq. 10).

References
----------
Deng, Zhao, Zhu, "A PDR algorithm based on human motion recognition", J. Chinese
Inertial Technology, 2021 (paper 003), sec. 4, eqs. (10)-(11).
"""

from __future__ import annotations

import numpy as np

from gaitml.errors import InputError

__all__ = ["MODE_OFFSET_RAD", "FORWARD_MODES", "mode_offsets_rad", "forward_update", "multi_state_update", "dead_reckon"]

#: Direction of motion relative to the facing heading, per motion mode (DESIGN sec. 4).
#: Paper 003 eq. (11) writes X += q L sin(theta + pi p / 2) with q = 1 for backward and
#: -1 otherwise, p = 1 for a left and -1 for a right side step. Taken literally every
#: forward step would move backwards and a left step would move to the right (theta + pi/2
#: is to the right in a clockwise compass), which contradicts the text; we implement the
#: physical meaning: backward = theta + pi, side_left = theta - pi/2, side_right = theta + pi/2,
#: walk and run along theta.
MODE_OFFSET_RAD: dict[str, float] = {
    "walk": 0.0,
    "run": 0.0,
    "forward": 0.0,
    "backward": np.pi,
    "side_left": -np.pi / 2,
    "side_right": np.pi / 2,
}

#: Modes that move along the facing heading.
FORWARD_MODES = ("walk", "run", "forward")


def mode_offsets_rad(modes, *, unknown: str = "raise") -> np.ndarray:
    """Offset of the motion direction from the facing heading for each step's mode.

    Parameters
    ----------
    modes : sequence of str, shape (n,)
        One motion mode per step (``walk``, ``run``, ``side_left``, ``side_right``,
        ``backward``; ``forward`` is an alias of ``walk``).
    unknown : {'raise', 'forward'}
        What to do with a mode outside :data:`MODE_OFFSET_RAD`: raise
        :class:`InputError`, or move it along the heading (offset 0).

    Returns
    -------
    offsets : ndarray of float, shape (n,), radians added to the facing heading.
    """
    modes = np.asarray(modes, dtype=object).reshape(-1)
    if unknown not in ("raise", "forward"):
        raise InputError(f"`unknown` must be 'raise' or 'forward', got {unknown!r}.")
    out = np.zeros(len(modes))
    bad = []
    for m in np.unique(modes.astype(str)) if len(modes) else []:
        sel = modes.astype(str) == m
        if m in MODE_OFFSET_RAD:
            out[sel] = MODE_OFFSET_RAD[m]
        elif unknown == "raise":
            bad.append(m)
    if bad:
        raise InputError(
            f"unknown motion mode(s) {bad} for the multi-state update; use one of {sorted(MODE_OFFSET_RAD)} "
            "or pass unknown='forward' to move them along the heading."
        )
    return out


def _check(step_length_m, heading_rad, start_xy_m):
    L = np.asarray(step_length_m, dtype=float).reshape(-1)
    th = np.asarray(heading_rad, dtype=float).reshape(-1)
    if L.shape != th.shape:
        raise InputError(f"`step_length_m` and `heading_rad` must have the same length, got {L.shape[0]} and {th.shape[0]}.")
    if not (np.isfinite(L).all() and np.isfinite(th).all()):
        raise InputError("`step_length_m` and `heading_rad` must be finite; remove NaN steps first.")
    if (L < 0).any():
        raise InputError(f"`step_length_m` must be >= 0, got a minimum of {L.min():.3f} m; negative lengths are not steps.")
    xy0 = np.asarray(start_xy_m, dtype=float).reshape(-1)
    if xy0.shape != (2,):
        raise InputError(f"`start_xy_m` must be a pair (x, y), got shape {xy0.shape}.")
    return L, th, xy0


def dead_reckon(step_length_m, direction_rad, *, start_xy_m=(0.0, 0.0)) -> np.ndarray:
    """Accumulate steps moving by ``L (sin d, cos d)`` (paper 003 eq. 10).

    Parameters
    ----------
    step_length_m : array, shape (n,)
    direction_rad : array, shape (n,)
        Compass direction of each step's *motion* (clockwise from north).
    start_xy_m : (x, y)

    Returns
    -------
    xy : ndarray, shape (n + 1, 2); row 0 is the start, row k the position after step k.
    """
    L, d, xy0 = _check(step_length_m, direction_rad, start_xy_m)
    xy = np.empty((len(L) + 1, 2))
    xy[0] = xy0
    xy[1:, 0] = xy0[0] + np.cumsum(L * np.sin(d))
    xy[1:, 1] = xy0[1] + np.cumsum(L * np.cos(d))
    return xy


def forward_update(step_length_m, heading_rad, *, start_xy_m=(0.0, 0.0)) -> np.ndarray:
    """Traditional PDR (paper 003 eq. 10): every step moves along the heading.

    This is the comparison baseline of paper 003 sec. 4.3: it cannot represent
    backward or sideways steps, so they are dead-reckoned as forward steps.
    Returns positions of shape (n + 1, 2), start first.
    """
    return dead_reckon(step_length_m, heading_rad, start_xy_m=start_xy_m)


def multi_state_update(step_length_m, heading_rad, modes, *, start_xy_m=(0.0, 0.0), unknown: str = "raise") -> np.ndarray:
    """Multi-state PDR (paper 003 eq. 11, physical sign reading of DESIGN sec. 4).

    Each step moves by ``L (sin(theta + o), cos(theta + o))`` where ``theta`` is the
    facing heading and ``o`` the offset of its mode: 0 for walk/run, pi for backward,
    -pi/2 for side_left (to the person's left in the clockwise compass), +pi/2 for
    side_right.

    Parameters
    ----------
    step_length_m, heading_rad : arrays, shape (n,)
    modes : sequence of str, shape (n,)
    start_xy_m : (x, y)
    unknown : {'raise', 'forward'}, see :func:`mode_offsets_rad`.

    Returns
    -------
    xy : ndarray, shape (n + 1, 2), start first.

    Notes
    -----
    The printed eq. (11) uses q_k = 1 for backward and -1 otherwise and
    theta + pi p_k / 2 with p = 1 for left; read literally forward steps would go
    backwards and left steps to the right. The text describes the physical meaning,
    which is what is implemented (DESIGN sec. 4).
    """
    L, th, _ = _check(step_length_m, heading_rad, start_xy_m)
    m = np.asarray(modes, dtype=object).reshape(-1)
    if m.shape != L.shape:
        raise InputError(f"`modes` must have one entry per step ({L.shape[0]}), got {m.shape[0]}.")
    return dead_reckon(L, th + mode_offsets_rad(m, unknown=unknown), start_xy_m=start_xy_m)
