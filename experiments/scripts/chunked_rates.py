"""Chunked prediction against whole-file prediction on real files of every format the chunked road serves.

Nothing is fitted here (the chunked road must reproduce the whole-file answer), so there is no held-out
split; tyrex is listed per person (one recording each) to show the agreement does not depend on the walker.

    PYTHONPATH=. python -m experiments.scripts.chunked_rates [--data ../shared/data]

For each file: ``gaitml predict MODEL FILE --json`` read whole, the same command with the long-input road
forced (``gaitml.io.chunked.LARGE_INPUT_SAMPLES`` = -1: one 10 min chunk for these files) and
:func:`gaitml.chunked_run.long_predict` in 15 s chunks (several chunks). Prints one markdown table: the
file's own rate, windows of each road, the share of windows with the same mode as the whole-file road and
the windows flagged as a foot-mounted sensor on each road. Used in experiments/reports/chunked-rates.md.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
from pathlib import Path

import numpy as np

import gaitml.io.chunked as ch
from gaitml.chunked_run import long_predict
from gaitml.cli import main as cli
from gaitml.models import load_model
from gaitml.models._placement import FOOT_REASON

ROOT = Path(__file__).resolve().parents[2]
PEOPLE = ("Guillaume", "Jakob", "Thibaud")


def _cli(argv: list[str], chunked: bool) -> dict:
    ch.LARGE_INPUT_SAMPLES = -1 if chunked else 10**12
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = cli(["predict", *argv, "--json"])
    if rc != 0:
        raise RuntimeError(f"gaitml predict {' '.join(argv)} failed: {err.getvalue().strip()}")
    return json.loads(out.getvalue())


def _files(data: Path) -> list[tuple[str, Path, str, list[str], dict]]:
    """(label, path, model, CLI options, read kwargs) of the real files compared."""
    out = []
    for f in sorted((data / "gaitmap-example").glob("imu_sample*.csv.gz")):
        out.append((f"gaitmap {f.name} (left)", f, "demo", ["--format", "gaitmap"], {"format": "gaitmap"}))
    for d in sorted((data / "oxford-step-counter" / "optimisation" / "data").iterdir())[:3]:
        out.append((f"oxford {d.name}", d, "demo-acc", [], {}))
    for person in PEOPLE:
        d = sorted(p for p in (data / "tyrex-attitude" / "android").iterdir() if p.name.startswith(person))[0]
        out.append((f"tyrex {d.name}", d, "demo", [], {}))
    for f in sorted((data / "ifsm-flat-phone").glob("*.xlsx")):
        out.append((f"ifsm {f.name}", f, "demo-acc", [], {}))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=os.environ.get("GAITML_SHARED_DATA", str(ROOT.parent / "shared" / "data")))
    a = ap.parse_args(argv)
    data = Path(a.data)
    print(
        "| file | own rate (Hz) | windows whole / CLI chunked / 15 s chunks | same mode (CLI chunked, 15 s chunks) | foot-flagged whole / CLI chunked / 15 s chunks |"
    )
    print("|---|---|---|---|---|")
    for label, path, model_name, opts, kw in _files(data):
        argv = [str(ROOT / "models" / model_name), str(path), *opts]
        whole, chunked = _cli(argv, False), _cli(argv, True)
        model = load_model(ROOT / "models" / model_name)
        several = long_predict(model, path, chunk_s=15.0, progress=False, **kw)
        mw = np.array([w["mode"] for w in whole["windows"]])
        mc = np.array([w["mode"] for w in chunked["windows"]])
        ms = several["mode"].to_numpy().astype(str)
        same_c = f"{(mw == mc).mean():.3f}" if len(mw) == len(mc) else "n/a"
        same_s = f"{(mw == ms).mean():.3f}" if len(mw) == len(ms) else "n/a"
        own = several.attrs.get("resampled_from_hz") or model.sampling_rate_hz
        feet = (
            whole["out_of_domain_reasons"].get(FOOT_REASON, 0),
            chunked["out_of_domain_reasons"].get(FOOT_REASON, 0),
            int((several["out_of_domain_reason"] == FOOT_REASON).sum()),
        )
        print(
            f"| {label} | {own:g} | {len(mw)} / {len(mc)} / {len(ms)} | {same_c}, {same_s} | {feet[0]} / {feet[1]} / {feet[2]} |",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
