"""Trajectory metrics for PDR: end-point error, closure error, checkpoint errors, ATE, and walk scores.

Paper 003 sec. 4.3 defines the positioning error as the distance between the start point
and the end of the estimated trajectory of a closed route, in percent of the total
distance travelled (``%D``). The general form used here is the distance between the
estimated and the true end points over the true distance; for a closed route the true
end is the start, which is the paper's definition.

On walks that loop in a small room (the tyrex motion-capture recordings: a 5 m room)
the end-point and mean errors as a % of the path are blind (a trajectory that never
moves scores a few %). :func:`walk_scores` scores such walks so that a wrong answer
fails: the walked-distance ratio against the truth low-passed to follow the body
(:func:`body_track`), the error of the displacement over every ``window_s`` of walking
as a % of the distance walked in it (:func:`displacement_errors`, the trajectory
aligned once on its first seconds, so that heading drift counts), and the drift of
the walking direction (:func:`walking_direction_drift`, deg/min).

References
----------
Paper 003 sec. 4.3; Sturm et al., "A benchmark for the evaluation of RGB-D SLAM
systems", IROS 2012 (absolute trajectory error, time-aligned RMSE after alignment).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.signal._track import BODY_CUTOFF_HZ, body_track
from gaitml.signal._track import uniform_track as _uniform_track

__all__ = [
    "BODY_CUTOFF_HZ",
    "moving_samples",
    "absolute_trajectory_error",
    "align_once",
    "body_track",
    "displacement_errors",
    "walk_scores",
    "walked_distance_ratio",
    "walking_direction_drift",
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


# --------------------------------------------------------------------------- walks in a small room

#: The body moves (walks) where its low-passed speed is above this (m/s): standing sway
#: and the phone's handling stay below it, the slowest tyrex walking (0.7 m/s) well above.
MOVING_SPEED_MS = 0.3


def _span(est_t_s, true_t) -> tuple[float, float]:
    t0 = max(float(true_t[0]), float(np.min(est_t_s)))
    t1 = min(float(true_t[-1]), float(np.max(est_t_s)))
    if t1 - t0 <= 0:
        raise InputError("the estimated trajectory and the truth do not overlap in time; put both on one clock.")
    return t0, t1


def _est_at(est_t_s, est_xy, t_query) -> np.ndarray:
    """Estimated positions at times: linear between steps, held before the first and after the last."""
    t = np.asarray(est_t_s, dtype=float).reshape(-1)
    a = _xy("est_xy", est_xy)
    if len(t) != len(a):
        raise InputError(f"`est_t_s` must have one time per position ({len(a)}), got {len(t)}.")
    if len(t) > 1 and (np.diff(t) < 0).any():
        raise InputError("trajectory times must be non-decreasing; sort the trajectory by time.")
    return np.column_stack([np.interp(t_query, t, a[:, j]) for j in range(2)])


def walked_distance_ratio(est_t_s, est_xy, true_t_s, true_xy, *, cutoff_hz: float = BODY_CUTOFF_HZ) -> dict:
    """Estimated over true walked distance in the time both cover.

    The true distance is the length of the body path (:func:`body_track`); the
    estimated one the length of the estimated polyline between the same times
    (positions linear between steps).

    Returns
    -------
    dict ``ratio``, ``est_m``, ``true_m``, ``t0_s``, ``t1_s``.
    """
    t, body, _ = _true_body(true_t_s, true_xy, cutoff_hz)
    t0, t1 = _span(est_t_s, t)
    inside = (t >= t0) & (t <= t1)
    true_m = path_length(body[inside])
    et = np.asarray(est_t_s, dtype=float).reshape(-1)
    knots = np.concatenate([[t0], et[(et > t0) & (et < t1)], [t1]])
    est_m = path_length(_est_at(est_t_s, est_xy, knots))
    return {"ratio": est_m / true_m if true_m > 0 else float("nan"), "est_m": est_m, "true_m": true_m, "t0_s": t0, "t1_s": t1}


def _true_body(true_t_s, true_xy, cutoff_hz):
    t, _, fs = _uniform_track(true_t_s, true_xy, "true_xy")
    return t, body_track(true_t_s, true_xy, cutoff_hz=cutoff_hz), fs


def moving_samples(t_s, true_t_s, true_xy, *, min_speed_ms: float = MOVING_SPEED_MS, cutoff_hz: float = BODY_CUTOFF_HZ) -> np.ndarray:
    """Which samples of a recording fall where the walker moves: 1 moving, 0 still, -1 outside the truth.

    The walker's path is the phone's true horizontal path low-passed (:func:`body_track`,
    which removes the arm swing and the handling of the phone); a sample is moving where
    that path's speed, interpolated at the sample's time, exceeds ``min_speed_ms``.

    Parameters
    ----------
    t_s : (n,) sample times (s) on the truth's clock.
    true_t_s, true_xy : the truth's times (s, uniform rate) and horizontal positions (m), (m, 2).

    Returns
    -------
    ndarray of int8, shape (n,)
    """
    t, body, _ = _true_body(true_t_s, true_xy, cutoff_hz)
    speed = np.linalg.norm(np.gradient(body, t, axis=0), axis=1)
    q = np.asarray(t_s, dtype=float).reshape(-1)
    out = (np.interp(q, t, speed) > float(min_speed_ms)).astype(np.int8)
    out[(q < t[0]) | (q > t[-1])] = -1
    return out


def _moving(t: np.ndarray, body: np.ndarray, min_speed_ms: float) -> np.ndarray:
    v = np.gradient(body, t, axis=0)
    return np.linalg.norm(v, axis=1) > min_speed_ms


def align_once(
    est_t_s, est_xy, true_t_s, true_xy, *, align_s: float = 10.0, cutoff_hz: float = BODY_CUTOFF_HZ, min_speed_ms: float = MOVING_SPEED_MS
) -> dict:
    """One rotation and translation that put the estimate on the truth over its first seconds of walking.

    The start of walking is the first time the body moves faster than
    ``min_speed_ms``; over the ``align_s`` seconds from there (sampled at the
    truth's rate) the estimate is anchored at that start and rotated about it by the
    angle that best maps its displacements onto the true ones (least squares,
    ``atan2(sum cross, sum dot)``). Scale is not fitted: a wrong distance counts.
    A heading without a compass is unknown up to this angle; everything after the
    alignment window (drift, jumps) counts.

    Returns
    -------
    dict ``angle_rad`` (counter-clockwise, applied to the estimate), ``anchor_t_s``,
    ``align_end_t_s``, ``est_anchor_xy``, ``true_anchor_xy``.
    """
    t, body, _ = _true_body(true_t_s, true_xy, cutoff_hz)
    t0, t1 = _span(est_t_s, t)
    inside = (t >= t0) & (t <= t1)
    moving = _moving(t, body, min_speed_ms) & inside
    start = float(t[np.argmax(moving)]) if moving.any() else t0
    end = min(start + align_s, t1)
    sel = (t >= start) & (t <= end)
    p = body[sel] - body[sel][0]
    e = _est_at(est_t_s, est_xy, t[sel])
    e = e - e[0]
    cross = float(np.sum(e[:, 0] * p[:, 1] - e[:, 1] * p[:, 0]))
    dot = float(np.sum(e * p))
    angle = float(np.arctan2(cross, dot)) if (abs(cross) + abs(dot)) > 1e-12 else 0.0
    return {
        "angle_rad": angle,
        "anchor_t_s": start,
        "align_end_t_s": end,
        "est_anchor_xy": _est_at(est_t_s, est_xy, [start])[0],
        "true_anchor_xy": body[sel][0],
    }


def _rot2(a: float) -> np.ndarray:
    return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])


def displacement_errors(
    est_t_s,
    est_xy,
    true_t_s,
    true_xy,
    *,
    window_s: float = 10.0,
    hop_s: float = 1.0,
    align_s: float = 10.0,
    cutoff_hz: float = BODY_CUTOFF_HZ,
    min_walked_m: float = 2.0,
) -> pd.DataFrame:
    """Error of the displacement over each ``window_s`` of walking, after one alignment.

    The estimate is aligned once (:func:`align_once`); then for windows
    ``[t, t + window_s]`` starting every ``hop_s`` inside the time both cover, the
    true displacement of the body (:func:`body_track`) and the estimated one are
    compared. Windows in which the body walked less than ``min_walked_m`` (standing)
    are left out.

    Returns
    -------
    DataFrame
        One row per window: ``t_start_s``, ``walked_m`` (body path length in the
        window), ``true_dx_m``, ``true_dy_m``, ``est_dx_m``, ``est_dy_m``, ``error_m``
        and ``error_pct`` (``100 error_m / walked_m``). ``attrs['alignment']`` holds
        the alignment.
    """
    if not (window_s > 0 and hop_s > 0):
        raise InputError(f"`window_s` and `hop_s` must be > 0, got {window_s!r}, {hop_s!r}.")
    t, body, _ = _true_body(true_t_s, true_xy, cutoff_hz)
    t0, t1 = _span(est_t_s, t)
    al = align_once(est_t_s, est_xy, true_t_s, true_xy, align_s=align_s, cutoff_hz=cutoff_hz)
    r = _rot2(al["angle_rad"])
    starts = np.arange(t0, t1 - window_s + 1e-9, hop_s)
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(body, axis=0), axis=1))])
    rows = []
    for a in starts:
        b = a + window_s
        walked = float(np.interp(b, t, cum) - np.interp(a, t, cum))
        if walked < min_walked_m:
            continue
        pa = np.array([np.interp(a, t, body[:, j]) for j in range(2)])
        pb = np.array([np.interp(b, t, body[:, j]) for j in range(2)])
        e = _est_at(est_t_s, est_xy, [a, b])
        de = r @ (e[1] - e[0])
        dp = pb - pa
        err = float(np.linalg.norm(de - dp))
        rows.append(
            {
                "t_start_s": float(a),
                "walked_m": walked,
                "true_dx_m": float(dp[0]),
                "true_dy_m": float(dp[1]),
                "est_dx_m": float(de[0]),
                "est_dy_m": float(de[1]),
                "error_m": err,
                "error_pct": 100.0 * err / walked,
            }
        )
    out = pd.DataFrame(rows, columns=["t_start_s", "walked_m", "true_dx_m", "true_dy_m", "est_dx_m", "est_dy_m", "error_m", "error_pct"])
    out.attrs["alignment"] = al
    return out


def walking_direction_drift(
    est_t_s,
    est_xy,
    true_t_s,
    true_xy,
    *,
    segment_s: float = 2.0,
    cutoff_hz: float = BODY_CUTOFF_HZ,
    min_speed_ms: float = MOVING_SPEED_MS,
) -> dict:
    """Drift of the estimated walking direction against the true one, deg/min.

    Over consecutive ``segment_s`` segments in which both the body and the
    estimate move faster than ``min_speed_ms``, the direction of each displacement is
    taken; the difference (estimate - truth, unwrapped) is fitted by a straight line
    against time (least squares): its slope is the drift. A constant offset (the
    unknown start heading, a phone carried sideways) does not count; a steady
    gyroscope bias does; jumps count by how much they tilt the line, and
    ``max_jump_deg`` reports the largest change between consecutive segments
    beyond the truth's.

    Returns
    -------
    dict ``drift_deg_per_min`` (signed; NaN with fewer than 3 segments),
    ``n_segments``, ``max_jump_deg``, ``rms_deg`` (of the difference about its line).
    """
    t, body, _ = _true_body(true_t_s, true_xy, cutoff_hz)
    t0, t1 = _span(est_t_s, t)
    edges = np.arange(t0, t1 + 1e-9, segment_s)
    nan = {"drift_deg_per_min": float("nan"), "n_segments": 0, "max_jump_deg": float("nan"), "rms_deg": float("nan")}
    if len(edges) < 4:
        return nan
    pb = np.column_stack([np.interp(edges, t, body[:, j]) for j in range(2)])
    pe = _est_at(est_t_s, est_xy, edges)
    db, de = np.diff(pb, axis=0), np.diff(pe, axis=0)
    min_d = min_speed_ms * segment_s
    ok = (np.linalg.norm(db, axis=1) > min_d) & (np.linalg.norm(de, axis=1) > min_d)
    if ok.sum() < 3:
        return {**nan, "n_segments": int(ok.sum())}
    diff = np.arctan2(de[:, 1], de[:, 0]) - np.arctan2(db[:, 1], db[:, 0])
    d = np.unwrap(diff[ok])
    tm = 0.5 * (edges[:-1] + edges[1:])[ok]
    slope, icpt = np.polyfit(tm, d, 1)
    jumps = np.abs(np.diff(d))
    return {
        "drift_deg_per_min": float(np.degrees(slope) * 60.0),
        "n_segments": int(ok.sum()),
        "max_jump_deg": float(np.degrees(jumps.max())) if len(jumps) else float("nan"),
        "rms_deg": float(np.degrees(np.sqrt(np.mean((d - (slope * tm + icpt)) ** 2)))),
    }


def walk_scores(est_t_s, est_xy, true_t_s, true_xy, *, window_s: float = 10.0, cutoff_hz: float = BODY_CUTOFF_HZ) -> dict:
    """The three walk scores of one estimated trajectory against a motion-capture track.

    Returns
    -------
    dict
        ``distance_ratio`` (:func:`walked_distance_ratio`), ``error_10s_pct`` (median
        over the windows of :func:`displacement_errors`: the typical error of the
        displacement over ``window_s`` of walking, % of the distance walked in it),
        ``error_10s_pooled_pct`` (sum of errors over sum of distances, the same
        windows), ``n_windows``, ``drift_deg_per_min`` and ``max_jump_deg``
        (:func:`walking_direction_drift`), ``true_m`` and ``est_m``.
    """
    dist = walked_distance_ratio(est_t_s, est_xy, true_t_s, true_xy, cutoff_hz=cutoff_hz)
    win = displacement_errors(est_t_s, est_xy, true_t_s, true_xy, window_s=window_s, cutoff_hz=cutoff_hz)
    drift = walking_direction_drift(est_t_s, est_xy, true_t_s, true_xy, cutoff_hz=cutoff_hz)
    n = len(win)
    return {
        "distance_ratio": dist["ratio"],
        "est_m": dist["est_m"],
        "true_m": dist["true_m"],
        "error_10s_pct": float(win["error_pct"].median()) if n else float("nan"),
        "error_10s_pooled_pct": float(100 * win["error_m"].sum() / win["walked_m"].sum()) if n else float("nan"),
        "n_windows": int(n),
        "drift_deg_per_min": drift["drift_deg_per_min"],
        "max_jump_deg": drift["max_jump_deg"],
    }
