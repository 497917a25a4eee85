"""Plot of a trajectory scored against ground truth (``gaitml pdr --truth --plot``)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.pdr.plot import save_map

__all__ = ["plot_truth_score"]


def plot_truth_score(path, aligned_xy, points: pd.DataFrame, truth: pd.DataFrame, *, dense: bool, title: str = ""):
    """Draw the aligned trajectory over the truth, with the error at each scored point, to a PNG.

    Parameters
    ----------
    path : output PNG (written atomically).
    aligned_xy : (n, 2) the trajectory after :func:`gaitml.evaluation.positioning.apply_alignment`.
    points : the per-point table of :func:`gaitml.evaluation.positioning.score_positions`.
    truth : the truth table (``x_m``, ``y_m``, ``segment``).
    dense : draw the truth as a path (True) or as numbered landmarks (False).
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 6), dpi=110)
    a = np.asarray(aligned_xy, dtype=float)
    for g, part in truth.groupby("segment"):
        ax.plot(
            part["x_m"],
            part["y_m"],
            color="black",
            lw=2.5 if dense else 1.0,
            alpha=0.35,
            ls="-" if dense else ":",
            label="truth" if g == truth["segment"].iloc[0] else None,
        )
    ax.plot(a[:, 0], a[:, 1], color="tab:blue", lw=1.0, label="PDR (aligned on the start)")
    scored = points[points["role"] == "scored"]
    if not dense:
        ax.scatter(points["x_m"], points["y_m"], s=22, color="black", zorder=3, label="landmarks")
        for k, r in enumerate(points.itertuples(index=False)):
            ax.annotate(str(k), (r.x_m, r.y_m), fontsize=6, xytext=(3, 3), textcoords="offset points")
    step = max(1, len(scored) // 60) if dense else 1
    for r in scored.iloc[::step].itertuples(index=False):
        ax.plot([r.x_m, r.est_x_m], [r.y_m, r.est_y_m], color="crimson", lw=0.7, alpha=0.8)
    ax.plot([], [], color="crimson", lw=0.7, label="error at truth points")
    anchor = points[points["role"] == "anchor"]
    ax.plot(anchor["x_m"], anchor["y_m"], marker="o", color="black", ms=7, ls="none", label="start (anchor)")
    return save_map(fig, ax, path, title=title, title_size=8)
