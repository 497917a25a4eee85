"""What fold models read the tempo rounds' two contested motions as (default-model.md TP.3, after round 2's verdict).

``python -m experiments.scripts.tempo_reads --data ../shared/data STEM [STEM ...]`` from the repository root, each STEM a
``tyrex_modes --model-cache`` folder (``STEM/models/<name>-<person>-<key>``, e.g. ``/tmp/tempo2/base /tmp/tempo2/p1``):

- Guillaume's RunningPocket recordings taken down to 20 Hz, read by the Guillaume-out fold model: per phone, the moving
  windows, those flagged, and the in-domain modes;
- Jakob's swinging-hand walking at 50 Hz, read by the Jakob-out fold model: per recording, the windows read as another
  mode;
- per Swinging and RunningPocket recording, the moving samples' gyroscope RMS (rad/s), dynamic acceleration RMS (m/s^2,
  about the recording's mean) and, for running, the cadence (steps/min, twice the gyroscope spectrum's peak in
  0.5-2.5 Hz), with the figures a tempo copy at ``--slow`` would have (x s, x s^2, x s).

Nothing here is chosen or ruled on: it explains a verdict already reached.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from experiments.scripts.tempo_rule import fold_models

#: the stride band searched for the running cadence (Hz): running strides are 1.2-1.6 Hz (145-190 steps/min)
STRIDE_BAND_HZ = (0.5, 2.5)


def motion_stats(rec, label: str) -> dict:
    """Gyroscope RMS, dynamic acceleration RMS and cadence of the samples of ``rec`` labelled ``label``."""
    m = np.asarray(rec.labels).astype(str) == label
    g, a = np.asarray(rec.gyr, dtype=float)[m], np.asarray(rec.acc, dtype=float)[m]
    fs = float(rec.sampling_rate_hz)
    f = np.fft.rfftfreq(len(g), 1 / fs)
    power = (np.abs(np.fft.rfft(g - g.mean(0), axis=0)) ** 2).sum(1)
    band = (f > STRIDE_BAND_HZ[0]) & (f < STRIDE_BAND_HZ[1])
    return {
        "gyr_rms": float(np.sqrt((g**2).sum(1).mean())),
        "acc_dyn_rms": float(np.sqrt(((a - a.mean(0)) ** 2).sum(1).mean())),
        "cadence": float(120.0 * f[band][np.argmax(power[band])]),
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", type=Path, required=True, help="the shared data folder (holding tyrex-attitude)")
    ap.add_argument("--slow", type=float, default=0.87, help="the slowed copy's tempo factor to compare with")
    ap.add_argument("stems", nargs="+")
    a = ap.parse_args(argv)
    folds = {s: fold_models(s) for s in a.stems}  # checked before the data are read
    from experiments.scripts.tyrex_modes import load_tyrex_labelled
    from gaitml.models import load_model, predict_recording, resample_recording

    items = load_tyrex_labelled(a.data, 50.0)
    print("Guillaume's RunningPocket at 20 Hz, Guillaume-out fold model: windows, flagged, in-domain modes")
    for stem, fm in folds.items():
        model = load_model(fm["Guillaume"])
        for it in [i for i in items if i["motion"] == "RunningPocket" and i["subject"] == "Guillaume"]:
            p = predict_recording(model, resample_recording(it["recording"], 20.0))
            w = p[(p["label"].astype(str) == "run") & (p["label_fraction"] >= 0.5)]
            ood = w["in_domain"].map(lambda v: v is False)
            print(
                f"  {Path(stem).name:10s} {it['phone']:9s} {len(w)} {int(ood.sum())} {w.loc[~ood, 'mode'].astype(str).value_counts().to_dict()}"
            )
    print("Jakob's swinging-hand walking at 50 Hz, Jakob-out fold model: windows, read as another mode")
    for stem, fm in folds.items():
        model = load_model(fm["Jakob"])
        for it in [i for i in items if i["motion"] == "Swinging" and i["subject"] == "Jakob"]:
            p = predict_recording(model, it["recording"])
            w = p[(p["label"].astype(str) == "walk") & (p["label_fraction"] >= 0.5)]
            other = w[w["mode"].astype(str) != "walk"]
            print(
                f"  {Path(stem).name:10s} {it['phone']:9s} {it['recording'].meta.get('disturbance', '')!s:7s} {len(w)} {other['mode'].astype(str).value_counts().to_dict()}"
            )
    s = a.slow
    print(f"moving samples: gyroscope RMS (rad/s), dynamic acceleration RMS (m/s^2), cadence (steps/min); running also at tempo {s:g}")
    for it in items:
        if it["motion"] not in ("Swinging", "RunningPocket"):
            continue
        st = motion_stats(it["recording"], it["mode"])
        line = f"  {it['subject']:9s} {it['phone']:9s} {it['motion']:13s} {st['gyr_rms']:5.2f} {st['acc_dyn_rms']:5.2f}"
        if it["motion"] == "RunningPocket":
            line += f" {st['cadence']:4.0f}   at {s:g}: {s * st['gyr_rms']:5.2f} {s**2 * st['acc_dyn_rms']:5.2f} {s * st['cadence']:4.0f}"
        print(line)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
