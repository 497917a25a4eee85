"""Positioning error of a PDR trajectory against landmarks or a dense reference path.

The indoor-positioning competitions (IPIN smartphone tracks, the EvAAL
framework) score a track by the horizontal error at the ground-truth points
and rank by its 75th percentile; PDR papers also give the error in % of the
distance walked (paper 003 sec. 4.3, ``%D``). :func:`score_positions` does both,
the same way for sparse landmarks and for a dense truth:

1. **Alignment on the start.** A PDR trajectory starts at (0, 0) with an assumed
   heading; the truth is in site coordinates. With ``align='start-heading'``
   (default) the trajectory is translated so that its position at the first
   truth time equals the first truth point, and rotated about it so that its
   direction from there to the first truth point at least ``heading_distance_m``
   away (along the truth) equals the truth's direction: the start position and
   initial heading come from the first truth points, nothing else is fitted.
   With ``align='start'`` only the position is matched (the trajectory keeps its
   own initial heading, e.g. from ``--initial-heading-rad``). ``'none'``
   compares as is.
2. **Errors at every later truth point** inside the recording: the trajectory
   position at that time (linear in time between step positions; the start
   position before the first step and the last position after the last step)
   against the truth; its distance is the error. The first point (the
   alignment anchor) is not scored; points more than :data:`END_TOLERANCE_S`
   outside the recording are counted and not scored.
3. **Summary**: mean, median, 75th percentile (numpy's linear interpolation
   between order statistics), max and RMS error; the distance walked along
   the truth up to each point (through the landmarks for sparse truth, so a
   path between landmarks counts as straight), the end error and the errors
   in % of that distance. Per floor segment (see :mod:`gaitml.io.truth`) the
   same summary again.

References
----------
Potorti et al., "The IPIN 2019 indoor localisation competition: description and
results", IEEE Access 8 (2020): 75th percentile of the horizontal error at the
evaluation points (floor penalty not applicable to a 2-D PDR). Paper 003
sec. 4.3: error in % of the distance travelled.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.errors import InputError

__all__ = ["ALIGNMENTS", "END_TOLERANCE_S", "HEADING_DISTANCE_M", "apply_alignment", "score_positions", "trajectory_at"]

#: Alignments of the trajectory on the truth.
ALIGNMENTS = ("start-heading", "start", "none")
#: Truth points up to this long before the start or after the end of the recording are still scored (s),
#: with the trajectory held at its first / last position (a landmark clicked as the recording stops).
END_TOLERANCE_S = 1.0
#: Distance along the truth from the start to the point that fixes the initial heading (m).
HEADING_DISTANCE_M = 5.0


def trajectory_at(est_t_s, est_xy, t_query) -> np.ndarray:
    """Trajectory positions (m) at ``t_query`` (s), linear in time, held before the first and after the last."""
    t = np.asarray(est_t_s, dtype=float)
    a = np.asarray(est_xy, dtype=float)
    if (np.diff(t) < 0).any():
        raise InputError("trajectory times must be non-decreasing; sort the trajectory by time.")
    q = np.asarray(t_query, dtype=float)
    return np.column_stack([np.interp(q, t, a[:, 0]), np.interp(q, t, a[:, 1])])


def apply_alignment(est_xy, summary: dict) -> np.ndarray:
    """The trajectory positions (n, 2) moved as :func:`score_positions` moved them (for plots and tables)."""
    a = np.asarray(est_xy, dtype=float)
    rot = float(summary["rotation_rad"])
    c, s = np.cos(rot), np.sin(rot)
    return (a - np.asarray(summary["anchor_est_xy_m"])) @ np.array([[c, s], [-s, c]]) + np.asarray(summary["anchor_xy_m"])


def _summary(err: np.ndarray, dist: np.ndarray) -> dict:
    if len(err) == 0:
        return {"n_points": 0}
    d_end = float(dist[-1])
    out = {
        "n_points": int(len(err)),
        "mean_error_m": float(err.mean()),
        "median_error_m": float(np.median(err)),
        "p75_error_m": float(np.percentile(err, 75)),
        "max_error_m": float(err.max()),
        "rmse_m": float(np.sqrt(np.mean(err**2))),
        "end_error_m": float(err[-1]),
        "distance_m": d_end,
    }
    if d_end > 0:
        out["end_error_pct_distance"] = 100.0 * float(err[-1]) / d_end
        out["mean_error_pct_distance"] = 100.0 * float(err.mean()) / d_end
    return out


def score_positions(
    est_t_s,
    est_xy,
    truth: pd.DataFrame,
    *,
    align: str = "start-heading",
    heading_distance_m: float = HEADING_DISTANCE_M,
    t_end_s: float | None = None,
) -> tuple[pd.DataFrame, dict]:
    """Score a trajectory against timed true positions (module doc).

    Parameters
    ----------
    est_t_s, est_xy : array (n,), (n, 2)
        The trajectory (PDR output: the start point then one row per step), s and m.
    truth : DataFrame
        ``t_s, x_m, y_m`` and optionally ``floor``, ``segment`` (:class:`gaitml.io.truth.Truth` table),
        on the trajectory's time base.
    align : {'start-heading', 'start', 'none'}
    heading_distance_m : float
        For ``'start-heading'``: the heading is taken to the first truth point at
        least this far from the start along the truth (the farthest one if none is).
    t_end_s : float, optional
        End of the recording (s); truth points after it are not scored (default:
        the trajectory's last time).

    Returns
    -------
    points : DataFrame
        One row per truth point: ``t_s, x_m, y_m, est_x_m, est_y_m, error_m,
        distance_m, error_pct_distance, floor, segment, role`` (``anchor``,
        ``scored`` or ``outside``); the estimate after alignment.
    summary : dict
        ``align``, ``rotation_rad``, ``n_points``, ``n_outside``, mean / median /
        p75 / max / RMS error (m), ``end_error_m``, ``distance_m``,
        ``end_error_pct_distance``, ``mean_error_pct_distance``, ``segments``
        (the same per floor segment, when there is more than one).
    """
    if align not in ALIGNMENTS:
        raise InputError(f"unknown alignment {align!r}; choose one of {', '.join(ALIGNMENTS)} (CLI: --truth-align).")
    if not heading_distance_m > 0:
        raise InputError(f"`heading_distance_m` must be > 0, got {heading_distance_m!r}.")
    t_est = np.asarray(est_t_s, dtype=float)
    xy_est = np.asarray(est_xy, dtype=float)
    if xy_est.ndim != 2 or xy_est.shape[1] != 2 or len(xy_est) != len(t_est) or len(t_est) == 0:
        raise InputError(f"the trajectory must be (n, 2) positions with n times, got {xy_est.shape} and {t_est.shape}.")
    for c in ("t_s", "x_m", "y_m"):
        if c not in truth:
            raise InputError(f"the truth table needs columns t_s, x_m, y_m; `{c}` is missing.")
    tt = truth["t_s"].to_numpy(float)
    txy = truth[["x_m", "y_m"]].to_numpy(float)
    t_lo = 0.0 if t_est[0] >= 0 else float(t_est[0])
    t_hi = float(t_est[-1]) if t_end_s is None else float(t_end_s)
    inside = (tt >= t_lo - END_TOLERANCE_S) & (tt <= t_hi + END_TOLERANCE_S)
    if inside.sum() < 2:
        raise InputError(
            f"only {int(inside.sum())} truth point(s) lie inside the recording ({t_lo:.1f} to {t_hi:.1f} s; truth {tt.min():.1f} to "
            f"{tt.max():.1f} s); are the truth times on the recording's clock (s)?"
        )
    idx = np.flatnonzero(inside)
    i0 = int(idx[0])
    est_at = trajectory_at(t_est, xy_est, tt)
    # distance walked along the truth, from the anchor
    step = np.r_[0.0, np.linalg.norm(np.diff(txy, axis=0), axis=1)]
    dist = np.cumsum(step) - np.cumsum(step)[i0]
    rot = 0.0
    if align == "none":
        aligned = est_at
    else:
        rel = est_at - est_at[i0]
        if align == "start-heading":
            later = idx[1:]
            far = later[dist[later] >= heading_distance_m]
            k = int(far[0]) if len(far) else int(later[np.argmax(dist[later])])
            v_true = txy[k] - txy[i0]
            v_est = rel[k]
            if np.linalg.norm(v_est) > 1e-9 and np.linalg.norm(v_true) > 1e-9:
                # compass convention does not matter here: a plain rotation of the x-y plane
                rot = float(np.arctan2(v_true[1], v_true[0]) - np.arctan2(v_est[1], v_est[0]))
                rot = (rot + np.pi) % (2 * np.pi) - np.pi
        c, s = np.cos(rot), np.sin(rot)
        aligned = rel @ np.array([[c, s], [-s, c]]) + txy[i0]
    err = np.linalg.norm(aligned - txy, axis=1)
    role = np.where(inside, "scored", "outside").astype(object)
    role[i0] = "anchor"
    floor = truth["floor"].to_numpy(float) if "floor" in truth else np.full(len(tt), np.nan)
    seg = truth["segment"].to_numpy(int) if "segment" in truth else np.zeros(len(tt), dtype=int)
    with np.errstate(divide="ignore", invalid="ignore"):
        pct = np.where(dist > 0, 100.0 * err / dist, np.nan)
    points = pd.DataFrame(
        {
            "t_s": tt,
            "x_m": txy[:, 0],
            "y_m": txy[:, 1],
            "est_x_m": aligned[:, 0],
            "est_y_m": aligned[:, 1],
            "error_m": err,
            "distance_m": dist,
            "error_pct_distance": pct,
            "floor": floor,
            "segment": seg,
            "role": role,
        }
    )
    scored = role == "scored"
    summary = {
        "align": align,
        "rotation_rad": rot,
        "anchor_t_s": float(tt[i0]),
        "anchor_est_xy_m": [float(v) for v in est_at[i0]] if align != "none" else [0.0, 0.0],
        "anchor_xy_m": [float(v) for v in txy[i0]] if align != "none" else [0.0, 0.0],
        **_summary(err[scored], dist[scored]),
        "n_outside": int((~inside).sum()),
    }
    if align == "start-heading":
        summary["heading_from_t_s"] = float(tt[k]) if len(idx) > 1 else None
    segs = np.unique(seg[scored])
    if len(np.unique(seg)) > 1:
        summary["segments"] = [
            {
                "segment": int(g),
                "floor": float(floor[scored & (seg == g)][0]),
                **_summary(err[scored & (seg == g)], dist[scored & (seg == g)]),
            }
            for g in segs
        ]
    return points, summary
