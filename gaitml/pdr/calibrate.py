"""Per-subject calibration of the PDR from a recording with known steps.

Paper 003 sec. 4.1 obtains the step length constants "by training". Here a calibration
recording of the subject whose ``reference['steps']`` carries the true step events (times,
modes, lengths, facing headings; the simulator writes them, a survey-measured walk can be
converted to them) gives:

- a :class:`~gaitml.pdr.step_length.StepLengthModel` fitted per mode by least squares;
- the per-mode polarity of the DW-PCA concavity rule (:meth:`DwPcaHeading.fit_polarity`).

:func:`calibrate_walk_distance` covers the simpler case of a walk of known total distance
(no per-step truth): it rescales a step length model.
"""

from __future__ import annotations

import numpy as np

from gaitml.consts import DEFAULT_STEP_DETECTOR
from gaitml.errors import InputError
from gaitml.pdr.attitude import AttitudeEstimator
from gaitml.pdr.dwpca import DwPcaHeading
from gaitml.pdr.step_length import StepLengthModel, step_length_features
from gaitml.pdr.update import mode_offsets_rad
from gaitml.recording import Recording

__all__ = ["Calibration", "calibrate_from_reference", "calibrate_walk_distance", "match_reference_steps"]

#: Detected and true step events closer than this are the same step.
MATCH_TOLERANCE_S = 0.15


class Calibration:
    """Result of :func:`calibrate_from_reference`: ``step_length`` model, ``dwpca`` estimator, ``n_matched``."""

    def __init__(self, step_length: StepLengthModel, dwpca: DwPcaHeading, n_matched: int, n_detected: int):
        self.step_length = step_length
        self.dwpca = dwpca
        self.n_matched = n_matched
        self.n_detected = n_detected


def match_reference_steps(step_t_s, ref_t_s, *, tolerance_s: float = MATCH_TOLERANCE_S) -> np.ndarray:
    """Index of the nearest reference step for each detected step, -1 when none is within ``tolerance_s``."""
    t = np.asarray(step_t_s, dtype=float)
    r = np.asarray(ref_t_s, dtype=float)
    if len(r) == 0:
        return np.full(len(t), -1)
    order = np.argsort(r)
    rs = r[order]
    j = np.searchsorted(rs, t)
    lo = np.clip(j - 1, 0, len(rs) - 1)
    hi = np.clip(j, 0, len(rs) - 1)
    pick = np.where(np.abs(t - rs[lo]) <= np.abs(rs[hi] - t), lo, hi)
    ok = np.abs(rs[pick] - t) <= tolerance_s
    return np.where(ok, order[pick], -1)


def calibrate_from_reference(recording: Recording, *, detector=DEFAULT_STEP_DETECTOR, min_steps: int = 5) -> Calibration:
    """Fit the step length model and the DW-PCA polarity on a recording with true steps.

    Parameters
    ----------
    recording : Recording with gyro and ``reference['steps']`` (``t_s``, ``mode``,
        ``step_length_m``, ``heading_rad``) and ``reference['trajectory']`` (for the initial heading).
    detector : step detector name or object (the one the PDR will use; default the PDR's own default,
        :data:`gaitml.consts.DEFAULT_STEP_DETECTOR`).
    """
    from gaitml.pdr.pipeline import _detect

    ref = recording.reference.get("steps")
    need = ("t_s", "mode", "step_length_m", "heading_rad")
    if ref is None or any(c not in ref for c in need):
        raise InputError(f"calibration needs reference['steps'] with columns {need}; use a simulated or surveyed recording.")
    steps, _ = _detect(recording, detector)
    event = steps.attrs.get("event", "t_peak_s")
    idx = match_reference_steps(steps[event].to_numpy(float), ref["t_s"].to_numpy(float))
    ok = idx >= 0
    if ok.sum() < min_steps:
        raise InputError(f"only {int(ok.sum())} detected steps match the reference; check the detector suits the recording.")
    st = steps[ok].reset_index(drop=True)
    r = ref.iloc[idx[ok]].reset_index(drop=True)
    modes = r["mode"].astype(str).to_numpy()
    feats = step_length_features(recording.acc, st, recording.sampling_rate_hz)
    slm = StepLengthModel().fit(feats, r["step_length_m"].to_numpy(float), modes, min_steps=min_steps)
    traj = recording.reference.get("trajectory")
    h0 = float(traj["heading_rad"].iloc[0]) if traj is not None and len(traj) else float(r["heading_rad"].iloc[0])
    att = AttitudeEstimator(initial_heading_rad=h0).estimate(recording)
    lin = att.linear_acc_nav(recording)[:, :2]
    motion = r["heading_rad"].to_numpy(float) + mode_offsets_rad(modes, unknown="forward")
    end = np.maximum(st["end"].to_numpy(np.int64), st["start"].to_numpy(np.int64) + 1)
    learned = DwPcaHeading().fit_polarity(lin, st["start"].to_numpy(np.int64), end, motion, modes, min_steps=min_steps).polarity_
    dw = DwPcaHeading(polarity=learned)
    return Calibration(slm, dw, int(ok.sum()), len(steps))


def calibrate_walk_distance(
    recording: Recording, distance_m: float, *, model: StepLengthModel | None = None, detector=DEFAULT_STEP_DETECTOR, mode: str = "walk"
) -> StepLengthModel:
    """Per-subject calibration from a walk of known distance (every step taken as ``mode``).

    The model's coefficients for ``mode`` are scaled so that the detected steps sum to
    ``distance_m`` (see :meth:`StepLengthModel.calibrate`).
    """
    from gaitml.pdr.pipeline import _detect

    steps, _ = _detect(recording, detector)
    if len(steps) == 0:
        raise InputError("no steps detected in the calibration walk; check the recording and the detector.")
    feats = step_length_features(recording.acc, steps, recording.sampling_rate_hz)
    return (model or StepLengthModel()).calibrate(feats, np.full(len(steps), mode), distance_m)


def main(argv: list[str] | None = None) -> int:
    """``python -m gaitml.pdr.calibrate INPUT --out STEP_LENGTH.json [--distance-m D]``.

    With ``--distance-m``: scale the defaults so that INPUT (a walk) sums to D. Without:
    fit per mode on INPUT's reference steps (a simulated or surveyed recording). The JSON is
    what ``gaitml pdr --step-length`` reads.
    """
    import argparse
    import sys

    from gaitml.consts import DEFAULT_STEP_DETECTOR
    from gaitml.errors import GaitmlError
    from gaitml.io import read_recording

    p = argparse.ArgumentParser(prog="python -m gaitml.pdr.calibrate", description="Calibrate the PDR step length model.")
    p.add_argument("input", metavar="INPUT")
    p.add_argument("--out", metavar="JSON", required=True)
    p.add_argument("--distance-m", type=float, help="known distance of a walk (scale calibration)")
    p.add_argument(
        "--detector",
        default=DEFAULT_STEP_DETECTOR,
        help=f"step detector (default {DEFAULT_STEP_DETECTOR}, as gaitml pdr's: calibrate with the detector you dead-reckon with)",
    )
    args = p.parse_args(argv)
    try:
        rec = read_recording(args.input)
        if args.distance_m is not None:
            model = calibrate_walk_distance(rec, args.distance_m, detector=args.detector)
            print(f"scaled the walk model by {model.scale_:.4f} to {args.distance_m} m", file=sys.stderr)
        else:
            cal = calibrate_from_reference(rec, detector=args.detector)
            model = cal.step_length
            print(f"fitted modes {model.fitted_modes_} on {cal.n_matched} of {cal.n_detected} detected steps", file=sys.stderr)
        model.save(args.out)
    except GaitmlError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
