"""End-point error of PDR variants on simulated mixed-mode routes (paper 003 sec. 4.3).

For each route (rectangle ~262 m, arc ~400 m) and seed: the simulated walk of
:func:`gaitml.simulate.simulate_route` (mixed modes, returns to the start); a separate
calibration recording of the same subject (150 s of mixed modes on a straight route,
another seed) fits the step length model per mode and the DW-PCA polarity
(:func:`gaitml.pdr.calibrate.calibrate_from_reference`). The initial heading is the true
one (a compass would give it; the closure error of a closed route does not depend on it).
Then the variants:

- ``multi / true modes / hde``: multi-state update, per-step modes from the labels.
- ``multi / model modes / hde``: modes from the model's window predictions (``--model``),
  mode changes re-placed step by step (:mod:`gaitml.pdr.step_modes`).
- ``multi / model modes / hde / nearest window``: the same without that refinement (each
  step takes the mode of the nearest corrected window, paper 003 as written).
- ``multi / model modes / hde / window at step middle``: the window nearest the middle
  between the step peak and the next one.
- ``forward-only / hde``: traditional PDR, every step a walk step (paper 003's baseline).
- ``multi / true modes / gyro``, ``dwpca``, ``dwpca-hde``: other heading sources.
- ``multi / true modes / hde / true lengths``: the step lengths of the reference (isolates
  heading and mode effects from step length).
- ``multi / true modes / paper HDE (no drift fit)``: buffered HDE without the drift-rate fit and without
  the structure guard (paper 003 has neither).
- ``multi / true modes / gyro / true gyro bias removed``: the simulator's gyro bias (in
  ``meta``) subtracted: what the heading error is made of.

The error is |estimated end - true end| / true distance (the true end is the start).

The printed table: ``python -m experiments.scripts.pdr_report`` (repository root).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.evaluation.trajectory import end_point_error, path_length
from gaitml.pdr.calibrate import calibrate_from_reference
from gaitml.pdr.hde import HeuristicDriftElimination
from gaitml.pdr.pipeline import modes_from_labels, run_pdr

__all__ = ["VARIANTS", "evaluate_route", "route_table"]

#: (label, run_pdr keyword arguments); "model" variants need a model.
VARIANTS = (
    ("multi / true modes / hde", {"modes": "true", "heading": "hde"}),
    ("multi / model modes / hde", {"modes": "model", "heading": "hde"}),
    ("multi / model modes / hde / nearest window", {"modes": "model", "heading": "hde", "mode_boundaries": "nearest"}),
    ("multi / model modes / hde / window at step middle", {"modes": "model", "heading": "hde", "mode_boundaries": "middle"}),
    ("forward-only / hde", {"modes": "forward", "heading": "hde"}),
    ("forward-only / gyro", {"modes": "forward", "heading": "gyro"}),
    ("multi / true modes / gyro", {"modes": "true", "heading": "gyro"}),
    ("multi / true modes / dwpca", {"modes": "true", "heading": "dwpca"}),
    ("multi / true modes / dwpca-hde", {"modes": "true", "heading": "dwpca-hde"}),
    ("multi / true modes / hde / true lengths", {"modes": "true", "heading": "hde", "step_length": "reference"}),
    (
        "multi / true modes / paper HDE (no drift fit)",
        {"modes": "true", "heading": "hde", "hde_kwargs": {"drift_rate": "none", "max_error_rad": np.pi, "structure_alpha": None}},
    ),
    ("multi / true modes / gyro / true gyro bias removed", {"modes": "true", "heading": "gyro", "remove_true_gyro_bias": True}),
)
CALIBRATION_S = 150.0


def evaluate_route(
    route: str,
    seed: int,
    *,
    model=None,
    variants=VARIANTS,
    keep_results: bool = False,
    position: str | None = None,
    detector: str = "single-peak",
    gyro_bias="off",
) -> list[dict]:
    """Run every variant on one simulated route; one dict per variant.

    ``detector`` is the step detector of every variant and of the calibration walk (a
    registered name; default paper 003's ``single-peak``, whose fixed 2 m/s^2 peak height
    misses steps of the simulator's calm hand-held walkers, hand gain below about 0.5:
    ``adaptive`` finds them). ``gyro_bias`` is :func:`gaitml.pdr.run_pdr`'s (default
    ``"off"``, paper 003's integration; a variant's own setting wins); the variant that
    removes the simulator's true gyroscope bias always runs with ``"off"``.

    ``position`` (one of :data:`gaitml.simulate.POSITIONS`; None: the subject's hand pose,
    as before) carries the phone there on the route and on the calibration walk (the same
    subject, pose or placement as :func:`gaitml.simulate.simulate_route` draws). Rows of
    model-mode variants carry ``mode_accuracy``: the fraction of steps whose mode is the
    true mode. Every row carries ``hde_applied``: for a variant with an HDE heading whether
    HDE's structure guard let it act (False: the variant ran on the uncorrected heading),
    None for the other headings.
    """
    from gaitml.simulate import POSITIONS, sample_subjects, simulate_recording, simulate_route
    from gaitml.simulate.positions import HAND_POSITIONS, Placement

    rec = simulate_route(route, seed=seed, position=position)
    subject = sample_subjects(1, seed)[0]  # the subject simulate_route draws for this seed
    placement = None
    if position is not None:  # the draw of simulate_route for this seed and position
        prng = np.random.default_rng([int(seed), 977, 3, POSITIONS.index(position)])
        if position in HAND_POSITIONS:
            subject = subject.with_pose(HAND_POSITIONS[position], prng)
        else:
            placement = Placement.random(position, prng)
    cal_rec = simulate_recording(subject, route="straight", duration_s=CALIBRATION_S, seed=(seed, 4242), placement=placement)
    cal = calibrate_from_reference(cal_rec, detector=detector)
    truth = rec.reference["trajectory"]
    xy_true = truth[["x_m", "y_m"]].to_numpy(float)
    dist = path_length(xy_true)
    h0 = float(truth["heading_rad"].iloc[0])
    rows = []
    for label, kw in variants:
        if kw.get("modes") == "model" and model is None:
            continue
        kw = dict(kw)
        kw.setdefault("step_length", cal.step_length)
        kw.setdefault("detector", detector)
        kw.setdefault("gyro_bias", gyro_bias)
        hde_kwargs = kw.pop("hde_kwargs", {})
        r = rec
        if kw.pop("remove_true_gyro_bias", False):
            bias = np.array([rec.meta.get(f"gyr_bias_{a}_rads", 0.0) for a in "xyz"], dtype=float)
            r = rec.replace(gyr=rec.gyr - bias)
            kw["gyro_bias"] = "off"
        res = run_pdr(
            r, model=model, initial_heading_rad=h0, dwpca=cal.dwpca, hde=HeuristicDriftElimination(reference_rad=h0, **hde_kwargs), **kw
        )
        err, pct = end_point_error(res.trajectory[["x_m", "y_m"]].to_numpy(), xy_true[-1], dist)
        row = {
            "route": route,
            "seed": seed,
            "variant": label,
            "distance_true_m": dist,
            "distance_est_m": res.distance_m,
            "n_steps": res.n_steps,
            "n_steps_true": int(rec.reference.get("n_steps_true", len(rec.reference["steps"]))),
            "detector": kw["detector"] if isinstance(kw["detector"], str) else type(kw["detector"]).__name__,
            "end_error_m": err,
            "end_error_pct": pct,
            # HDE's structure guard (gaitml.pdr.hde, Notes step 6): whether an HDE variant's HDE acted (None: no HDE)
            "hde_applied": None if res.info.get("heading_check") is None else bool(res.info["heading_check"]["hde_applied"]),
        }
        if position is not None:
            row["position"] = position
        if kw.get("modes") == "model":
            start = res.steps["start"].to_numpy()
            true_modes = modes_from_labels(rec.labels, start, np.maximum(res.steps["end"].to_numpy(), start + 1))
            row["mode_accuracy"] = float(np.mean(true_modes == res.steps["mode"].to_numpy()))
        if keep_results:
            row["result"] = res
        rows.append(row)
    return rows


def route_table(rows: list[dict]) -> pd.DataFrame:
    """Pivot: one row per variant, columns route/seed end-point errors (%) and per-route means."""
    df = pd.DataFrame([{k: v for k, v in r.items() if k != "result"} for r in rows])
    order = list(dict.fromkeys(df["variant"]))
    tab = df.pivot_table(index="variant", columns=["route", "seed"], values="end_error_pct").reindex(order)
    for route in dict.fromkeys(df["route"]):
        tab[(route, "mean")] = tab[route].mean(axis=1)
        tab[(route, "max")] = tab[route].drop(columns=["mean"], errors="ignore").max(axis=1)
    # seeds in numeric order, then max and mean, per route
    return tab[sorted(tab.columns, key=lambda c: (c[0], 1, c[1], 0) if isinstance(c[1], str) else (c[0], 0, "", c[1]))]
