"""`gaitml pdr INPUT [--model MODEL_DIR] [--out FILE] [--plot PNG] [--json]` (DESIGN sec. 5)."""

from __future__ import annotations

from gaitml.commands._util import emit_json, load_input, log
from gaitml.evaluation.trajectory import end_point_error
from gaitml.io import write_csv


def run(args) -> int:
    """Dead-reckon INPUT; print a summary or the JSON contract; optionally write the table and a plot."""
    from gaitml.pdr import run_pdr
    from gaitml.pdr.step_length import StepLengthModel

    rec = load_input(args)
    model = None
    modes = getattr(args, "modes", None)
    if args.model:
        from gaitml.models import load_model

        model = load_model(args.model)
    if modes is None:
        if model is not None:
            modes = "model"
        elif rec.labels is not None:
            modes = "true"
            log("note: no --model; using the recording's own per-sample labels as the motion modes (--modes true).")
        else:
            modes = "forward"
            log("note: no --model and no labels: every step is treated as a forward walk step (traditional PDR, --modes forward).")
    step_length = StepLengthModel.load(args.step_length) if getattr(args, "step_length", None) else None
    if step_length is None:
        log("note: step lengths from the uncalibrated default model (pass --step-length FILE.json for a calibrated one).")
    h0 = getattr(args, "initial_heading_rad", None)
    truth = rec.reference.get("trajectory")
    if h0 is None:
        if truth is not None and len(truth) and "heading_rad" in truth:
            h0 = float(truth["heading_rad"].iloc[0])
            log(
                f"note: start heading {h0:.3f} rad taken from the input's reference trajectory (no compass; pass --initial-heading-rad to override)."
            )
        else:
            h0 = 0.0
    res = run_pdr(
        rec,
        model=model,
        detector=getattr(args, "detector", "single-peak"),
        heading=getattr(args, "heading", "hde"),
        modes=modes,
        step_length=step_length,
        initial_heading_rad=h0,
    )
    for note in res.info["notes"]:
        log(f"note: {note}")
    if args.out:
        write_csv(args.out, res.trajectory)
    if args.plot:
        from gaitml.pdr.plot import plot_trajectory

        title = f"{rec.name}: {res.n_steps} steps, heading {res.info['heading']}, modes {res.info['modes']}, update {res.info['update']}"
        plot_trajectory(args.plot, res.trajectory, truth=truth, title=title)
    if args.json:
        emit_json(res.to_json_dict())
        return 0
    x, y = res.end_xy_m
    lines = [
        f"{rec.name}: {res.n_steps} steps, distance {res.distance_m:.1f} m, end point ({x:.2f}, {y:.2f}) m "
        f"[heading {res.info['heading']}, modes {res.info['modes']}, update {res.info['update']}]"
    ]
    if truth is not None and len(truth):
        import numpy as np

        xy = truth[["x_m", "y_m"]].to_numpy(float)
        d_true = float(np.linalg.norm(np.diff(xy, axis=0), axis=1).sum())
        if d_true > 0:
            err, pct = end_point_error(res.trajectory[["x_m", "y_m"]].to_numpy(), xy[-1], d_true)
            lines.append(f"  truth: distance {d_true:.1f} m; end-point error {err:.2f} m = {pct:.2f} % of distance")
    if args.out:
        lines.append(f"  trajectory written to {args.out}")
    if args.plot:
        lines.append(f"  plot written to {args.plot}")
    print("\n".join(lines))
    return 0
