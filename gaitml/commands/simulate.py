"""`gaitml simulate OUT_DIR`: write simulated recordings with full ground truth (DESIGN sec. 3, 7)."""

from __future__ import annotations

import argparse
import math

from gaitml.commands._util import log
from gaitml.errors import InputError

#: The command's one-line description in ``gaitml --help``.
HELP = "simulate recordings with full ground truth"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml simulate`` on its parser ``p``."""
    p.add_argument("out_dir", metavar="OUT_DIR")
    p.add_argument("--subjects", type=int, default=4)
    p.add_argument("--duration-s", type=float, default=None, help="seconds per recording (default 120; straight/random routes only)")
    p.add_argument("--modes", default="walk,run,side_left,side_right,backward", help="comma-separated motion modes")
    p.add_argument("--route", default="straight", help="straight | rectangle | arc | random")
    p.add_argument("--sampling-rate-hz", type=float, default=None)
    p.add_argument("--seed", type=int, default=0)
    # carrying positions (comma list, checked against gaitml.simulate.POSITIONS)
    p.add_argument(
        "--positions",
        metavar="LIST",
        default=None,
        help="comma-separated carrying positions, e.g. front-pocket,belt (a wrong name lists them all; default: the hand-held "
        "flat phone, one recording per subject; with a list, one recording per subject and position)",
    )


#: Seconds per recording when ``--duration-s`` is not given (straight / random routes).
DEFAULT_DURATION_S = 120.0


def _validate(args) -> tuple[list[str], float, float | None]:
    """Check every argument before any work; return (modes, sampling rate, duration)."""
    from gaitml.simulate import ROUTES, check_modes, check_positions
    from gaitml.simulate.dataset import MAX_DURATION_S, SAMPLING_RATE_RANGE_HZ
    from gaitml.simulate.subject import MAX_SUBJECTS

    modes = check_modes(args.modes)
    if getattr(args, "positions", None) is not None:
        check_positions(args.positions)  # one line naming the valid positions
    if not 1 <= args.subjects <= MAX_SUBJECTS:
        raise InputError(f"--subjects must be within 1-{MAX_SUBJECTS}, got {args.subjects}.")
    if args.seed < 0:
        raise InputError(f"--seed must be a non-negative integer, got {args.seed}; use e.g. --seed 0.")
    if args.route not in ROUTES:
        raise InputError(f"unknown --route {args.route!r}; choose from {', '.join(ROUTES)}.")
    lo, hi = SAMPLING_RATE_RANGE_HZ
    fs = 50.0 if args.sampling_rate_hz is None else float(args.sampling_rate_hz)
    if not (math.isfinite(fs) and lo <= fs <= hi):
        raise InputError(f"--sampling-rate-hz must be within {lo:g}-{hi:g} Hz, got {args.sampling_rate_hz}; phones log at 50-200 Hz.")
    duration = getattr(args, "duration_s", None)
    if duration is not None and not (math.isfinite(duration) and 2.0 <= duration <= MAX_DURATION_S):
        raise InputError(f"--duration-s must be within 2-{MAX_DURATION_S:g} s (24 h per recording), got {duration}.")
    return modes, fs, duration


def run(args) -> int:
    """Simulate ``--subjects`` recordings along ``--route`` and write them to OUT_DIR.

    ``straight`` and ``random`` routes last ``--duration-s`` each (default 120 s); the
    closed ``rectangle`` (~262 m) and ``arc`` (~400 m) routes are walked once around
    (their duration follows from the route; a given ``--duration-s`` is not used).
    ``--positions LIST`` simulates every subject once per carrying position
    (:data:`gaitml.simulate.POSITIONS`; ``manifest.csv`` has the ``position`` column).
    """
    from gaitml.simulate import check_positions, sample_subjects, simulate_dataset, simulate_route, write_simulation

    modes, fs, duration = _validate(args)
    positions = None if getattr(args, "positions", None) is None else check_positions(args.positions)
    notes = []
    if args.route in ("rectangle", "arc"):
        if duration is not None:
            notes.append(f"note: route {args.route}: one loop per subject; --duration-s is not used")
        subjects = sample_subjects(args.subjects, args.seed, pose="flat")
        if positions is None:
            recs = [
                simulate_route(args.route, subject=s, modes=modes, sampling_rate_hz=fs, seed=args.seed + i) for i, s in enumerate(subjects)
            ]
        else:  # the same loop walked once per position (the walk depends on the seed only)
            recs = [
                simulate_route(args.route, subject=s, modes=modes, sampling_rate_hz=fs, seed=args.seed + i, position=p)
                for i, s in enumerate(subjects)
                for p in positions
            ]
    else:
        duration = DEFAULT_DURATION_S if duration is None else duration
        recs = simulate_dataset(args.subjects, duration, modes, sampling_rate_hz=fs, seed=args.seed, route=args.route, positions=positions)
    paths = write_simulation(recs, args.out_dir)
    for note in notes:
        log(note)
    n_steps = sum(int(r.reference["n_steps_true"]) for r in recs)
    log(f"wrote {len(paths)} recordings ({n_steps} true steps, {sum(r.duration_s for r in recs):.0f} s) to {args.out_dir}")
    return 0
