"""Trajectory plot (PNG, matplotlib Agg, written atomically)."""

from __future__ import annotations

import pandas as pd

from gaitml.io import atomic_path

__all__ = ["plot_trajectory"]

#: One colour per motion mode (steps drawn as points on the estimated path).
MODE_COLOURS = {"walk": "tab:blue", "run": "tab:red", "side_left": "tab:green", "side_right": "tab:orange", "backward": "tab:purple"}


def plot_trajectory(path, trajectory: pd.DataFrame, *, truth: pd.DataFrame | None = None, others: dict | None = None, title: str = ""):
    """Draw an estimated trajectory (steps coloured by mode) and the truth to a PNG.

    Parameters
    ----------
    path : output PNG (written atomically).
    trajectory : DataFrame with ``x_m``, ``y_m`` and ``mode`` (a PdrResult trajectory).
    truth : DataFrame with ``x_m``, ``y_m`` (reference['trajectory']), optional.
    others : {label: trajectory DataFrame}, extra estimates drawn as thin lines (e.g. forward-only).
    title : plot title.
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 6), dpi=110)
    if truth is not None and len(truth):
        ax.plot(truth["x_m"], truth["y_m"], color="black", lw=2.5, alpha=0.35, label="truth")
    for label, tr in (others or {}).items():
        ax.plot(tr["x_m"], tr["y_m"], lw=1.0, ls="--", label=label)
    x = trajectory["x_m"].to_numpy()
    y = trajectory["y_m"].to_numpy()
    ax.plot(x, y, color="0.3", lw=0.8, label="estimate")
    modes = trajectory["mode"].astype(str).to_numpy()
    for m in pd.unique(modes[1:]):
        sel = modes == m
        ax.scatter(x[sel], y[sel], s=6, color=MODE_COLOURS.get(m, "tab:gray"), label=f"steps: {m}", zorder=3)
    ax.plot([x[0]], [y[0]], marker="o", color="black", ms=7, ls="none", label="start")
    ax.plot([x[-1]], [y[-1]], marker="x", color="crimson", ms=9, mew=2, ls="none", label="end (estimate)")
    return save_map(fig, ax, path, title=title, title_size=9)


def save_map(fig, ax, path, *, title: str = "", title_size: float = 9):
    """Finish a plan-view plot (equal axes east / north in m, grid, legend, title) and write it as PNG atomically.

    Shared by :func:`plot_trajectory` and :func:`gaitml.pdr.plot_truth.plot_truth_score`;
    the figure is closed. Returns ``path``.
    """
    import matplotlib.pyplot as plt

    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x east (m)")
    ax.set_ylabel("y north (m)")
    ax.grid(True, alpha=0.3)
    if title:
        ax.set_title(title, fontsize=title_size)
    ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    with atomic_path(path, suffix=".png") as tmp:
        fig.savefig(tmp, format="png")
    plt.close(fig)
    return path
