"""`gaitml split INPUT --out DIR`: cut a recording at its long timestamp gaps into separate files.

Every command refuses a recording whose timestamps jump by more than
:func:`gaitml.recording.max_bridge_s` (the longer of 1 s and ten sampling intervals):
bridging such a gap by interpolation would invent signal. This command is the fix
that refusal names: it reads the stretches between the long gaps as separate
recordings (:func:`gaitml.io.read_segments`) and writes each as a gaitml-csv file
(times from 0, labels kept) into ``DIR`` with a ``manifest.csv`` that records where
each segment lay in the original file. ``DIR`` is then a data set folder that every
command and ``data.source = "folder"`` configs read.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from gaitml.commands._args import add_input_options
from gaitml.commands._util import emit_json, log, read_kwargs

#: The command's one-line description in ``gaitml --help``.
HELP = "cut a recording at its long timestamp gaps into separate files (with a manifest)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml split`` on its parser ``p``."""
    p.add_argument("input", metavar="INPUT")
    p.add_argument("--out", metavar="DIR", required=True, help="folder for one gaitml-csv per segment and manifest.csv")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    add_input_options(p)


def run(args) -> int:
    """Read INPUT as segments between long gaps and write one gaitml-csv per segment to ``--out``."""
    from gaitml.io import read_segments, write_gaitml_csv, write_manifest
    from gaitml.io._atomic import atomic_dir

    kw = read_kwargs(args)
    segments = read_segments(args.input, **kw)
    for warning in segments[0].meta.get("warnings", []):
        log(f"gaitml: warning: {warning}")
    stem = Path(args.input).name.split(".")[0] or "recording"
    rows = []
    with atomic_dir(args.out) as tmp:
        for k, rec in enumerate(segments):
            seg = rec.meta.get("segment", {"index": 0, "of": 1, "first_sample": 0, "t_start_s": 0.0})
            name = f"{stem}-seg{k + 1:03d}.csv"
            write_gaitml_csv(rec, tmp / name)
            rows.append(
                {
                    "file": name,
                    "subject": rec.meta.get("subject", stem),
                    "session": k + 1,
                    "source": str(args.input),
                    "first_sample": seg.get("first_sample", 0),
                    "last_sample": seg.get("last_sample", rec.n_samples - 1),
                    "t_start_s": round(float(seg.get("t_start_s", 0.0)), 6),
                    "duration_s": round(float(rec.duration_s), 6),
                    "n_samples": int(rec.n_samples),
                    "sampling_rate_hz": float(rec.sampling_rate_hz),
                }
            )
        write_manifest(rows, tmp)
    dropped = int(segments[0].meta.get("segments_dropped", 0))
    if dropped:
        log(f"gaitml: warning: {dropped} stretches between gaps held a single sample (too short for a recording) and were not written.")
    if args.json:
        emit_json({"input": str(args.input), "out": str(args.out), "n_segments": len(rows), "segments_dropped": dropped, "segments": rows})
    else:
        log(f"wrote {len(rows)} segments ({sum(r['n_samples'] for r in rows)} samples) to {args.out}")
        for r in rows:
            log(f"  {r['file']}  from t = {r['t_start_s']:.3f} s  {r['duration_s']:.2f} s  {r['n_samples']} samples")
    return 0
