"""The labelling report figure."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from gaitml.labels._labeller import IntervalLabeller

__all__ = ["plot_label_report"]


def plot_label_report(labeller: IntervalLabeller, path: str | os.PathLike, *, max_width_in: float = 40.0) -> Path:
    """Write a PNG: |acc|, the intervals as written and as snapped, the steps and the moved boundaries.

    Top panel: |acc| (m/s^2) with the detected step events (dots) or stride
    starts, the boundaries as written (dashed grey) and where they were moved
    (solid, coloured by status). Bottom panel: two bands, the intervals as
    written (upper) and the final per-sample labels (lower), one colour per label.
    Written atomically.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from gaitml.io._atomic import atomic_path

    rec = labeller.recording_
    t = rec.t_s
    mag = np.linalg.norm(rec.acc, axis=1)
    names = sorted(set(labeller.intervals_["label"]) | {labeller.unlabelled})
    cmap = plt.get_cmap("tab10")
    colour = {lab: ("0.85" if lab == labeller.unlabelled else cmap(i % 10)) for i, lab in enumerate(names)}
    width = float(np.clip(rec.duration_s / 4.0, 10.0, max_width_in))
    fig, (ax, axl) = plt.subplots(2, 1, figsize=(width, 5.5), sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    ax.plot(t, mag, lw=0.6, color="0.25", label="|acc|")
    st = labeller.steps_
    if len(st):
        k = np.clip(np.round(st["t_s"].to_numpy() * rec.sampling_rate_hz).astype(int), 0, rec.n_samples - 1)
        kind = "stride starts" if labeller.snap == "strides" else "step events"
        ax.plot(t[k], mag[k], "o", ms=3, color="tab:blue", label=f"{kind} ({labeller.report_['detector']})")
    first = {"written": True, "moved": True, "kept": True}
    for row in labeller.boundaries_.itertuples():
        if row.status == "recording edge":
            continue
        ax.axvline(row.t_s, color="0.5", ls="--", lw=0.9, label="boundary as written" if first["written"] else None)
        first["written"] = False
        if row.status == "snapped":
            ax.axvline(row.snapped_t_s, color="tab:green", lw=1.4, label="snapped boundary" if first["moved"] else None)
            first["moved"] = False
        elif row.status != "not snapped":
            ax.axvline(row.t_s, color="tab:red", lw=1.4, label=f"not snapped ({row.status})" if first["kept"] else None)
            first["kept"] = False
    ax.set_ylabel("|acc| (m/s^2)")
    ax.legend(loc="upper right", fontsize=8, ncol=3, framealpha=0.9)
    r = labeller.report_
    ax.set_title(
        f"{rec.name}: {r['n_snapped']}/{r['n_boundaries']} boundaries snapped to {labeller.snap} "
        f"(max {r['max_snap_s']:g} s, mean shift {r['mean_abs_shift_s']:.3f} s)",
        fontsize=10,
    )
    for row in labeller.intervals_.itertuples():
        axl.axvspan(row.start_s, row.end_s, ymin=0.55, ymax=0.95, color=colour[row.label], lw=0)
        axl.text((row.start_s + row.end_s) / 2, 0.75, row.label, ha="center", va="center", fontsize=7, transform=axl.get_xaxis_transform())
    lab = rec.labels
    change = np.concatenate([[0], np.flatnonzero(lab[1:] != lab[:-1]) + 1, [len(lab)]])
    for a, b in zip(change[:-1], change[1:], strict=True):
        axl.axvspan(t[a], t[b - 1] + 1.0 / rec.sampling_rate_hz, ymin=0.05, ymax=0.45, color=colour.get(lab[a], "0.5"), lw=0)
    axl.set_yticks([0.25, 0.75], ["labels", "written"])
    axl.set_ylim(0, 1)
    axl.set_xlabel("time (s)")
    axl.set_xlim(t[0], t[-1])
    fig.tight_layout()
    out = Path(path)
    with atomic_path(out, suffix=".png") as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    return out
