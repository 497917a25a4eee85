"""Leave one carrying position out: which domain check flags a position the model was not trained on? (issue 12)

Run from the repository root (about 3-4 minutes on an idle machine)::

    python -m experiments.scripts.lopo_domain [--out FILE] [--cache DIR]

Protocol (the one of ``domain_report --positions``): 8 simulated training subjects
(seed 1000) and 4 test subjects (seed 2024), 120 s in each of the seven positions of
:data:`gaitml.simulate.POSITIONS`, five modes, 1.5 s windows at 50 Hz with 50 %
overlap. For each position P in turn every candidate check is fitted on the training
windows of the other six positions (thresholds: the 0.99 quantile of held-out-fold
distances over the training subjects, as :func:`gaitml.models.domain.fit_domain`
does) and applied to the test subjects: the fraction of P's windows it flags (should
be high), the fraction of the six trained positions' test windows it flags (false
alarms, should stay near 1-3 %) and the fraction of P's windows that are *silently
wrong* (not flagged and the mode of a linear OVO SVM trained on the six positions,
``all52+gyro`` phone frame, is not the true mode).

Candidates (window level unless said otherwise):

- ``today``: :func:`fit_domain` on ``all52+gyro`` phone-frame features with the
  gravity-direction check (what ``gaitml train`` records);
- ``gauss/<repr>``: one Ledoit-Wolf Gaussian per class, smallest Mahalanobis distance,
  on another representation: ``grav`` the ``all52+gyro`` features in the gravity frame,
  ``odyn`` a few orientation-dynamics features per window (:func:`orientation_dynamics`),
  ``grav+odyn`` both;
- ``posgauss/<repr>``: one Gaussian per (mode, position);
- ``knn/<repr>``: distance to the k-th nearest of a set of k-means prototypes of the
  standardised training windows;
- ``.../span``: the window distances aggregated over a running span (median of the
  last 10 windows of the recording, about 7.5 s) before thresholding; the threshold is
  the 0.99 quantile of the held-out span medians.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

SPAN = 10  # windows in the running span (0.75 s hop: 7.5 s)
QUANTILE = 0.99
FOLDS = 5


#: Columns of the descriptors that need no gyroscope (gaitml.models.domain.DYNAMICS_NAMES 0-7).
ODYN_ACC = 8


# ---------------------------------------------------------------- data
def build(cache: Path | None):
    """Window tables of the training and test sets (cached as npz when ``cache`` is given)."""
    if cache is not None and (cache / "lopo.npz").is_file():
        d = np.load(cache / "lopo.npz", allow_pickle=False)
        return {k: d[k] for k in d.files}
    from gaitml.models import build_window_dataset
    from gaitml.models.domain import DYNAMICS_NAMES, orientation_dynamics, window_gravity
    from gaitml.simulate import POSITIONS, simulate_dataset

    out = {}
    for tag, n, seed in (("tr", 8, 1000), ("te", 4, 2024)):
        print(f"simulating {tag} ...", file=sys.stderr, flush=True)
        recs = simulate_dataset(n_subjects=n, duration_s=120.0, pose="mixed", seed=seed, positions=POSITIONS)
        groups = [r.meta["subject"] for r in recs]
        for frame in ("phone", "gravity"):
            ds = build_window_dataset(recs, groups=groups, length_s=1.5, overlap=0.5, feature_set="all52+gyro", frame=frame)
            out[f"{tag}_X_{frame}"] = ds.inputs("features").astype(float)
        starts = ds.windows["start"].to_numpy(np.int64)
        length = int(ds.windows["end"].iloc[0] - starts[0])
        ri = np.asarray(ds.recording_index)
        grav = np.zeros((len(ds), 3))
        odyn = np.zeros((len(ds), len(DYNAMICS_NAMES)))
        pos = np.empty(len(ds), dtype=object)
        for i in np.unique(ri):
            rows = np.flatnonzero(ri == i)
            r = recs[int(i)]
            grav[rows] = window_gravity(r.acc, starts[rows], length)
            odyn[rows] = orientation_dynamics(r.acc, r.gyr, starts[rows], starts[rows] + length, r.sampling_rate_hz)
            pos[rows] = r.meta["position"]
        out[f"{tag}_grav"] = grav
        out[f"{tag}_odyn"] = odyn
        out[f"{tag}_y"] = np.asarray(ds.y).astype(str)
        out[f"{tag}_g"] = np.asarray(ds.groups).astype(str)
        out[f"{tag}_pos"] = pos.astype(str)
        out[f"{tag}_rec"] = ri.astype(np.int64)
        out[f"{tag}_start"] = starts
    if cache is not None:
        cache.mkdir(parents=True, exist_ok=True)
        np.savez(cache / "lopo.npz", **out)
    return out


# ---------------------------------------------------------------- candidate distances
def _std(X):
    from gaitml.models.domain import _standardiser

    return _standardiser(X)


class Gauss:
    """One Ledoit-Wolf Gaussian per label; the distance is the smallest Mahalanobis distance."""

    def __init__(self, by_position: bool = False):
        self.by_position = by_position

    def fit(self, X, y, pos):
        from gaitml.models.domain import _class_gaussians

        self.c, self.s = _std(X)
        lab = np.char.add(np.char.add(y, "|"), pos) if self.by_position else y
        self.m, self.P = _class_gaussians((X - self.c) / self.s, lab, sorted(set(lab)))
        return self

    def dist(self, X):
        from gaitml.models.domain import _min_mahalanobis

        return _min_mahalanobis((X - self.c) / self.s, self.m, self.P)


class KNN:
    """Distance to the k-th nearest of ``n_proto`` k-means prototypes of the standardised training windows."""

    def __init__(self, n_proto: int = 256, k: int = 1, seed: int = 0):
        self.n_proto, self.k, self.seed = n_proto, k, seed

    def fit(self, X, y, pos):
        from sklearn.cluster import KMeans

        self.c, self.s = _std(X)
        Z = (X - self.c) / self.s
        n = min(self.n_proto, len(Z))
        self.proto = KMeans(n_clusters=n, n_init=1, random_state=self.seed, max_iter=50).fit(Z).cluster_centers_
        self.pp = (self.proto**2).sum(axis=1)
        return self

    def dist(self, X):
        Z = (X - self.c) / self.s
        d2 = (Z**2).sum(axis=1)[:, None] - 2 * Z @ self.proto.T + self.pp[None, :]
        d2 = np.partition(np.maximum(d2, 0.0), self.k - 1, axis=1)[:, self.k - 1]
        return np.sqrt(d2)


def span_median(d, rec, start, span: int = SPAN):
    """Median of the distances of the last ``span`` windows of the same recording (fewer at its start)."""
    out = np.empty(len(d))
    for r in np.unique(rec):
        rows = np.flatnonzero(rec == r)
        rows = rows[np.argsort(start[rows], kind="stable")]
        dr = d[rows]
        pad = np.concatenate([np.full(span - 1, np.nan), dr])
        win = np.lib.stride_tricks.sliding_window_view(pad, span)
        out[rows] = np.nanmedian(win, axis=1)
    return out


def heldout_distances(make, X, y, pos, groups):
    """Window distances of every training window from models fitted on the other folds (over the subjects)."""
    from sklearn.model_selection import GroupKFold

    d = np.full(len(X), np.nan)
    for tr, te in GroupKFold(n_splits=FOLDS).split(X, y, groups):
        d[te] = make().fit(X[tr], y[tr], pos[tr]).dist(X[te])
    return d


# ---------------------------------------------------------------- the protocol
def representations(D, tag):
    return {
        "phone": D[f"{tag}_X_phone"],
        "grav": D[f"{tag}_X_gravity"],
        "odyn": D[f"{tag}_odyn"],
        "odyn-acc": D[f"{tag}_odyn"][:, :ODYN_ACC],
        "grav+odyn": np.hstack([D[f"{tag}_X_gravity"], D[f"{tag}_odyn"]]),
    }


CANDIDATES = {
    "gauss/phone": ("phone", lambda: Gauss()),
    "gauss/grav": ("grav", lambda: Gauss()),
    "gauss/odyn": ("odyn", lambda: Gauss()),
    "gauss/grav+odyn": ("grav+odyn", lambda: Gauss()),
    "posgauss/grav": ("grav", lambda: Gauss(by_position=True)),
    "posgauss/odyn": ("odyn", lambda: Gauss(by_position=True)),
    "posgauss/grav+odyn": ("grav+odyn", lambda: Gauss(by_position=True)),
    "knn/odyn": ("odyn", lambda: KNN()),
    "knn/grav": ("grav", lambda: KNN()),
    "knn/grav+odyn": ("grav+odyn", lambda: KNN()),
}


def run(D, candidates=None, positions=None, spans=(SPAN,)):
    from gaitml.features import feature_names
    from gaitml.models._svm import LinearOVOSVM
    from gaitml.models.domain import fit_domain

    cands = CANDIDATES if candidates is None else {k: CANDIDATES[k] for k in candidates}
    Rtr, Rte = representations(D, "tr"), representations(D, "te")
    ptr, pte = D["tr_pos"], D["te_pos"]
    ytr, yte = D["tr_y"], D["te_y"]
    rows = []
    for held in positions or list(dict.fromkeys(ptr)):
        t0 = time.perf_counter()
        keep = ptr != held
        out = pte == held
        svm = LinearOVOSVM().fit(D["tr_X_phone"][keep], ytr[keep])
        wrong = svm.predict(D["te_X_phone"]) != yte
        flags = {}
        dom = fit_domain(
            D["tr_X_phone"][keep],
            ytr[keep],
            D["tr_g"][keep],
            D["tr_grav"][keep],
            feature_names=feature_names("all52+gyro"),
            feature_set="all52+gyro",
            frame="phone",
            positions=ptr[keep],
            seed=1000,
        )
        flags["today"] = ~dom.check(D["te_X_phone"], D["te_grav"])["in_domain"]
        # the recorded check of this branch: today's plus the orientation-dynamics part (fit_domain(dynamics=...))
        dom = fit_domain(
            D["tr_X_phone"][keep],
            ytr[keep],
            D["tr_g"][keep],
            D["tr_grav"][keep],
            feature_names=feature_names("all52+gyro"),
            feature_set="all52+gyro",
            frame="phone",
            positions=ptr[keep],
            seed=1000,
            dynamics=D["tr_odyn"][keep],
            sequence=D["tr_rec"][keep],
        )
        new = np.zeros(len(yte), dtype=bool)
        dyn_only = np.zeros(len(yte), dtype=bool)
        for r in np.unique(D["te_rec"]):
            ix = np.flatnonzero(D["te_rec"] == r)
            ix = ix[np.argsort(D["te_start"][ix], kind="stable")]
            res = dom.check(D["te_X_phone"][ix], D["te_grav"][ix], D["te_odyn"][ix])
            new[ix] = ~res["in_domain"]
            dyn_only[ix] = res["dynamics_distance"] > dom.dynamics["threshold"]
        flags["recorded: dynamics span only"] = dyn_only
        flags["recorded: today + dynamics span"] = new
        for name, (rep, make) in cands.items():
            Xk = Rtr[rep][keep]
            hd = heldout_distances(make, Xk, ytr[keep], ptr[keep], D["tr_g"][keep])
            m = make().fit(Xk, ytr[keep], ptr[keep])
            d = m.dist(Rte[rep])
            flags[name] = d > np.quantile(hd, QUANTILE)
            for span in spans:
                hs = span_median(hd, D["tr_rec"][keep], D["tr_start"][keep], span)
                flags[f"{name}/span{span}"] = span_median(d, D["te_rec"], D["te_start"], span) > np.quantile(hs, QUANTILE)
        for name, f in flags.items():
            rows.append(
                {
                    "left out": held,
                    "check": name,
                    "left-out flagged": float(f[out].mean()),
                    "left-out silently wrong": float((~f[out] & wrong[out]).mean()),
                    "left-out mode wrong (no check)": float(wrong[out].mean()),
                    "trained flagged": float(f[~out].mean()),
                    "trained mode wrong (no check)": float(wrong[~out].mean()),
                }
            )
        print(f"{held}: {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
    return pd.DataFrame(rows)


class PCAThen:
    """Standardise, keep the first ``n`` principal components, then ``inner`` (a low-dimensional density)."""

    def __init__(self, inner, n: int = 10):
        self.inner, self.n = inner, n

    def fit(self, X, y, pos):
        self.c, self.s = _std(X)
        Z = (X - self.c) / self.s
        _, _, vt = np.linalg.svd(Z - Z.mean(axis=0), full_matrices=False)
        self.V = vt[: self.n].T
        self.inner.fit(Z @ self.V, y, pos)
        return self

    def dist(self, X):
        return self.inner.dist(((X - self.c) / self.s) @ self.V)


CANDIDATES.update(
    {
        "pca10-gauss/grav": ("grav", lambda: PCAThen(Gauss())),
        "pca10-posgauss/grav+odyn": ("grav+odyn", lambda: PCAThen(Gauss(by_position=True))),
        "pca10-knn/grav+odyn": ("grav+odyn", lambda: PCAThen(KNN())),
        "knn5-512/odyn": ("odyn", lambda: KNN(n_proto=512, k=5)),
    }
)

CANDIDATES.update(
    {
        "posgauss/odyn-acc": ("odyn-acc", lambda: Gauss(by_position=True)),
        "knn/odyn-acc": ("odyn-acc", lambda: KNN()),
    }
)
