"""`gaitml simulate OUT_DIR`: write simulated recordings with full ground truth (DESIGN sec. 3, 7)."""

from __future__ import annotations

from gaitml.commands._util import log
from gaitml.errors import InputError
from gaitml.simulate import ROUTES, check_modes, sample_subjects, simulate_dataset, simulate_route, write_simulation


def run(args) -> int:
    """Simulate ``--subjects`` recordings along ``--route`` and write them to OUT_DIR.

    ``straight`` and ``random`` routes last ``--duration-s`` each; the closed
    ``rectangle`` (~262 m) and ``arc`` (~400 m) routes are walked once around
    (their duration follows from the route; ``--duration-s`` is not used).
    """
    modes = check_modes(args.modes)
    if args.subjects < 1:
        raise InputError(f"--subjects must be at least 1, got {args.subjects}.")
    if args.route not in ROUTES:
        raise InputError(f"unknown --route {args.route!r}; choose from {', '.join(ROUTES)}.")
    fs = 50.0 if args.sampling_rate_hz is None else float(args.sampling_rate_hz)
    if args.route in ("rectangle", "arc"):
        log(f"route {args.route}: one loop per subject; --duration-s is not used")
        subjects = sample_subjects(args.subjects, args.seed, pose="flat")
        recs = [simulate_route(args.route, subject=s, modes=modes, sampling_rate_hz=fs, seed=args.seed + i) for i, s in enumerate(subjects)]
    else:
        recs = simulate_dataset(args.subjects, args.duration_s, modes, sampling_rate_hz=fs, seed=args.seed, route=args.route)
    paths = write_simulation(recs, args.out_dir)
    n_steps = sum(int(r.reference["n_steps_true"]) for r in recs)
    log(f"wrote {len(paths)} recordings ({n_steps} true steps, {sum(r.duration_s for r in recs):.0f} s) to {args.out_dir}")
    return 0
