"""Throughput of the PDR pieces: gyro attitude integration and the whole pipeline.

- ``attitude-prefix-scan``: pure quaternion integration of the gyro (paper 003 sec. 4.2)
  vectorised as a parallel prefix product, against the reference: scipy ``Rotation``
  composed sample by sample in a plain loop (run on a prefix and scaled linearly).
- ``attitude-gravity-loop``: the complementary (gravity-corrected) integration, a tight
  loop on plain floats, against the same per-sample ``Rotation`` loop.
- ``pipeline``: :func:`gaitml.pdr.run_pdr` (single-peak steps, true modes, HDE) on a
  simulated 262 m rectangle, in steps/s.
- ``pipeline-model-tyrex-phoning`` (when the shared data is there): :func:`gaitml.pdr.run_pdr` with ``models/demo``'s
  modes on the 18 tyrex Phoning walks, against the same run whose still-gate step veto runs its step finder whenever
  a window reads still (what ``gaitml pdr --model`` did before it ran it only when the veto can change a step's mode,
  :func:`gaitml.models._predict.veto_can_change_step_modes`); the two give the same trajectories.
"""

from __future__ import annotations

import contextlib
import os
import time
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from gaitml.pdr.attitude import integrate_gyro, integrate_gyro_gravity

__all__ = ["run"]


def _reference_rotation_loop(gyr: np.ndarray, fs: float, r0: Rotation) -> np.ndarray:
    """Plain reference: compose scipy rotations one sample at a time."""
    out = np.empty((len(gyr), 4))
    r = r0
    out[0] = r.as_quat()
    dt = 1.0 / fs
    for i in range(1, len(gyr)):
        r = r * Rotation.from_rotvec(0.5 * (gyr[i - 1] + gyr[i]) * dt)
        out[i] = r.as_quat()
    return out


def _time(fn, repeat: int = 3) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def run(quick: bool = False) -> list[dict]:
    fs = 50.0
    n = 50_000 if quick else 500_000
    n_ref = 5_000 if quick else 20_000
    rng = np.random.default_rng(0)
    gyr = rng.normal(0, 0.5, (n, 3))
    up = np.tile([0.0, 0.0, 1.0], (n, 1))
    r0 = Rotation.identity()
    rows = []
    t_ref = _time(lambda: _reference_rotation_loop(gyr[:n_ref], fs, r0), repeat=1) * n / n_ref
    t_scan = _time(lambda: integrate_gyro(gyr, fs, r0))
    rows.append(
        {
            "area": "pdr",
            "name": "attitude-prefix-scan",
            "n_items": n,
            "unit": "samples",
            "seconds": t_scan,
            "throughput_per_s": n / t_scan,
            "reference_seconds": t_ref,
            "ratio": t_ref / t_scan,
            "note": f"reference: per-sample scipy Rotation loop on {n_ref} samples, scaled",
        }
    )
    t_loop = _time(lambda: integrate_gyro_gravity(gyr, up, fs, r0, 0.5), repeat=1)
    rows.append(
        {
            "area": "pdr",
            "name": "attitude-gravity-loop",
            "n_items": n,
            "unit": "samples",
            "seconds": t_loop,
            "throughput_per_s": n / t_loop,
            "reference_seconds": t_ref,
            "ratio": t_ref / t_loop,
            "note": "complementary filter, tight float loop; same reference",
        }
    )
    from gaitml.pdr import run_pdr
    from gaitml.simulate import simulate_route

    rec = simulate_route("rectangle", seed=0)
    h0 = float(rec.reference["trajectory"]["heading_rad"].iloc[0])
    kw = {"modes": "true", "heading": "hde", "initial_heading_rad": h0, "detector": "single-peak", "gyro_bias": "off"}
    res = run_pdr(rec, **kw)
    t_pipe = _time(lambda: run_pdr(rec, **kw), repeat=1 if quick else 3)
    rows.append(
        {
            "area": "pdr",
            "name": "pipeline-rectangle",
            "n_items": res.n_steps,
            "unit": "steps",
            "seconds": t_pipe,
            "throughput_per_s": res.n_steps / t_pipe,
            "note": f"run_pdr single-peak + true modes + HDE, no gyro-bias removal (the rows before the new defaults) on a {rec.duration_s:.0f} s, {rec.n_samples}-sample simulated rectangle",
        }
    )
    rows.extend(_model_rows(quick))
    return rows


@contextlib.contextmanager
def veto_finder_whenever_still():
    """The still gate's step veto as it ran before ``veto_for_step_modes``: its step finder runs whenever a window reads
    still, whether or not the veto can change a step's mode (the reference of ``pipeline-model-tyrex-phoning``)."""
    import gaitml.models._predict as P

    real = P.veto_can_change_step_modes
    P.veto_can_change_step_modes = lambda still, modes, modes_raw: True
    try:
        yield
    finally:
        P.veto_can_change_step_modes = real


def _model_rows(quick: bool) -> list[dict]:
    """``pipeline-model-tyrex-phoning``: run_pdr with a model's modes on real phone-at-ear walks (none without the data)."""
    root = Path(os.environ.get("GAITML_SHARED_DATA", Path(__file__).resolve().parents[2] / "shared" / "data")) / "tyrex-attitude"
    walks = sorted(p for os_ in ("android", "ios") for p in (root / os_).glob("*_Phoning") if p.is_dir())
    if not walks:
        return []
    from gaitml.io import read_recording
    from gaitml.models import load_model
    from gaitml.pdr import run_pdr

    model = load_model(Path(__file__).resolve().parents[1] / "models" / "demo")
    recs = [read_recording(p) for p in walks]

    def all_walks():
        return [run_pdr(r, model=model, modes="model") for r in recs]

    ours, ref = np.inf, np.inf
    for _ in range(1 if quick else 3):  # interleaved: the machine's load falls on both sides alike
        t0 = time.perf_counter()
        res = all_walks()
        ours = min(ours, time.perf_counter() - t0)
        with veto_finder_whenever_still():
            t0 = time.perf_counter()
            res_ref = all_walks()
            ref = min(ref, time.perf_counter() - t0)
    same = all(
        np.array_equal(a.trajectory[["x_m", "y_m"]].to_numpy(), b.trajectory[["x_m", "y_m"]].to_numpy())
        for a, b in zip(res, res_ref, strict=True)
    )
    n_steps = sum(r.n_steps for r in res)
    return [
        {
            "area": "pdr",
            "name": "pipeline-model-tyrex-phoning",
            "n_items": n_steps,
            "unit": "steps",
            "seconds": ours,
            "throughput_per_s": n_steps / ours,
            "reference_seconds": ref,
            "ratio": ref / ours,
            "note": f"run_pdr with models/demo's modes on {len(recs)} tyrex Phoning walks; reference: the veto's step finder run "
            f"whenever a window reads still; trajectories {'identical' if same else 'DIFFER'}",
        }
    ]
