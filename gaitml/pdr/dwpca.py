"""Dynamic-window PCA (DW-PCA) step direction (paper 002 sec. 3).

For each step window (the FSM's S2..S6 segment, paper 002 sec. 3.1 and Fig. 10; or the
step detector's [start, end) window) the horizontal linear acceleration in the
navigation frame is analysed with PCA2d (sec. 3.2): its first principal axis is the
motion axis. The 180 deg ambiguity (sec. 3.3) is resolved from the shape of the
acceleration projected on that axis: within one step the forward acceleration first
decreases then increases (convex), so if the projection is convex the eigenvector points
along the motion, otherwise opposite. Convexity is the sign of the quadratic coefficient
of a least-squares parabola through the projection over the window.

Gyro check and adjacent averaging (sec. 3.4, Algorithm 3): when two consecutive
directions differ by more than 30 deg, the gyro is consulted. Algorithm 3 sets
``heading_i = heading_{i-1} + gyro_step_i`` when the gyro also turned more than 30 deg
and says nothing for the other case; our reading: if the gyro turned less, the jump is
an ambiguity error, so the direction is flipped by 180 deg when that brings it within
30 deg of the previous one, and otherwise propagated with the gyro
(``heading_{i-1} + gyro_step_i``). The first step has no predecessor; its ambiguity is
resolved against the gyro heading (flipped when more than 90 deg away), otherwise one
wrong first step would flip the whole chain. ``gyro_step_i`` is the change of the gyro heading
between the two steps (difference of their mean gyro headings). Finally adjacent
measurements are averaged (circular mean of step i-1 and i, non-recursive: "the average
of two adjacent measurements"), except across a turn (the two differ by more than the
30 deg check threshold), where averaging would only add lag: the averaging is meant to
cancel the opposite left/right-foot biases within a straight leg.

PCA measures the direction of *motion*. For the multi-state update the facing heading
is needed: ``facing = motion - offset(mode)`` (backward pi, side_left -pi/2,
side_right +pi/2). Checks and averaging run on the facing heading so that a change of
mode (a 90 deg jump of the motion direction) is not taken for a turn.

References
----------
Zhu et al., "Dynamic-Window PCA Algorithm for Step Direction Estimation", J. Software
(paper 002), sec. 3.1-3.4, Algorithm 3.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from gaitml._base import NON_NEGATIVE, NON_NEGATIVE_INTEGER
from gaitml.errors import InputError
from gaitml.pdr.attitude import AttitudeEstimator, wrap_angle
from gaitml.pdr.hde import HeuristicDriftElimination, hde_heading
from gaitml.pdr.heading import BaseHeadingSource
from gaitml.pdr.update import mode_offsets_rad

__all__ = ["DwPcaHeading", "DwPcaHdeHeading", "dwpca_check_and_average", "pca_step_directions"]

#: paper 002 sec. 3.4: left/right foot directions differ by less than 30 deg.
GYRO_CHECK_RAD = np.deg2rad(30.0)
MIN_WINDOW_SAMPLES = 3


def pca_step_directions(lin_acc_h: np.ndarray, start, end, polarity=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """PCA2d motion direction of each step window with 180-degree disambiguation.

    Parameters
    ----------
    lin_acc_h : array (n, 2), horizontal linear acceleration (east, north), m/s^2.
    start, end : int arrays (m,), windows ``[start, end)``.
    polarity : array (m,) of +1/-1, optional
        +1 (paper 002, default): a convex projection means the eigenvector points along the
        motion; -1 reverses the rule (for gaits whose window shows the opposite shape, see
        :meth:`DwPcaHeading.fit_polarity`).

    Returns
    -------
    direction_rad : (m,) compass direction of motion after disambiguation.
    axis_rad : (m,) compass direction of the raw first eigenvector (before disambiguation).
    explained : (m,) fraction of horizontal variance along the first axis (NaN for a
        window shorter than 3 samples, whose direction is NaN too).
    """
    a = np.asarray(lin_acc_h, dtype=float)
    if a.ndim != 2 or a.shape[1] != 2:
        raise InputError(f"`lin_acc_h` must have shape (n, 2) (east, north), got {a.shape}.")
    start = np.asarray(start, dtype=np.int64)
    end = np.asarray(end, dtype=np.int64)
    if len(start) and (start.min() < 0 or end.max() > len(a) or (end < start).any()):
        raise InputError(f"step windows must satisfy 0 <= start <= end <= {len(a)}; check the windows match the recording.")
    m = len(start)
    pol = np.ones(m) if polarity is None else np.asarray(polarity, dtype=float).reshape(-1)
    if pol.shape != (m,):
        raise InputError(f"`polarity` must have one value per window ({m}), got {pol.shape[0]}.")
    direction = np.full(m, np.nan)
    axis = np.full(m, np.nan)
    explained = np.full(m, np.nan)
    for i in range(m):
        x = a[start[i] : end[i]]
        if len(x) < MIN_WINDOW_SAMPLES:
            continue
        xc = x - x.mean(axis=0)
        w, v = np.linalg.eigh(xc.T @ xc)
        e = v[:, 1]  # largest eigenvalue last
        tot = w.sum()
        explained[i] = w[1] / tot if tot > 0 else np.nan
        axis[i] = np.arctan2(e[0], e[1])
        p = xc @ e
        t = np.linspace(-1.0, 1.0, len(p))
        c2 = np.polyfit(t, p, 2)[0] * pol[i]
        if c2 < 0:  # concave: the eigenvector points against the motion
            e = -e
        direction[i] = np.arctan2(e[0], e[1])
    return direction, axis, explained


def dwpca_check_and_average(
    direction_rad, gyro_heading_rad, *, check_rad: float = GYRO_CHECK_RAD, average: bool = True, reanchor_steps: int = 3
) -> tuple[np.ndarray, np.ndarray]:
    """Gyro check and adjacent averaging of paper 002 Algorithm 3 (see module doc).

    Parameters
    ----------
    direction_rad : (m,) per-step direction (facing heading), NaN where PCA failed
        (replaced by the gyro-propagated previous value).
    gyro_heading_rad : (m,) per-step gyro heading (its differences are the gyro turns).
    check_rad : the 30 deg threshold.
    average : adjacent averaging.
    reanchor_steps : re-anchoring (our addition, 0 = off): when this many consecutive PCA
        directions agree with each other (within ``check_rad``) but were all overruled by
        the gyro check, the chain is wrong (e.g. it picked up a mid-turn value at a change
        of mode, where the body turns 90 or 180 deg within a step) and the PCA direction is
        taken again. Algorithm 3 alone never recovers from such a state.

    Returns
    -------
    heading : (m,) checked (and averaged) headings.
    gyro_fixed : (m,) bool, steps changed by the gyro check.
    """
    raw = np.asarray(direction_rad, dtype=float).reshape(-1)
    h = raw.copy()
    g = np.asarray(gyro_heading_rad, dtype=float).reshape(-1)
    if h.shape != g.shape:
        raise InputError(f"`direction_rad` and `gyro_heading_rad` must have the same length, got {h.shape[0]} and {g.shape[0]}.")
    m = len(h)
    fixed = np.zeros(m, dtype=bool)
    if m == 0:
        return h, fixed
    if np.isnan(h[0]):
        h[0] = g[0]
        fixed[0] = True
    elif abs(wrap_angle(h[0] - g[0])) > np.pi / 2:
        # the first step has no predecessor: resolve its 180-degree ambiguity with the
        # gyro heading (which starts from the known initial heading)
        h[0] = h[0] + np.pi
        fixed[0] = True
    dg = wrap_angle(np.diff(g))
    overruled = 0  # consecutive overruled PCA values that agree with each other
    for i in range(1, m):
        if np.isnan(h[i]):
            h[i] = h[i - 1] + dg[i - 1]
            fixed[i] = True
            overruled = 0
            continue
        d = wrap_angle(h[i] - h[i - 1])
        if abs(d) <= check_rad:
            overruled = 0
            continue
        consistent = not np.isnan(raw[i - 1]) and abs(wrap_angle(raw[i] - raw[i - 1])) <= check_rad
        overruled = overruled + 1 if consistent else 1
        if reanchor_steps and overruled >= reanchor_steps:
            overruled = 0
            continue  # keep the PCA direction: re-anchor the chain
        fixed[i] = True
        if abs(dg[i - 1]) > check_rad:
            h[i] = h[i - 1] + dg[i - 1]
        elif abs(wrap_angle(h[i] + np.pi - h[i - 1])) <= check_rad:
            h[i] = h[i] + np.pi
        else:
            h[i] = h[i - 1] + dg[i - 1]
    h = wrap_angle(h)
    if average and m > 1:
        out = h.copy()
        pair = np.arctan2(np.sin(h[1:]) + np.sin(h[:-1]), np.cos(h[1:]) + np.cos(h[:-1]))
        same_leg = np.abs(wrap_angle(h[1:] - h[:-1])) <= check_rad
        out[1:] = np.where(same_leg, pair, h[1:])
        h = out
    return h, fixed


class DwPcaHeading(BaseHeadingSource):
    """DW-PCA facing heading per step (paper 002 sec. 3) for the multi-state update.

    Parameters
    ----------
    check_rad : float, default 30 deg
        Gyro check threshold (paper 002: 30 deg).
    average : bool, default True
        Adjacent averaging (paper 002 sec. 3.4).
    polarity : dict mode -> +1/-1, optional
        Sign of the concavity rule per motion mode (default +1 for every mode: the paper's
        rule, derived for walking). :meth:`fit_polarity` learns it from steps of known
        direction (into ``polarity_``); the rule does not hold for every gait (see Notes).
    reanchor_steps : int, default 3
        See :func:`dwpca_check_and_average` (our addition; 0 = Algorithm 3 only).
    drift_correction : HeuristicDriftElimination, optional
        HDE applied to the DW-PCA headings afterwards (``dwpca-hde``): DW-PCA works in the
        gyro-integrated navigation frame, so it inherits the gyro's yaw drift (paper 002
        used the magnetometer-aided rotation vector). Only its HDE parameters are used.
    attitude : AttitudeEstimator, optional
        Gyro attitude: navigation frame of the PCA and the gyro check (default ``AttitudeEstimator()``).

    Attributes
    ----------
    motion_rad_ : (m,) PCA motion direction after 180-degree disambiguation.
    axis_rad_ : (m,) raw first-eigenvector direction.
    heading_rad_ : (m,) facing heading after mode offset, gyro check and averaging (and HDE).
    heading_check_ : dict, with ``drift_correction``: its structure guard's record
        (:func:`gaitml.pdr.hde.hde_heading`; HDE held off leaves the DW-PCA headings as they are).
    gyro_fixed_ : (m,) bool.
    polarity_ : dict, after :meth:`fit_polarity` (used by later ``estimate`` calls instead of ``polarity``).

    Notes
    -----
    Paper 002 states the concavity rule for walking only. On the gaitml simulator the
    running steps' forward acceleration (braking then propulsion centred on the peak of
    the single-peak window) has the opposite shape within the window, so the rule flips
    every running step; a learned per-mode polarity fixes that.
    """

    name = "dwpca"
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "check_rad": [NON_NEGATIVE],
        "reanchor_steps": [NON_NEGATIVE_INTEGER],
    }

    def __init__(
        self,
        *,
        check_rad: float = GYRO_CHECK_RAD,
        average: bool = True,
        polarity: dict | None = None,
        reanchor_steps: int = 3,
        drift_correction=None,
        attitude: AttitudeEstimator | None = None,
    ):
        self.check_rad = check_rad
        self.average = average
        self.polarity = polarity
        self.reanchor_steps = reanchor_steps
        self.drift_correction = drift_correction
        self.attitude = attitude

    def _polarity(self, modes, m: int) -> np.ndarray:
        polarity = getattr(self, "polarity_", self.polarity)
        if modes is None or not polarity:
            return np.ones(m)
        modes = np.asarray(modes).astype(str)
        return np.array([float(polarity.get(x, 1.0)) for x in modes])

    def fit_polarity(self, lin_acc_h, start, end, motion_rad, modes, *, min_steps: int = 5) -> DwPcaHeading:
        """Learn the concavity polarity per mode from steps whose motion direction is known.

        For each mode the majority vote of "the paper's rule pointed the right way" (within
        90 deg of the known direction) sets the polarity to +1, else -1. Modes with fewer
        than ``min_steps`` steps keep +1. Sets ``polarity_`` (``polarity`` is left as given);
        ``clone(self).set_params(polarity=self.polarity_)`` makes a configured copy.
        """
        d, _, _ = pca_step_directions(lin_acc_h, start, end)
        modes = np.asarray(modes).astype(str)
        ok = np.isfinite(d)
        right = np.abs(wrap_angle(d - np.asarray(motion_rad, dtype=float))) < np.pi / 2
        pol = {}
        for mode in map(str, np.unique(modes)):
            sel = ok & (modes == mode)
            pol[mode] = 1.0 if sel.sum() < min_steps or right[sel].mean() >= 0.5 else -1.0
        self.polarity_ = pol
        return self

    def _heading(self, recording, steps, gyro_h, t_step, dur):
        n = len(steps)
        start = steps["start"].to_numpy(np.int64)
        end = np.maximum(steps["end"].to_numpy(np.int64), start + 1)
        if {"window_start", "window_end"} <= set(steps.columns):
            start = steps["window_start"].to_numpy(np.int64)
            end = steps["window_end"].to_numpy(np.int64)
        modes = steps["mode"].to_numpy() if "mode" in steps else None
        if "mode_offset_rad" in steps:
            offsets = steps["mode_offset_rad"].to_numpy(float)
        elif modes is not None:
            offsets = mode_offsets_rad(modes, unknown="forward")
        else:
            offsets = np.zeros(n)
        lin = self.attitude_.linear_acc_nav(recording)[:, :2]
        theta = self.directions(lin, start, end, gyro_h, offsets, modes)
        hde = self._drift_correction()
        if hde is not None:
            if not hasattr(hde, "hde_params"):
                raise InputError(f"`drift_correction` must be a HeuristicDriftElimination or None, got {type(hde).__name__}.")
            hde._validate_params()
            theta, self.correction_rad_, self.straight_, self.drift_rate_rads_, self.heading_check_ = hde_heading(
                theta, dur, t_step, **hde.hde_params()
            )
        return theta

    def directions(self, lin_acc_h, start, end, gyro_step_heading_rad, mode_offset_rad=None, modes=None) -> np.ndarray:
        """The DW-PCA core on arrays: facing heading per window (sets ``motion_rad_``, ``axis_rad_``, ``gyro_fixed_``)."""
        start = np.asarray(start, dtype=np.int64)
        motion, axis, expl = pca_step_directions(lin_acc_h, start, end, self._polarity(modes, len(start)))
        off = np.zeros(len(motion)) if mode_offset_rad is None else np.asarray(mode_offset_rad, dtype=float)
        if off.shape != motion.shape:
            raise InputError(f"`mode_offset_rad` must have one value per step ({len(motion)}), got {off.shape[0]}.")
        facing = wrap_angle(motion - off)
        self.motion_rad_ = motion
        self.axis_rad_ = axis
        self.explained_ = expl
        heading, self.gyro_fixed_ = dwpca_check_and_average(
            facing, gyro_step_heading_rad, check_rad=self.check_rad, average=self.average, reanchor_steps=self.reanchor_steps
        )
        return heading

    def _drift_correction(self):
        return self.drift_correction


class DwPcaHdeHeading(DwPcaHeading):
    """DW-PCA followed by buffered HDE (``dwpca-hde``): :class:`DwPcaHeading` with a default ``drift_correction``.

    Parameters
    ----------
    check_rad : float, default 30 deg
        Gyro check threshold (paper 002: 30 deg).
    average : bool, default True
        Adjacent averaging (paper 002 sec. 3.4).
    polarity : dict mode -> +1/-1, optional
        Concavity polarity per mode (:class:`DwPcaHeading`).
    reanchor_steps : int, default 3
        See :func:`dwpca_check_and_average`.
    drift_correction : HeuristicDriftElimination, optional
        The HDE applied afterwards (default ``HeuristicDriftElimination()``).
    attitude : AttitudeEstimator, optional
        Gyro attitude (default ``AttitudeEstimator()``).

    Attributes
    ----------
    heading_rad_ : (m,) DW-PCA heading corrected by HDE.
    """

    name = "dwpca-hde"

    def _drift_correction(self):
        if self.drift_correction is not None:
            return self.drift_correction
        return HeuristicDriftElimination()
