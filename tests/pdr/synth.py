"""A tiny deterministic IMU generator for the PDR tests (independent of gaitml.simulate).

The phone lies flat (or tilted about its x axis by ``pitch_deg``) with its forward axis along
the person's facing heading. Each step of period T gives a vertical acceleration
``amp sin(2 pi tau / T)`` (one peak, zero crossings at 0, T/2, T: the single-peak
detector's window is the step) and a horizontal acceleration along the direction of
motion ``c cos(2 pi tau / T)`` (first decreasing then increasing: paper 002 sec. 3.3).
Turns happen between legs at a constant yaw rate while standing.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.spatial.transform import Rotation

from gaitml.consts import GRAVITY_MS2
from gaitml.pdr.update import MODE_OFFSET_RAD
from gaitml.recording import Recording

FS = 50.0


def synth_walk(
    legs,
    *,
    fs=FS,
    period_s=0.5,
    amp_ms2=4.0,
    fwd_ms2=2.0,
    pitch_deg=0.0,
    gyro_bias_rads=(0.0, 0.0, 0.0),
    turn_s=1.0,
    start_heading_rad=0.0,
    pause_s=1.0,
    noise=0.0,
    seed=0,
    step_length_m=0.7,
):
    """``legs``: list of (mode, n_steps, turn_after_rad). Returns a Recording with labels and references."""
    rng = np.random.default_rng(seed)
    ns = int(round(period_s * fs))
    tau = np.arange(ns) / ns
    seg_heading, seg_acc_nav, seg_labels = [], [], []
    steps = []
    traj = [(0.0, 0.0, 0.0, start_heading_rad)]
    h = start_heading_rad
    x = y = 0.0
    t = 0.0

    def still(nsamp, h_from, h_to):
        hs = np.linspace(h_from, h_to, nsamp, endpoint=False) if nsamp else np.zeros(0)
        seg_heading.append(hs)
        seg_acc_nav.append(np.zeros((nsamp, 3)))
        seg_labels.append(np.full(nsamp, "walk", dtype=object))

    n_pause = int(round(pause_s * fs))
    still(n_pause, h, h)
    t += n_pause / fs
    for mode, n_steps, turn in legs:
        d = h + MODE_OFFSET_RAD[mode]
        for _ in range(n_steps):
            a = np.zeros((ns, 3))
            a[:, 2] = amp_ms2 * np.sin(2 * np.pi * tau)
            am = fwd_ms2 * np.cos(2 * np.pi * tau)
            a[:, 0] = am * np.sin(d)
            a[:, 1] = am * np.cos(d)
            seg_acc_nav.append(a)
            seg_heading.append(np.full(ns, h))
            seg_labels.append(np.full(ns, mode, dtype=object))
            x += step_length_m * np.sin(d)
            y += step_length_m * np.cos(d)
            steps.append((t + 0.25 * period_s, mode, step_length_m, h))
            t += ns / fs
            traj.append((t, x, y, h))
        nt = int(round(turn_s * fs)) if turn else 0
        still(nt, h, h + turn)
        h += turn
        t += nt / fs
    still(n_pause, h, h)
    heading = np.concatenate(seg_heading)
    acc_nav = np.concatenate(seg_acc_nav)
    labels = np.concatenate(seg_labels)
    acc_nav[:, 2] += GRAVITY_MS2
    # body-to-nav: yaw (compass heading h -> rotation about up by -h) after the pitch tilt
    rot = Rotation.from_euler("z", -heading[:, None]) * Rotation.from_euler("x", pitch_deg, degrees=True)
    acc_b = rot.inv().apply(acc_nav)
    # body rate: R_{k+1} = R_k exp(w dt) -> w = log(R_k^-1 R_{k+1}) / dt
    rel = (rot[:-1].inv() * rot[1:]).as_rotvec() * fs
    gyr = np.vstack([rel[:1], rel]) + np.asarray(gyro_bias_rads)
    if noise:
        acc_b = acc_b + rng.normal(0, noise, acc_b.shape)
        gyr = gyr + rng.normal(0, noise * 0.01, gyr.shape)
    ref_steps = pd.DataFrame(steps, columns=["t_s", "mode", "step_length_m", "heading_rad"])
    ref_traj = pd.DataFrame(traj, columns=["t", "x_m", "y_m", "heading_rad"])
    return Recording.from_arrays(acc_b, fs, gyr=gyr, labels=labels.astype(str), reference={"steps": ref_steps, "trajectory": ref_traj})
