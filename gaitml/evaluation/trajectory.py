"""Trajectory metrics for PDR: end-point error, closure error, checkpoint errors, ATE.

Paper 003 sec. 4.3 defines the positioning error as the distance between the start point
and the end of the estimated trajectory of a closed route, in percent of the total
distance travelled (``%D``). The general form used here is the distance between the
estimated and the true end points over the true distance; for a closed route the true
end is the start, which is the paper's definition.

References
----------
Paper 003 sec. 4.3; Sturm et al., "A benchmark for the evaluation of RGB-D SLAM
systems", IROS 2012 (absolute trajectory error, time-aligned RMSE after alignment).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.errors import InputError

__all__ = [
    "absolute_trajectory_error",
    "checkpoint_errors",
    "closure_error",
    "end_point_error",
    "path_length",
    "rigid_align_2d",
]


def _xy(name: str, xy) -> np.ndarray:
    a = np.asarray(xy, dtype=float)
    if a.ndim != 2 or a.shape[1] != 2 or len(a) == 0:
        raise InputError(f"`{name}` must have shape (n, 2) with n >= 1 (x east, y north in m), got {a.shape}.")
    if not np.isfinite(a).all():
        raise InputError(f"`{name}` has NaN/inf positions; remove them first.")
    return a


def path_length(xy) -> float:
    """Length (m) of the polyline through the positions."""
    a = _xy("xy", xy)
    return float(np.linalg.norm(np.diff(a, axis=0), axis=1).sum())


def end_point_error(est_xy, true_end_xy, distance_m: float) -> tuple[float, float]:
    """Distance (m) between the estimated end point and the true one, and that in % of ``distance_m``.

    Parameters
    ----------
    est_xy : (n, 2) estimated positions (the last row is the end point).
    true_end_xy : (2,) true end point (the start for a closed route, paper 003).
    distance_m : true distance travelled (D).
    """
    a = _xy("est_xy", est_xy)
    e = np.asarray(true_end_xy, dtype=float).reshape(-1)
    if e.shape != (2,):
        raise InputError(f"`true_end_xy` must be a pair (x, y), got shape {e.shape}.")
    if not (np.isfinite(distance_m) and distance_m > 0):
        raise InputError(f"`distance_m` must be a positive distance, got {distance_m!r}.")
    err = float(np.linalg.norm(a[-1] - e))
    return err, 100.0 * err / distance_m


def closure_error(est_xy) -> tuple[float, float]:
    """Closure error of a closed route: |end - start| (m) and that in % of the estimated path length.

    Dividing by the *estimated* length makes the percentage invariant to a uniform scale
    of all step lengths, so closed real recordings can be judged without step length
    calibration.
    """
    a = _xy("est_xy", est_xy)
    err = float(np.linalg.norm(a[-1] - a[0]))
    length = path_length(a)
    if length <= 0:
        raise InputError("the trajectory has zero length; closure error is undefined (no steps?).")
    return err, 100.0 * err / length


def _interp_xy(t_query, t, xy):
    t = np.asarray(t, dtype=float)
    if (np.diff(t) < 0).any():
        raise InputError("trajectory times must be non-decreasing; sort the trajectory by time.")
    return np.column_stack([np.interp(t_query, t, xy[:, 0]), np.interp(t_query, t, xy[:, 1])])


def checkpoint_errors(est_t_s, est_xy, checkpoints: pd.DataFrame) -> pd.DataFrame:
    """Position error at known checkpoints.

    Parameters
    ----------
    est_t_s, est_xy : estimated trajectory (times (n,), positions (n, 2)).
    checkpoints : DataFrame with ``t_s``, ``x_m``, ``y_m`` (true positions at known times).

    Returns
    -------
    DataFrame ``t_s, x_m, y_m, est_x_m, est_y_m, error_m`` (estimate linearly interpolated in time).
    """
    a = _xy("est_xy", est_xy)
    for c in ("t_s", "x_m", "y_m"):
        if c not in checkpoints:
            raise InputError(f"`checkpoints` needs columns t_s, x_m, y_m; `{c}` is missing.")
    q = checkpoints["t_s"].to_numpy(dtype=float)
    est = _interp_xy(q, est_t_s, a)
    true = checkpoints[["x_m", "y_m"]].to_numpy(dtype=float)
    out = checkpoints[["t_s", "x_m", "y_m"]].copy()
    out["est_x_m"] = est[:, 0]
    out["est_y_m"] = est[:, 1]
    out["error_m"] = np.linalg.norm(est - true, axis=1)
    return out.reset_index(drop=True)


def rigid_align_2d(src_xy, dst_xy) -> tuple[np.ndarray, np.ndarray]:
    """Least-squares rotation R (2, 2) and translation t (2,) with ``R src + t ~ dst`` (Kabsch, no scale)."""
    s = _xy("src_xy", src_xy)
    d = _xy("dst_xy", dst_xy)
    if s.shape != d.shape:
        raise InputError(f"`src_xy` and `dst_xy` must have the same shape, got {s.shape} and {d.shape}.")
    ms, md = s.mean(axis=0), d.mean(axis=0)
    h = (s - ms).T @ (d - md)
    u, _, vt = np.linalg.svd(h)
    sign = np.sign(np.linalg.det(vt.T @ u.T)) or 1.0
    r = vt.T @ np.diag([1.0, sign]) @ u.T
    return r, md - r @ ms


def absolute_trajectory_error(est_t_s, est_xy, true_t_s, true_xy, *, align: str = "none") -> dict:
    """Absolute trajectory error (time-aligned): RMSE, mean and max of position errors.

    The true trajectory is linearly interpolated at the estimated times (both share the
    recording's clock). ``align='rigid'`` first applies the best rotation + translation
    (the heading at the start is not observable without a compass); ``'none'`` compares
    as is.

    Returns a dict ``{"rmse_m", "mean_m", "max_m", "n"}``.
    """
    a = _xy("est_xy", est_xy)
    tt = np.asarray(est_t_s, dtype=float).reshape(-1)
    if len(tt) != len(a):
        raise InputError(f"`est_t_s` must have one time per position ({len(a)}), got {len(tt)}.")
    truth = _interp_xy(tt, true_t_s, _xy("true_xy", true_xy))
    if align == "rigid":
        r, t = rigid_align_2d(a, truth)
        a = a @ r.T + t
    elif align != "none":
        raise InputError(f"`align` must be 'none' or 'rigid', got {align!r}.")
    e = np.linalg.norm(a - truth, axis=1)
    return {"rmse_m": float(np.sqrt(np.mean(e**2))), "mean_m": float(e.mean()), "max_m": float(e.max()), "n": int(len(e))}
