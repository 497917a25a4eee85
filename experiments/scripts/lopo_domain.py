"""Leave one carrying position out: which domain check flags a position the model was not trained on? (issue 12)

Run from the repository root (about 3 minutes on a nearly idle machine, 13 at load 4-5)::

    python -m experiments.scripts.lopo_domain [--data ../shared/data] [--out FILE] [--cache DIR]

``--cache DIR`` keeps the simulated windows in ``DIR/lopo.npz`` for a rerun, keyed on
:func:`cache_key` (gaitml's version, the protocol and the sources of the simulator, the
features and the domain descriptors): a cache made by other code is not used.

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
- ``.../spanN``: the window distances aggregated over a running span (median of the
  last N windows of the recording, N x 0.75 s) before thresholding; the threshold is
  the 0.99 quantile of the held-out span medians;
- ``recorded``: what ``gaitml train`` now records for a gyroscope model
  (:func:`fit_domain` with ``dynamics``): today's check plus ``posgauss/odyn/span20``.

Then the accelerometer-only descriptors on the real Oxford walks (no gyroscope there),
and the cost of the check in ``predict_recording``.
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
def store_window_set(out: dict, tag: str, recs, ds) -> None:
    """Store set ``tag``'s per-window arrays in ``out`` (the cache layout): gravity and orientation-dynamics
    descriptors, mode labels, subjects, positions, recording index and start sample of each window of ``ds``."""
    grav, odyn, pos = window_descriptors(recs, ds)
    out[f"{tag}_grav"] = grav
    out[f"{tag}_odyn"] = odyn
    out[f"{tag}_y"] = np.asarray(ds.y).astype(str)
    out[f"{tag}_g"] = np.asarray(ds.groups).astype(str)
    out[f"{tag}_pos"] = pos.astype(str)
    out[f"{tag}_rec"] = np.asarray(ds.recording_index).astype(np.int64)
    out[f"{tag}_start"] = ds.windows["start"].to_numpy(np.int64)


def window_descriptors(recs, ds) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per window of ``ds`` (built from ``recs``): gravity direction, orientation-dynamics
    descriptors (:func:`gaitml.models.domain.orientation_dynamics`) and the recording's position."""
    from gaitml.models.domain import DYNAMICS_NAMES, orientation_dynamics, window_gravity

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
    return grav, odyn, pos


#: The simulated sets: (tag, subjects, seed); 120 s per position, 1.5 s windows with 50 % overlap.
SETS = (("tr", 8, 1000), ("te", 4, 2024))
DURATION_S = 120.0
WINDOW = {"length_s": 1.5, "overlap": 0.5, "feature_set": "all52+gyro"}
#: The code the cached windows are computed by (below gaitml/): the simulator and what turns its
#: recordings into windows, features and descriptors. A change to any of them changes the cache key.
CACHE_SOURCES = ("simulate", "features", "signal", "models/_dataset.py", "models/domain")
CACHE_FILE = "lopo.npz"


def cache_key(root: Path | None = None, sets=SETS) -> str:
    """A hash of what the cached windows depend on: gaitml's version, the protocol and the sources of :data:`CACHE_SOURCES`.

    ``root`` is the package folder (default: the imported ``gaitml``); a source missing there is part of the key too.
    ``sets`` are the simulated sets (default :data:`SETS`; ``lopo_span`` keys its other seeds on them).
    """
    import hashlib

    import gaitml

    root = Path(gaitml.__file__).parent if root is None else Path(root)
    h = hashlib.sha256(f"gaitml {gaitml.__version__}; sets {tuple(sets)}; {DURATION_S} s; {sorted(WINDOW.items())}".encode())
    for rel in CACHE_SOURCES:
        p = root / rel
        files = sorted(p.rglob("*.py")) if p.is_dir() else [p]
        for f in files:
            h.update(f.relative_to(root).as_posix().encode())
            h.update(f.read_bytes() if f.is_file() else b"<missing>")
    return h.hexdigest()


def load_cache(cache: Path, key: str, name: str = CACHE_FILE) -> dict | None:
    """The cached arrays when ``cache`` holds them (file ``name``) under ``key``; None (a miss) when absent or made by other code."""
    path = cache / name
    if not path.is_file():
        return None
    d = np.load(path, allow_pickle=False)
    if "cache_key" not in d.files or str(d["cache_key"]) != key:
        print(f"cache {path} was made by other simulator or feature code; simulating again", file=sys.stderr, flush=True)
        return None
    return {k: d[k] for k in d.files if k != "cache_key"}


def save_cache(cache: Path, key: str, arrays: dict, name: str = CACHE_FILE) -> None:
    """Write ``arrays`` with ``key`` to ``cache`` (file ``name``; atomically: a failure leaves no partial file)."""
    from gaitml.io import atomic_path

    cache.mkdir(parents=True, exist_ok=True)
    with atomic_path(cache / name, suffix=".npz") as tmp:
        np.savez(tmp, cache_key=np.asarray(key), **arrays)


def build(cache: Path | None):
    """Window tables of the training and test sets (cached as npz when ``cache`` is given, keyed on :func:`cache_key`)."""
    key = cache_key() if cache is not None else None
    if cache is not None:
        cached = load_cache(cache, key)
        if cached is not None:
            return cached
    from gaitml.models import build_window_dataset
    from gaitml.simulate import POSITIONS, simulate_dataset

    out = {}
    for tag, n, seed in SETS:
        print(f"simulating {tag} ...", file=sys.stderr, flush=True)
        recs = simulate_dataset(n_subjects=n, duration_s=DURATION_S, pose="mixed", seed=seed, positions=POSITIONS)
        groups = [r.meta["subject"] for r in recs]
        for frame in ("phone", "gravity"):
            ds = build_window_dataset(recs, groups=groups, frame=frame, **WINDOW)
            out[f"{tag}_X_{frame}"] = ds.inputs("features").astype(float)
        store_window_set(out, tag, recs, ds)
    if cache is not None:
        save_cache(cache, key, out)
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
    """Median of the distances of the last ``span`` windows of the same recording (fewer at its start).

    :func:`gaitml.models.domain.running_median` (what ``check`` uses) over the windows put in
    time order within each recording.
    """
    from gaitml.models.domain import running_median

    order = np.lexsort((start, rec))
    out = np.empty(len(d))
    out[order] = running_median(np.asarray(d, dtype=float)[order], span, np.asarray(rec)[order])
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
        training = (D["tr_X_phone"][keep], ytr[keep], D["tr_g"][keep], D["tr_grav"][keep])
        settings = dict(feature_names=feature_names("all52+gyro"), feature_set="all52+gyro", frame="phone", positions=ptr[keep], seed=1000)
        dom = fit_domain(*training, **settings)
        flags["today"] = ~dom.check(D["te_X_phone"], D["te_grav"])["in_domain"]
        # the recorded check of this branch: today's plus the orientation-dynamics part (fit_domain(dynamics=...))
        dom = fit_domain(*training, **settings, dynamics=D["tr_odyn"][keep], sequence=D["tr_rec"][keep])
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


# ---------------------------------------------------------------- report
def lopo_tables(df: pd.DataFrame) -> str:
    """Three markdown tables (checks x left-out positions): left-out flagged, left-out silently wrong, trained flagged."""
    keep = [c for c in dict.fromkeys(df["check"]) if "/span" not in c or "odyn" in c or c.endswith("/span20")]
    order = list(dict.fromkeys(df["left out"]))
    out = []
    for col, title in (
        ("left-out flagged", "left-out position: windows flagged"),
        ("left-out silently wrong", "left-out position: windows silently wrong (not flagged, mode wrong)"),
        ("trained flagged", "new subjects of the trained positions: windows flagged (false alarms)"),
    ):
        pv = df.pivot(index="check", columns="left out", values=col).loc[keep, order]
        lines = ["| check | " + " | ".join(order) + " |", "|---|" + "---:|" * len(order)]
        lines += ["| " + k + " | " + " | ".join(f"{100 * v:.1f} %" for v in pv.loc[k]) + " |" for k in keep]
        out.append(f"#### {title}\n\n" + "\n".join(lines))
    base = df.groupby("left out")[["left-out mode wrong (no check)", "trained mode wrong (no check)"]].first().loc[order]
    lines = ["| | " + " | ".join(order) + " |", "|---|" + "---:|" * len(order)]
    for c, lab in (
        ("left-out mode wrong (no check)", "left-out position, mode wrong"),
        ("trained mode wrong (no check)", "trained positions (new subjects), mode wrong"),
    ):
        lines.append(f"| {lab} | " + " | ".join(f"{100 * v:.1f} %" for v in base[c]) + " |")
    out.append(
        "#### the classifier without any check (linear OVO SVM, all52+gyro, phone frame, trained on the six positions)\n\n"
        + "\n".join(lines)
    )
    return "\n\n".join(out)


OXFORD = {
    "inhand": "InHand",
    "frontpocket": "FrontPocket",
    "backpocket": "BackPocket",
    "purse": "Purse",
    "swingingarm": "SwingingArm",
    "neckpouch": "NeckPouch",
    "armband": "Armband",
}


def oxford_table(D, data: Path, span: int = 20) -> pd.DataFrame:
    """Accelerometer-only descriptors (no gyroscope on the Oxford phones): per-(mode, position) Gaussians fitted on all seven simulated positions."""
    from gaitml.io import read_dataset
    from gaitml.models._dataset import resample_recording
    from gaitml.models.domain import orientation_dynamics

    Xtr = D["tr_odyn"][:, :ODYN_ACC]
    make = lambda: Gauss(by_position=True)  # noqa: E731
    hd = heldout_distances(make, Xtr, D["tr_y"], D["tr_pos"], D["tr_g"])
    thr_w = np.quantile(hd, QUANTILE)
    thr_s = np.quantile(span_median(hd, D["tr_rec"], D["tr_start"], span), QUANTILE)
    m = make().fit(Xtr, D["tr_y"], D["tr_pos"])
    dte = m.dist(D["te_odyn"][:, :ODYN_ACC])
    rows = [
        {
            "data": "simulated new subjects, all seven positions (trained)",
            "windows": len(dte),
            "flagged (window)": float(np.mean(dte > thr_w)),
            f"flagged (span {span})": float(np.mean(span_median(dte, D["te_rec"], D["te_start"], span) > thr_s)),
        }
    ]
    ox = data / "oxford-step-counter" / "optimisation"
    if not ox.exists():
        return pd.DataFrame(rows)
    by: dict[str, list] = {}
    for r in read_dataset(ox):
        by.setdefault(OXFORD.get(str(r.meta.get("position", "")).lower(), str(r.meta.get("position"))), []).append(r)
    for pos in OXFORD.values():
        fw, fs, n = 0, 0, 0
        for r in by.get(pos, []):
            r = resample_recording(r, 50.0)
            starts = np.arange(0, len(r.acc) - 75 + 1, 37)  # 1.5 s windows, 50 % overlap (as predict: hop 37 samples)
            q = orientation_dynamics(r.acc, np.zeros_like(r.acc), starts, starts + 75, 50.0)[:, :ODYN_ACC]
            d = m.dist(q)
            fw += int((d > thr_w).sum())
            fs += int((span_median(d, np.zeros(len(d)), starts, span) > thr_s).sum())
            n += len(d)
        if n:
            sim = {
                "InHand": "hand",
                "FrontPocket": "front-pocket",
                "BackPocket": "back-pocket",
                "Purse": "bag",
                "SwingingArm": "swinging-hand",
            }
            trained = f"trained (simulated {sim[pos]})" if pos in sim else "not trained"
            rows.append(
                {
                    "data": f"Oxford {pos} ({len(by[pos])} walks), {trained}",
                    "windows": n,
                    "flagged (window)": fw / n,
                    f"flagged (span {span})": fs / n,
                }
            )
    return pd.DataFrame(rows)


def cost_table(D, repeats: int = 5) -> pd.DataFrame:
    """predict_recording of a 10-minute recording with models/demo: no domain, its domain, its domain plus a dynamics part."""
    import dataclasses

    from gaitml.features import feature_names
    from gaitml.models import load_model, predict_recording
    from gaitml.models.domain import fit_domain
    from gaitml.simulate import simulate_dataset

    root = Path(__file__).resolve().parents[2]
    model = load_model(root / "models" / "demo")
    dyn = fit_domain(
        D["tr_X_phone"],
        D["tr_y"],
        D["tr_g"],
        D["tr_grav"],
        feature_names=feature_names("all52+gyro"),
        feature_set="all52+gyro",
        frame="phone",
        positions=D["tr_pos"],
        seed=1000,
        dynamics=D["tr_odyn"],
        sequence=D["tr_rec"],
    )
    base = model.domain
    with_dyn = dataclasses.replace(
        base, dynamics=dyn.dynamics, arrays={**base.arrays, **{k: v for k, v in dyn.arrays.items() if k.startswith("dyn_")}}
    )
    rec = simulate_dataset(n_subjects=1, duration_s=600.0, pose="mixed", seed=77)[0]
    n = len(predict_recording(model, rec))
    rows = []
    for label, dom in (("no domain check", None), ("today's check", base), ("today's check + orientation dynamics", with_dyn)):
        model.domain = dom
        best = np.inf
        for _ in range(repeats):
            t0 = time.perf_counter()
            predict_recording(model, rec)
            best = min(best, time.perf_counter() - t0)
        rows.append({"predict (10 min at 50 Hz)": label, f"best of {repeats} (s)": best, "windows/s": n / best})
    model.domain = base
    return pd.DataFrame(rows)


def _md(df: pd.DataFrame) -> str:
    cols = list(df.columns)
    lines = ["| " + " | ".join(cols) + " |", "|" + "|".join("---" if df[c].dtype == object else "---:" for c in cols) + "|"]
    for _, r in df.iterrows():
        cells = []
        for c in cols:
            v = r[c]
            if isinstance(v, float):
                cells.append(f"{100 * v:.1f} %" if c.startswith("flagged") else f"{v:.4g}")
            else:
                cells.append(str(v))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Leave one carrying position out: candidate domain checks (issue 12).")
    ap.add_argument("--data", type=Path, default=Path(__file__).resolve().parents[3] / "shared" / "data", help="the shared data folder")
    ap.add_argument("--out", type=Path, help="write the tables as markdown to this file")
    ap.add_argument("--cache", type=Path, help="keep the simulated windows here (npz, keyed on the simulator and feature code) for a rerun")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    D = build(args.cache)
    cands = [
        "gauss/grav",
        "posgauss/grav",
        "pca10-gauss/grav",
        "knn/grav",
        "gauss/odyn",
        "posgauss/odyn",
        "knn/odyn",
        "posgauss/odyn-acc",
        "knn/odyn-acc",
    ]
    df = run(D, candidates=cands, spans=(10, 20, 40))
    print("oxford ...", file=sys.stderr, flush=True)
    ox = oxford_table(D, args.data)
    print("cost ...", file=sys.stderr, flush=True)
    cost = cost_table(D)
    from experiments.scripts.domain_report import emit_tables

    return emit_tables(
        [
            "### Leave one position out (8 training subjects seed 1000, 4 test subjects seed 2024, 120 s per position)\n\n"
            + lopo_tables(df),
            "### Accelerometer-only descriptors on real walking (per-(mode, position) Gaussians on all seven simulated positions)\n\n"
            + _md(ox),
            "### Cost of the check\n\n" + _md(cost),
        ],
        args.out,
        t0,
    )


if __name__ == "__main__":
    raise SystemExit(main())
