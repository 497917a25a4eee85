"""`gaitml predict MODEL_DIR INPUT [--out FILE] [--no-correction] [--json]`: per-window motion modes.

A step-window model (``window.by`` steps or strides in model.json) gives one row per
detected step (stride) instead; both are reported by :func:`_report`.
"""

from __future__ import annotations

import argparse

import numpy as np

from gaitml.commands._args import add_input_options
from gaitml.commands._util import emit_json, is_large_input, load_input, log, long_read_kwargs

#: The command's one-line description in ``gaitml --help``.
HELP = "predict motion modes with a saved model"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml predict`` on its parser ``p``."""
    p.add_argument("model_dir", metavar="MODEL_DIR")
    p.add_argument("input", metavar="INPUT")
    p.add_argument("--out", metavar="FILE")
    p.add_argument("--no-correction", action="store_true", help="skip the adjacent-window correction")
    p.add_argument("--json", action="store_true")
    add_run_cadence_option(p)
    p.add_argument(
        "--still-step-veto",
        metavar="on|off|N",
        default=None,
        help="a window the still gate reads still keeps its mode when the step detector (adaptive; its swing stage on where "
        "there is a gyroscope, gaitml.models._predict.STILL_STEP_SWING_PERIODICITY) finds at least N steps in it "
        "(on: 2, gaitml.models._predict.STILL_STEP_VETO_MIN_STEPS; off: the gate alone); default: STILL_STEP_VETO_DEFAULT (on)",
    )
    add_input_options(p)


def still_step_veto_arg(value) -> int | None:
    """``--still-step-veto``'s step count for the library: None (not given: the library default), 0 (off) or steps."""
    from gaitml.errors import InputError
    from gaitml.models._predict import STILL_STEP_VETO_MIN_STEPS, still_step_veto_threshold

    if value is None:
        return None
    v = str(value).strip().lower()
    if v == "on":
        return STILL_STEP_VETO_MIN_STEPS
    if v == "off":
        return 0
    try:
        n = float(v)
    except ValueError:
        raise InputError(f"--still-step-veto {value!r} is not on, off or a number of steps; give e.g. --still-step-veto on.") from None
    return still_step_veto_threshold(n) or 0


def add_run_cadence_option(p: argparse.ArgumentParser) -> None:
    """``--run-cadence on|off|HZ``: the run-cadence rule (gaitml.models._predict.run_cadence_rule) of ``predict`` and ``pdr``.

    Declared without importing gaitml.models (``gaitml --help`` stays fast); the value is read by :func:`run_cadence_arg`.
    """
    p.add_argument(
        "--run-cadence",
        metavar="on|off|HZ",
        default=None,
        help="a window read 'run' whose step cadence is under HZ steps/s takes the model's best other mode (on: 2.33 steps/s, "
        "the walk-to-run transition's 140 steps/min); default: gaitml.models._predict.RUN_CADENCE_DEFAULT_HZ (on)",
    )


def run_cadence_arg(value) -> float | None:
    """``--run-cadence``'s threshold for the library: None (not given: the library default), 0 (off) or steps/s."""
    from gaitml.errors import InputError
    from gaitml.models._predict import RUN_MIN_CADENCE_HZ, run_cadence_threshold

    if value is None:
        return None
    v = str(value).strip().lower()
    if v == "on":
        return RUN_MIN_CADENCE_HZ
    if v == "off":
        return 0.0
    try:
        hz = float(v)
    except ValueError:
        raise InputError(f"--run-cadence {value!r} is not on, off or a cadence in steps/s; give e.g. --run-cadence on.") from None
    return run_cadence_threshold(hz) or 0.0


def run(args) -> int:
    from gaitml.models import load_model

    model = load_model(args.model_dir)
    run_cad = run_cadence_arg(getattr(args, "run_cadence", None))
    veto = still_step_veto_arg(getattr(args, "still_step_veto", None))
    if model.window_by != "time":
        from gaitml.models import predict_step_windows

        table = predict_step_windows(
            model, load_input(args), correction=not args.no_correction, run_min_cadence_hz=run_cad, still_step_veto=veto
        )
        unit = "strides" if model.window_by == "strides" else "steps"
        return _report(args, model, table, unit, {"window_by": model.window_by, "detector": model.window_detector})
    if is_large_input(args):
        from gaitml.chunked_run import long_predict

        kw = long_read_kwargs(args)  # judged at the file's own rate, as a file read whole
        table = long_predict(model, args.input, correction=not args.no_correction, run_min_cadence_hz=run_cad, still_step_veto=veto, **kw)
        log("gaitml predict: long input, processed in chunks of 10 min (bounded memory)")
    else:
        from gaitml.models import predict_recording

        table = predict_recording(
            model, load_input(args), correction=not args.no_correction, run_min_cadence_hz=run_cad, still_step_veto=veto
        )
    return _report(args, model, table, "windows", {"window_s": model.length_s, "overlap": model.overlap})


def default_still_gate() -> dict:
    """The still gate in force when a table does not carry its own (``statistic``, ``threshold_ms2``, ``step_veto_min_steps``)."""
    from gaitml.models._predict import STILL_RULE, STILL_THRESHOLDS_MS2, still_step_veto_threshold

    return {
        "statistic": STILL_RULE,
        "threshold_ms2": STILL_THRESHOLDS_MS2[STILL_RULE],
        "step_veto_min_steps": still_step_veto_threshold(None),
    }


def still_warning(n_still: int, n: int, unit: str, n_vetoed: int = 0, step_veto: int | None = None) -> str:
    """One line: how many windows hold no step and are reported as ``still`` (gaitml.models._predict.still_windows), and
    how many more the step veto kept in their mode (``n_vetoed``, gaitml.models._predict.STILL_STEP_VETO_MIN_STEPS;
    ``step_veto``: the veto in force, None the default, 0 off). With no window still and some kept, the line names the
    kept ones (printed whenever either count is above 0, as the other flags' lines)."""
    from gaitml.models._predict import describe_still_gate, still_step_veto_threshold

    if not n_still:
        return (
            f"{n_vetoed} of {n} {unit} vary |acc| as little as a phone lying still ({describe_still_gate(step_veto=0)}) but hold "
            f"{still_step_veto_threshold(step_veto) or ''} or more detected steps: they keep the model's mode (still_vetoed); none is reported as 'still'."
        )
    kept = f" ({n_vetoed} more vary |acc| as little but hold detected steps and keep their mode: still_vetoed)" if n_vetoed else ""
    return (
        f"{n_still} of {n} {unit} hold no step ({describe_still_gate(step_veto=step_veto)}: lying still or standing); "
        f"they are reported as 'still', not as one of the model's motion modes (mode_raw keeps the model's answer){kept}."
    )


def side_direction_warning(n_unsure: int, n: int, unit: str) -> str:
    """One line: side steps read from an upright phone, whose left / right is unsure (gaitml.models._predict.side_direction_unsure)."""
    from gaitml.models._predict import FACE_UP_MAX_DEG

    return (
        f"{n_unsure} of {n} {unit} are side steps read from a phone held upright (its screen more than {FACE_UP_MAX_DEG:g} deg "
        "from facing up: a pocket, the swinging hand, the ear), where its placement can flip left and right; their direction "
        "is unsure (side_direction_unsure): read them as a side step."
    )


def still_unsure_warning(n_unsure: int, n: int, unit: str) -> str:
    """One line: windows reported ``still`` in which the phone turns with a stride rhythm (gaitml.models._predict.still_unsure)."""
    return (
        f"{n_unsure} of {n} {unit} reported 'still' turn the phone with a walker's stride rhythm (the gyroscope swings once "
        "per stride and reverses between steps) although |acc| shows no step: still or a calm walk is unsure there "
        "(still_unsure; mode_raw keeps the model's answer)."
    )


def run_cadence_warning(n_moved: int, n: int, unit: str, min_cadence_hz: float | None = None) -> str:
    """One line: windows the model read ``run`` at a walking step cadence, answered with its best other mode (gaitml.models._predict.run_cadence_rule)."""
    from gaitml.models._predict import RUN_MIN_CADENCE_HZ, RUN_STRIDE_CADENCE_HZ

    thr = RUN_MIN_CADENCE_HZ if min_cadence_hz is None else float(min_cadence_hz)
    return (
        f"{n_moved} of {n} {unit} read as run have a walking step cadence ({RUN_STRIDE_CADENCE_HZ:g}-{thr:.3g} steps/s, under "
        f"the walk-to-run transition's {60 * thr:.0f} steps/min); they are answered with the model's best other mode "
        "(run_at_walking_cadence; mode_raw keeps the model's answer)."
    )


def reason_counts(reasons) -> dict:
    """How many windows are out of domain for each reason (``out_of_domain_reason``), e.g. ``{"placement: rests between fast swings (foot-mounted sensor?)": 47}``."""
    if reasons is None:
        return {}
    vals, counts = np.unique(np.array([str(r) for r in reasons if r], dtype=str), return_counts=True)
    return {str(v): int(c) for v, c in zip(vals, counts, strict=True)}


def _report(args, model, table, unit: str, settings: dict) -> int:
    """Write / print the prediction table of windows (time-window model) or steps / strides (step-window model).

    ``settings``: the model's window settings for the JSON (length and overlap, or
    ``window_by`` and detector). Out-of-domain check (:mod:`gaitml.models.domain`): one
    warning line, the fraction in the JSON. The accelerometer range
    (:mod:`gaitml.features._range`): ``acc_range`` in the JSON (null for a model without
    one: the range, samples clipped, the largest |axis|), one stderr line when the
    recording reads well beyond it (a wider-range sensor; not for phones that clip near it),
    else a note beside the plain summary. The rate check (:func:`gaitml.models.rate_reason`):
    ``rate_check`` in the JSON (null when not checked), its reason on every flagged window and in
    the warning line.
    """
    from gaitml.commands._domain import domain_warning
    from gaitml.io import write_csv
    from gaitml.models.domain import out_of_domain_fraction

    if table.attrs.get("resampled_from_hz"):
        log(
            f"gaitml predict: resampled the input from {table.attrs['resampled_from_hz']:g} Hz to the model's {model.sampling_rate_hz:g} Hz"
        )
    if args.out:
        write_csv(args.out, table)
        log(f"gaitml predict: {len(table)} {unit} written to {args.out}")
    counts = {str(k): int(v) for k, v in table["mode"].value_counts().sort_index().items()}
    in_domain = table["in_domain"].to_numpy(dtype=object) if "in_domain" in table else []
    ood_fraction = out_of_domain_fraction(in_domain)
    reasons = table["out_of_domain_reason"].to_numpy(dtype=object) if "out_of_domain_reason" in table else None
    warning = domain_warning(model, in_domain, unit, reasons)
    if warning:
        log(f"gaitml: warning: {warning}")
    n_still = int(table["still"].sum()) if "still" in table else 0
    n_vetoed = int(table["still_vetoed"].sum()) if "still_vetoed" in table else 0
    if n_still or n_vetoed:  # a line whenever a window is flagged either way, as the other flags
        veto_in_force = (table.attrs.get("still_gate") or default_still_gate()).get("step_veto_min_steps")
        log(f"gaitml: warning: {still_warning(n_still, len(table), unit, n_vetoed, veto_in_force or 0)}")
    n_still_unsure = int(table["still_unsure"].sum()) if "still_unsure" in table else 0
    if n_still_unsure:
        log(f"gaitml: warning: {still_unsure_warning(n_still_unsure, len(table), unit)}")
    n_unsure = int(table["side_direction_unsure"].sum()) if "side_direction_unsure" in table else 0
    if n_unsure:
        log(f"gaitml: warning: {side_direction_warning(n_unsure, len(table), unit)}")
    n_moved = int(table["run_at_walking_cadence"].sum()) if "run_at_walking_cadence" in table else 0
    run_cadence = table.attrs.get("run_cadence")
    # the line names the windows answered in domain; the out-of-domain ones are the domain warning's
    n_moved_in = (
        int(sum(bool(m) and d is not False for m, d in zip(table["run_at_walking_cadence"], in_domain, strict=True)))
        if n_moved and len(in_domain)
        else n_moved
    )
    if n_moved_in:
        log(f"gaitml: warning: {run_cadence_warning(n_moved_in, len(table), unit, (run_cadence or {}).get('min_cadence_hz'))}")
    acc_range = table.attrs.get("acc_range")
    if acc_range and acc_range.get("wider"):
        log(f"gaitml predict: {acc_range_note(acc_range)}")
    by_steps = unit != "windows"
    if args.json:
        emit_json(
            {
                "model": str(model.path),
                "sampling_rate_hz": model.sampling_rate_hz,
                **settings,
                "correction": not args.no_correction,
                "windows": [
                    {
                        "t_start_s": float(r.t_start_s),
                        "t_end_s": float(r.t_end_s),
                        **({"t_event_s": float(r.t_event_s)} if by_steps else {}),
                        "mode": str(r.mode),
                        "in_domain": None if r.in_domain is None else bool(r.in_domain),
                        "out_of_domain_reason": (getattr(r, "out_of_domain_reason", "") or None),
                        "side_direction_unsure": bool(getattr(r, "side_direction_unsure", False)),
                        "run_at_walking_cadence": bool(getattr(r, "run_at_walking_cadence", False)),
                        "still_vetoed": bool(getattr(r, "still_vetoed", False)),
                        "still_unsure": bool(getattr(r, "still_unsure", False)),
                    }
                    for r in table.itertuples()
                ],
                "counts": counts,
                "out_of_domain_fraction": ood_fraction,
                "out_of_domain_reasons": reason_counts(reasons),
                "still_fraction": n_still / len(table) if len(table) else None,
                "still_gate": table.attrs.get("still_gate", default_still_gate()),
                # windows whose |acc| statistic read still but in which the veto's step finder found steps (the step veto)
                "still_vetoed_count": n_vetoed,
                # windows reported still in which the phone turns with a stride rhythm: the evidence disagrees (still_unsure)
                "still_unsure_count": n_still_unsure,
                "side_direction_unsure_count": n_unsure,
                "run_at_walking_cadence_count": n_moved,
                "run_cadence": run_cadence,
                "acc_range": acc_range,
                # the rate check (gaitml.models.rate_reason): the recording's rate against the lowest the model was trained at
                "rate_check": table.attrs.get("rate_check"),
            }
        )
    elif not args.out:
        if by_steps:
            detail = f" detected by {model.window_detector}"
        else:
            detail = "" if ood_fraction is None else f", {100 * ood_fraction:.1f} % out of the model's domain"
        log(
            "gaitml predict: "
            + ", ".join(f"{k} {v}" for k, v in counts.items())
            + f" ({len(table)} {unit}{detail}; use --out FILE or --json for the table)"
        )
    if acc_range and not acc_range.get("wider") and not args.json:
        log(
            f"gaitml predict: accelerometer read through the model's range +-{acc_range['range_ms2']:g} m/s^2 per axis "
            f"({acc_range['n_samples_clipped']} of {acc_range['n_samples']} samples clipped)"
        )
    return 0


def acc_range_note(acc_range: dict) -> str:
    """One line: the recording reads beyond the model's accelerometer range, which the model clips it to (gaitml.features._range)."""
    return (
        f"the accelerometer reads up to {acc_range['max_abs_axis_ms2']:.1f} m/s^2 on an axis, beyond the model's range of "
        f"+-{acc_range['range_ms2']:g} m/s^2 (its training phones' sensors): {acc_range['n_samples_clipped']} of "
        f"{acc_range['n_samples']} samples were read clipped to it, as those phones read them, before the features and the domain check."
    )
