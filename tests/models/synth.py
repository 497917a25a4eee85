"""Tiny synthetic labelled recordings (independent of the simulator) for the model tests.

Each mode gets its own step frequency, amplitude and axis pattern, plus noise, so
a linear classifier on the 52 features separates them well but not trivially.
"""

from __future__ import annotations

import numpy as np

from gaitml.consts import GRAVITY_MS2
from gaitml.io import write_gaitml_csv, write_manifest
from gaitml.recording import Recording

MODES = ("walk", "run", "side_left")
_PATTERN = {  # (step frequency Hz, amplitude m/s^2, weights on x, y, z)
    "walk": (1.8, 2.0, (0.3, 1.0, 0.6)),
    "run": (2.7, 6.0, (0.4, 0.8, 1.0)),
    "side_left": (1.4, 2.5, (1.0, 0.2, 0.5)),
    "side_right": (1.4, 2.5, (-1.0, 0.2, 0.5)),
    "backward": (1.6, 2.0, (0.3, -1.0, 0.6)),
}


def synth_recording(
    subject: int,
    modes=MODES,
    seconds_per_mode: float = 20.0,
    fs: float = 50.0,
    seed: int = 0,
    gyr: bool = False,
    position: str | None = None,
) -> Recording:
    rng = np.random.default_rng(seed * 1000 + subject)
    accs, labels = [], []
    for m in modes:
        f, a, w = _PATTERN[m]
        f *= 1 + 0.05 * rng.standard_normal()
        n = int(seconds_per_mode * fs)
        t = np.arange(n) / fs
        base = a * np.sin(2 * np.pi * f * t) + 0.3 * a * np.sin(4 * np.pi * f * t + 0.5)
        acc = np.outer(base, w) + 0.4 * rng.standard_normal((n, 3))
        acc[:, 2] += GRAVITY_MS2
        accs.append(acc)
        labels += [m] * n
    acc = np.concatenate(accs)
    g = 0.5 * np.sin(acc[:, [1, 0, 2]] / 5.0) if gyr else None
    meta = {"subject": f"s{subject}", "session": f"s{subject}-1", "id": f"s{subject}-1"}
    if position:
        meta["position"] = position
    return Recording.from_arrays(acc, fs, gyr=g, labels=np.array(labels), meta=meta)


def synth_set(n_subjects: int = 3, **kw) -> list[Recording]:
    return [synth_recording(s, **kw) for s in range(n_subjects)]


def write_synth_folder(folder, n_subjects: int = 3, with_labels: bool = True, positions=("InHand", "Pocket"), **kw):
    """gaitml-csv folder with manifest columns subject, session, user, position."""
    rows = []
    for s in range(n_subjects):
        for k, pos in enumerate(positions):
            rec = synth_recording(s, seed=k, **kw)
            if not with_labels:
                rec = rec.replace(labels=None)
            name = f"s{s}_{pos}.csv"
            write_gaitml_csv(rec, folder / name)
            rows.append({"file": name, "subject": f"s{s}", "session": f"s{s}-{pos}", "user": f"u{s}", "position": pos})
    write_manifest(rows, folder)
    return folder
